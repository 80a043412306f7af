// The misfit of a replay against a machine's recording
// (recording_misfit.hpp), by compare_bags.py's rules for --align angle.
#include "coil_winding_sim/core/run/recording_misfit.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace cws {

namespace {

constexpr int kMinSamples = 10;  // compare_bags.py's MIN_SAMPLES

std::string format(const char* fmt, double a, double b = 0, double c = 0, double d = 0) {
  char buf[512];
  std::snprintf(buf, sizeof buf, fmt, a, b, c, d);
  return buf;
}

// Linear interpolation with the ends held (numpy's interp).
double interp(double xq, const std::vector<double>& x, const std::vector<double>& y) {
  if (xq <= x.front()) return y.front();
  if (xq >= x.back()) return y.back();
  const std::size_t i = std::upper_bound(x.begin(), x.end(), xq) - x.begin();
  const double u = (xq - x[i - 1]) / (x[i] - x[i - 1]);
  return y[i - 1] + u * (y[i] - y[i - 1]);
}

// The angle made increasing (either direction), and which samples advance
// it (series_math.py's monotone_angle).
void monotone(const std::vector<double>& theta, std::vector<double>& u, std::vector<char>& keep) {
  const double sign = theta.back() >= theta.front() ? 1.0 : -1.0;
  u.resize(theta.size());
  keep.assign(theta.size(), 1);
  double run_max = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < theta.size(); ++i) {
    u[i] = sign * theta[i];
    if (i > 0) keep[i] = u[i] > run_max;
    run_max = std::max(run_max, u[i]);
  }
}

double rmsOf(const std::vector<double>& r) {
  if (r.empty()) return 0.0;
  double s = 0.0;
  for (double v : r) s += v * v;
  return std::sqrt(s / r.size());
}

}  // namespace

std::vector<double> hermite(const std::vector<double>& xq, const std::vector<double>& x,
                            const std::vector<double>& y) {
  std::vector<double> out(xq.size());
  const std::size_t n = x.size();
  if (n < 3) {
    for (std::size_t k = 0; k < xq.size(); ++k) out[k] = interp(xq[k], x, y);
    return out;
  }
  std::vector<double> m(n);
  for (std::size_t i = 1; i + 1 < n; ++i) m[i] = (y[i + 1] - y[i - 1]) / (x[i + 1] - x[i - 1]);
  m[0] = (y[1] - y[0]) / (x[1] - x[0]);
  m[n - 1] = (y[n - 1] - y[n - 2]) / (x[n - 1] - x[n - 2]);
  for (std::size_t k = 0; k < xq.size(); ++k) {
    // The piece: searchsorted(side=right) - 1, clipped to 0 .. n-2.
    const long j = static_cast<long>(std::upper_bound(x.begin(), x.end(), xq[k]) - x.begin()) - 1;
    const std::size_t i = static_cast<std::size_t>(std::clamp(j, 0L, static_cast<long>(n) - 2));
    const double h = x[i + 1] - x[i];
    const double u = (xq[k] - x[i]) / h, u2 = u * u, u3 = u2 * u;
    out[k] = (2 * u3 - 3 * u2 + 1) * y[i] + (u3 - 2 * u2 + u) * h * m[i] +
             (-2 * u3 + 3 * u2) * y[i + 1] + (u3 - u2) * h * m[i + 1];
  }
  return out;
}

double signedDistanceToPolyline(const Eigen::Vector3d& p,
                                const std::vector<Eigen::Vector3d>& poly) {
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector3d q_best = poly.front();
  for (std::size_t i = 0; i + 1 < poly.size(); ++i) {
    const Eigen::Vector3d ab = poly[i + 1] - poly[i];
    const double u =
        std::clamp((p - poly[i]).dot(ab) / std::max(ab.squaredNorm(), 1e-30), 0.0, 1.0);
    const Eigen::Vector3d q = poly[i] + u * ab;
    const double d2 = (p - q).squaredNorm();
    if (d2 < best) {
      best = d2;
      q_best = q;
    }
  }
  const double d = std::sqrt(best);
  return p.head<2>().norm() >= q_best.head<2>().norm() ? d : -d;
}

double Misfit::rms(const std::vector<double>& r) const { return rmsOf(r); }

double Misfit::value(const MisfitWeights& w) const { return weighted(w).squaredNorm(); }

Eigen::VectorXd Misfit::weighted(const MisfitWeights& w) const {
  Eigen::VectorXd r(tension_N.size() + profile_mm.size() + bulging_mm.size());
  Eigen::Index k = 0;
  auto put = [&](const std::vector<double>& v, double weight) {
    const double s = std::sqrt(weight);
    for (double x : v) r[k++] = s * x;
  };
  put(tension_N, w.tension);
  put(profile_mm, w.profile);
  put(bulging_mm, w.bulging);
  return r;
}

Misfit recordingMisfit(const RecordedSeries& m, const RecordedSeries& s,
                       const MisfitWeights& weights) {
  auto need = [](const char* topic, std::size_t n) {
    if (n < static_cast<std::size_t>(kMinSamples)) {
      char buf[256];
      std::snprintf(buf, sizeof buf, "too few samples to align: %s has %zu (need %d)", topic, n,
                    kMinSamples);
      throw std::invalid_argument(buf);
    }
  };
  need("machine/spindle/state", m.spindle_t_s.size());
  need("sim/spindle/state", s.spindle_t_s.size());
  need("machine/tension/measured", m.tension_t_s.size());
  need("sim/tension/measured", s.tension_t_s.size());
  // The time overlap of the required traces.
  const double m0 = std::max(m.spindle_t_s.front(), m.tension_t_s.front());
  const double m1 = std::min(m.spindle_t_s.back(), m.tension_t_s.back());
  const double s0 = std::max(s.spindle_t_s.front(), s.tension_t_s.front());
  const double s1 = std::min(s.spindle_t_s.back(), s.tension_t_s.back());
  const double lo = std::max(m0, s0), hi = std::min(m1, s1);
  if (hi <= lo) {
    throw std::invalid_argument(
        format("no time overlap between machine and sim: machine stamps %.6f..%.6f s, sim stamps "
               "%.6f..%.6f s",
               m0, m1, s0, s1));
  }

  // Tension at equal spindle angle, each side's angle from its own spindle.
  Misfit out;
  std::vector<double> um, us;
  std::vector<char> keep_m, keep_s;
  monotone(hermite(m.tension_t_s, m.spindle_t_s, m.spindle_angle_rad), um, keep_m);
  monotone(hermite(s.tension_t_s, s.spindle_t_s, s.spindle_angle_rad), us, keep_s);
  std::vector<double> us_k, ts_k;
  for (std::size_t i = 0; i < us.size(); ++i) {
    if (keep_s[i]) {
      us_k.push_back(us[i]);
      ts_k.push_back(s.tension_N[i]);
    }
  }
  std::vector<double> um_k;
  for (std::size_t i = 0; i < um.size(); ++i) {
    if (keep_m[i]) um_k.push_back(um[i]);
  }
  if (us_k.size() < static_cast<std::size_t>(kMinSamples) ||
      um_k.size() < static_cast<std::size_t>(kMinSamples)) {
    throw std::invalid_argument(
        format("too few samples to align by angle: the spindle turns in %.0f machine and %.0f sim "
               "tension samples (need 10)",
               static_cast<double>(um_k.size()), static_cast<double>(us_k.size())));
  }
  // The common range, reaching a micro-radian beyond the simulation's end:
  // a last sample at the same angle must not come and go with the last
  // bits of the simulated angle (the curvature at the optimum needs the
  // same samples at every evaluation; both angles start at exactly 0).
  const double ulo = std::max(um_k.front(), us_k.front());
  const double uhi = std::min(um_k.back(), us_k.back() + 1e-6);
  std::vector<double> at, measured;
  for (std::size_t i = 0; i < um.size(); ++i) {
    if (keep_m[i] && um[i] >= ulo && um[i] <= uhi && m.tension_t_s[i] >= lo &&
        m.tension_t_s[i] <= hi) {
      at.push_back(um[i]);
      measured.push_back(m.tension_N[i]);
    }
  }
  if (at.size() < static_cast<std::size_t>(kMinSamples)) {
    throw std::invalid_argument(format(
        "too few samples to align by angle: %.0f machine tension samples in the common angle "
        "range %.3f..%.3f rad (need 10)",
        static_cast<double>(at.size()), ulo, uhi));
  }
  const std::vector<double> sim_at = hermite(at, us_k, ts_k);
  for (std::size_t i = 0; i < at.size(); ++i) out.tension_N.push_back(sim_at[i] - measured[i]);

  // Profiles: each machine cloud in the overlap with the sim cloud nearest
  // in spindle angle (each side's angle at its cloud's stamp).
  std::vector<const ProfileCloud*> sim_clouds;
  for (const ProfileCloud& c : s.profiles) {
    if (c.p_core.size() >= 2) sim_clouds.push_back(&c);
  }
  if (m.profiles.empty() || sim_clouds.empty()) {
    out.notes.push_back(m.profiles.empty() ? "profile not compared: the machine has none"
                                           : "profile not compared: no sim profile of 2 points");
    return out;
  }
  auto angleAt = [](double t, const RecordedSeries& r) {
    const double sign = r.spindle_angle_rad.back() >= r.spindle_angle_rad.front() ? 1.0 : -1.0;
    return sign * interp(t, r.spindle_t_s, r.spindle_angle_rad);
  };
  std::vector<double> sim_key;
  for (const ProfileCloud* c : sim_clouds) sim_key.push_back(angleAt(c->t_s, s));
  // The pairs: each machine cloud with the sim cloud nearest in angle.
  std::vector<std::pair<const ProfileCloud*, const ProfileCloud*>> pairs;
  std::vector<double> sim_bulge, machine_bulge;
  bool bulging = true;
  for (const ProfileCloud& c : m.profiles) {
    if (!(c.t_s >= lo && c.t_s <= hi) || c.p_core.empty()) continue;
    const double a = angleAt(c.t_s, m);
    std::size_t k = 0;
    for (std::size_t j = 1; j < sim_key.size(); ++j) {
      if (std::abs(sim_key[j] - a) < std::abs(sim_key[k] - a)) k = j;
    }
    const ProfileCloud& sc = *sim_clouds[k];
    pairs.emplace_back(&c, &sc);
    if (c.stand_off_m.empty() || sc.stand_off_m.empty()) {
      bulging = false;
    } else {
      sim_bulge.push_back(1e3 * *std::max_element(sc.stand_off_m.begin(), sc.stand_off_m.end()));
      machine_bulge.push_back(1e3 * *std::max_element(c.stand_off_m.begin(), c.stand_off_m.end()));
    }
  }
  out.profile_pairs = static_cast<int>(pairs.size());
  if (pairs.empty()) {
    out.notes.push_back("profile not compared: no machine profile in the overlap");
    return out;
  }
  // Each measured point's distance [mm] to the simulated wire, the points
  // first moved towards the axis by offset_mm.
  auto distances = [&](double offset_mm, std::vector<double>* d_mm) {
    double sum = 0.0;
    for (const auto& [mc, sc] : pairs) {
      for (const Eigen::Vector3d& p : mc->p_core) {
        const double r = p.head<2>().norm();
        Eigen::Vector3d q = p;
        if (r > 0.0) q.head<2>() *= (r - 1e-3 * offset_mm) / r;
        const double d = 1e3 * std::abs(signedDistanceToPolyline(q, sc->p_core));
        sum += d * d;
        if (d_mm) d_mm->push_back(d);
      }
    }
    return sum;
  };
  // A line sensor's radial zero offset: the one shift that brings the
  // points closest to the wire (golden section over +-0.1 mm, less than
  // half a wire's pitch, where the sum is unimodal).
  if (weights.remove_profile_offset) {
    const double g = (std::sqrt(5.0) - 1.0) / 2.0;
    double a = -0.1, b = 0.1;
    double c = b - g * (b - a), d = a + g * (b - a);
    double fc = distances(c, nullptr), fd = distances(d, nullptr);
    while (b - a > 1e-7) {
      if (fc < fd) {
        b = d, d = c, fd = fc;
        c = b - g * (b - a);
        fc = distances(c, nullptr);
      } else {
        a = c, c = d, fc = fd;
        d = a + g * (b - a);
        fd = distances(d, nullptr);
      }
    }
    out.profile_offset_mm = 0.5 * (a + b);
  }
  distances(out.profile_offset_mm, &out.profile_mm);
  if (!bulging) {
    out.notes.push_back("bulging not compared: a profile has no stand_off field");
    return out;
  }
  for (std::size_t i = 0; i < sim_bulge.size(); ++i) {
    out.bulging_mm.push_back(sim_bulge[i] - (machine_bulge[i] - out.profile_offset_mm));
  }
  return out;
}

}  // namespace cws
