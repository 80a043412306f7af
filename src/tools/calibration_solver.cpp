// The calibration's evaluations, fit and verdicts (calibration_solver.hpp).
#include "calibration_solver.hpp"

#include <dlib/global_optimization.h>
#include <unistd.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <limits>

#include "sweep.hpp"
#include "sweep_slurm.hpp"

namespace cws_tools {

namespace fs = std::filesystem;

Evaluator::Evaluator(const CalibrationOptions& o, std::string exe, std::function<bool()> stop)
    : o_(o),
      exe_(std::move(exe)),
      stop_(std::move(stop)),
      keys_(fitKeys(o)),
      base_(cws::loadScene(o.scene, o.overrides)) {}

Eigen::VectorXd Evaluator::values(const Eigen::VectorXd& u) const {
  Eigen::VectorXd x(u.size());
  for (Eigen::Index k = 0; k < u.size(); ++k) {
    const FitParameter& f = o_.fit[k];
    x[k] = f.lo + std::clamp(u[k], 0.0, 1.0) * (f.hi - f.lo);
  }
  // Within the keys' order: every point evaluated, reported and kept.
  return keepKeyOrder(keys_, base_, x);
}

std::string Evaluator::describe(const Eigen::VectorXd& u) const {
  const Eigen::VectorXd x = values(u);
  std::string s;
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.5g", x[k]);
    s += (k ? ", " : "") + o_.fit[k].key + "=" + buf;
  }
  return s;
}

std::vector<Evaluation> Evaluator::run(const std::vector<Eigen::VectorXd>& points) {
  // Points evaluated before (within this run) are not run again.
  std::vector<Evaluation> out(points.size());
  std::vector<Eigen::VectorXd> todo;
  std::vector<std::size_t> where;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::vector<double> key(points[i].data(), points[i].data() + points[i].size());
    const auto it = cache_.find(key);
    if (it != cache_.end()) {
      out[i] = it->second;
    } else {
      todo.push_back(points[i]);
      where.push_back(i);
    }
  }
  if (todo.empty()) return out;
  std::vector<Eigen::VectorXd> x;
  for (const Eigen::VectorXd& u : todo) x.push_back(values(u));
  const SweepPlan plan = calibrationPlan(o_, x);
  char name[16];
  std::snprintf(name, sizeof name, "%04d", batch_++);
  const std::string dir = (fs::path(o_.out) / "evaluations" / name).string();
  fs::create_directories(dir);
  std::size_t kept = 0;
  writePlan(plan, dir);
  casesToRun(plan, dir, kept);
  int rc = 0;
  if (o_.slurm) {
    rc = runSweepSlurm(plan, dir, o_.slurm_options, exe_);
    if (rc != 0) throw std::runtime_error("the batch " + dir + " could not be submitted to Slurm");
    // Waits for every case's status (the gather job writes nothing).
    for (;;) {
      bool all = true;
      for (std::size_t i = 0; i < plan.cases.size() && all; ++i) {
        all = readCaseStatus(plan, dir, i).present;
      }
      if (all) break;
      if (stop_ && stop_()) throw CalibrationStopped{};
      sleep(2);
    }
  } else {
    rc = runSweepLocal(plan, dir, o_.jobs, exe_, stop_);
  }
  const bool stopped = o_.slurm ? false : rc < 0;
  kept_ += static_cast<int>(kept);
  for (std::size_t j = 0; j < todo.size(); ++j) {
    Evaluation e = readEvaluation(plan, dir, j);
    // Stopped: the cases that finished count (the best so far among them).
    if (stopped && !readCaseStatus(plan, dir, j).present) continue;
    ++evaluations_;
    history_.emplace_back(todo[j], e);
    const std::vector<double> key(todo[j].data(), todo[j].data() + todo[j].size());
    cache_[key] = e;
    if (e.ok && (!best_.ok || e.misfit < best_.misfit)) {
      best_ = e;
      best_u_ = todo[j];
    }
    out[where[j]] = e;
  }
  if (stopped) throw CalibrationStopped{};
  std::fprintf(stderr,
               "calibrate: %d evaluations (%d kept from an earlier run), best misfit %.6g at %s\n",
               evaluations_, kept_, best_.ok ? best_.misfit : std::nan(""),
               best_.ok ? describe(best_u_).c_str() : "(none yet)");
  return out;
}

namespace {

// Point i (from 1) of the Halton sequence in n dimensions: a deterministic
// design that fills the box evenly, so the fit starts in the best basin
// the design finds (the misfit of a replay has many small local minima).
Eigen::VectorXd halton(int i, int n) {
  static const int kPrimes[] = {2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53};
  Eigen::VectorXd u(n);
  for (int k = 0; k < n; ++k) {
    const int b = kPrimes[k % 16];
    double f = 1.0, r = 0.0;
    for (int j = i; j > 0; j /= b) {
      f /= b;
      r += f * (j % b);
    }
    u[k] = r;
  }
  return u;
}

}  // namespace

FitOutcome fitGlobal(Evaluator& ev, const Eigen::VectorXd& u0) {
  FitOutcome out;
  out.u = u0;
  const int n = static_cast<int>(u0.size());
  const CalibrationOptions& o = ev.options();
  // The start, the design and a line through the start along each key,
  // as one batch: dlib's first model. Then the point that takes each
  // key's best value on its line (most keys act apart: a yield point and a
  // friction coefficient find their valleys each on its own).
  std::vector<Eigen::VectorXd> design = {u0};
  for (int i = 1; i <= o.design_points; ++i) design.push_back(halton(i, n));
  const std::size_t lines_from = design.size();
  constexpr int kLine = 10;
  for (int k = 0; k < n; ++k) {
    for (int i = 0; i < kLine; ++i) {
      Eigen::VectorXd p = u0;
      p[k] = (i + 0.5) / kLine;
      design.push_back(p);
    }
  }
  auto toDlib = [n](const Eigen::VectorXd& u) {
    dlib::matrix<double, 0, 1> x(n);
    for (int k = 0; k < n; ++k) x(k) = u[k];
    return x;
  };
  // dlib maximizes: -misfit; a failed replay counts as twice the worst.
  double worst = 0.0;
  auto score = [&](const Evaluation& e) { return e.ok ? -e.misfit : -2.0 * std::max(worst, 1.0); };
  std::vector<dlib::function_evaluation> initial;
  try {
    const std::vector<Evaluation> first = ev.run(design);
    if (!first[0].ok) throw std::runtime_error("the replay at the start failed: " + first[0].error);
    for (const Evaluation& e : first) {
      if (e.ok) worst = std::max(worst, e.misfit);
    }
    for (std::size_t i = 0; i < design.size(); ++i) {
      initial.emplace_back(toDlib(design[i]), score(first[i]));
    }
    Eigen::VectorXd separable = u0;
    for (int k = 0; k < n; ++k) {
      double best = first[0].misfit;
      for (int i = 0; i < kLine; ++i) {
        const Evaluation& e = first[lines_from + k * kLine + i];
        if (e.ok && e.misfit < best) {
          best = e.misfit;
          separable[k] = design[lines_from + k * kLine + i][k];
        }
      }
    }
    const Evaluation sep = ev.run({separable})[0];
    if (sep.ok) worst = std::max(worst, sep.misfit);
    initial.emplace_back(toDlib(separable), score(sep));
  } catch (const CalibrationStopped&) {
    out.stopped = true;
    return out;
  }
  dlib::global_function_search search(
      {dlib::function_spec(toDlib(Eigen::VectorXd::Zero(n)), toDlib(Eigen::VectorXd::Ones(n)))},
      {initial});
  // Batches of the requests dlib has outstanding at once: one refines the
  // best point's local model, the others explore the global one. A batch
  // takes an i-th point while room(points done, i) says so; false when
  // stopped.
  const int batch = std::max(2, o.slurm ? o.batch : o.jobs);
  auto searchInBatches = [&](dlib::global_function_search& s,
                             const std::function<bool(int, int)>& room) {
    for (int done = 0; room(done, 0);) {
      std::vector<dlib::function_evaluation_request> requests;
      std::vector<Eigen::VectorXd> points;
      for (int i = 0; i < batch && room(done, i); ++i) {
        requests.push_back(s.get_next_x());
        Eigen::VectorXd u(n);
        for (int k = 0; k < n; ++k) u[k] = requests.back().x()(k);
        points.push_back(u);
      }
      std::vector<Evaluation> e;
      try {
        e = ev.run(points);
      } catch (const CalibrationStopped&) {
        return false;
      }
      for (std::size_t i = 0; i < e.size(); ++i) {
        if (e[i].ok) worst = std::max(worst, e[i].misfit);
        requests[i].set(score(e[i]));
      }
      done += static_cast<int>(points.size());
    }
    return true;
  };
  out.stopped = !searchInBatches(
      search, [&](int, int i) { return ev.evaluations() + i < o.max_evaluations; });
  // Every other basin the search found, refined before the verdicts: the
  // best evaluation of each region more than 15 % of a range from the best
  // and from each other (up to three), searched again within +-15 % of it.
  // A second basin that fits about as well leaves the keys that differ not
  // identifiable, rather than the first basin's curvature pinning them.
  if (!out.stopped && ev.haveBest()) {
    std::vector<std::pair<double, Eigen::VectorXd>> sorted;
    for (const auto& [uh, eh] : ev.history()) {
      if (eh.ok) sorted.emplace_back(eh.misfit, uh);
    }
    std::sort(sorted.begin(), sorted.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<Eigen::VectorXd> basins = {ev.bestU()};
    for (const auto& [f, uh] : sorted) {
      if (basins.size() > 3) break;
      bool apart = true;
      for (const Eigen::VectorXd& b : basins)
        apart = apart && (uh - b).cwiseAbs().maxCoeff() > 0.15;
      if (apart) basins.push_back(uh);
    }
    for (std::size_t b = 1; b < basins.size() && !out.stopped; ++b) {
      const Eigen::VectorXd lo = (basins[b].array() - 0.15).max(0.0).matrix();
      const Eigen::VectorXd hi = (basins[b].array() + 0.15).min(1.0).matrix();
      std::vector<dlib::function_evaluation> seen;
      for (const auto& [uh, eh] : ev.history()) {
        if (eh.ok && (uh.array() >= lo.array()).all() && (uh.array() <= hi.array()).all())
          seen.emplace_back(toDlib(uh), -eh.misfit);
      }
      dlib::global_function_search local({dlib::function_spec(toDlib(lo), toDlib(hi))}, {seen});
      out.stopped = !searchInBatches(local, [&](int done, int i) { return done + i < 10 * n; });
    }
  }
  out.u = ev.haveBest() ? ev.bestU() : u0;
  char line[160];
  std::snprintf(line, sizeof line,
                "dlib global_function_search: %d evaluations (the search's budget %d, then the "
                "other basins refined).",
                ev.evaluations(), o.max_evaluations);
  out.termination = line;
  return out;
}
// A key is pinned down when its 1-sigma uncertainty is at most this
// fraction of its range.
constexpr double kPinnedDown = 0.1;

std::vector<ParameterVerdict> judgeParameters(Evaluator& ev, const Eigen::VectorXd& u) {
  const int n = static_cast<int>(u.size());
  const double step = ev.step();
  // Central differences about the optimum (one-sided at a bound).
  std::vector<Eigen::VectorXd> points = {u};
  std::vector<double> lo(n), hi(n);
  for (int k = 0; k < n; ++k) {
    lo[k] = std::max(0.0, u[k] - step);
    hi[k] = std::min(1.0, u[k] + step);
    Eigen::VectorXd a = u, b = u;
    a[k] = lo[k];
    b[k] = hi[k];
    points.push_back(a);
    points.push_back(b);
  }
  // And a line through the optimum along each key (the other keys held):
  // where the misfit stays as low far away, the key is not pinned down.
  std::vector<Eigen::VectorXd> lines;
  std::vector<int> line_key;
  for (int k = 0; k < n; ++k) {
    for (double f : {-0.5, -0.3, -0.2, -0.1, 0.1, 0.2, 0.3, 0.5}) {
      Eigen::VectorXd p = u;
      p[k] = std::clamp(u[k] + f, 0.0, 1.0);
      if (std::abs(p[k] - u[k]) > step) {
        lines.push_back(p);
        line_key.push_back(k);
      }
    }
  }
  std::vector<Eigen::VectorXd> all = points;
  all.insert(all.end(), lines.begin(), lines.end());
  const std::vector<Evaluation> e = ev.run(all);
  const Evaluation& c = e[0];
  if (!c.ok) throw std::runtime_error("the replay at the optimum failed: " + c.error);
  const Eigen::Index m = c.residuals.size();
  Eigen::MatrixXd j(m, n);
  for (int k = 0; k < n; ++k) {
    const Evaluation& a = e[1 + 2 * k];
    const Evaluation& b = e[2 + 2 * k];
    for (const Evaluation* x : {&a, &b}) {
      if (!x->ok) throw std::runtime_error("a replay beside the optimum failed: " + x->error);
      if (x->residuals.size() != m) {
        throw std::runtime_error("a replay beside the optimum compares " +
                                 std::to_string(x->residuals.size()) + " samples, the optimum " +
                                 std::to_string(m) + " (the profiles paired changed)");
      }
    }
    j.col(k) = (b.residuals - a.residuals) / (hi[k] - lo[k]);
  }
  // Each measurement's noise from its own residuals at the optimum: the
  // variance of a weighted residual is its group's mean square.
  Eigen::VectorXd d(m);
  const int groups[3] = {c.tension_samples, c.profile_points,
                         static_cast<int>(m) - c.tension_samples - c.profile_points};
  Eigen::Index at = 0;
  for (int g : groups) {
    if (g <= 0) continue;
    const double ms = c.residuals.segment(at, g).squaredNorm() / g;
    d.segment(at, g).setConstant(ms);
    at += g;
  }
  // Cov = H+ J^T D J H+, H = J^T J (the sandwich: right for any weights).
  const Eigen::MatrixXd h = j.transpose() * j;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::VectorXd s = svd.singularValues();
  Eigen::VectorXd s_inv = Eigen::VectorXd::Zero(n);
  for (int k = 0; k < n; ++k) {
    if (s[k] > 1e-12 * s[0]) s_inv[k] = 1.0 / s[k];
  }
  const Eigen::MatrixXd h_plus = svd.matrixV() * s_inv.asDiagonal() * svd.matrixU().transpose();
  const Eigen::MatrixXd cov = h_plus * (j.transpose() * d.asDiagonal() * j) * h_plus;

  // The band: every evaluation whose chi-square is within 9 of the
  // optimum's (each measurement's noise its residuals' RMS there) is not
  // excluded at three sigma; a third of the farthest one's distance sets a
  // floor under each key's uncertainty (the curvature alone misses a misfit
  // with many small minima, and a second basin that fits almost as well).
  const double rms_opt[3] = {c.tension_rms_N, c.profile_rms_mm, c.bulging_rms_mm};
  std::vector<double> band(n, 0.0);
  for (const auto& [uh, eh] : ev.history()) {
    if (!eh.ok || eh.residuals.size() != m) continue;
    const double rms_h[3] = {eh.tension_rms_N, eh.profile_rms_mm, eh.bulging_rms_mm};
    double dchi = 0.0;
    for (int g = 0; g < 3; ++g) {
      if (groups[g] > 0 && rms_opt[g] > 0.0)
        dchi +=
            groups[g] * (rms_h[g] * rms_h[g] - rms_opt[g] * rms_opt[g]) / (rms_opt[g] * rms_opt[g]);
    }
    if (dchi > 9.0) continue;
    // Within 3 sigma: a third of its distance is a 1-sigma floor.
    for (int k = 0; k < n; ++k) band[k] = std::max(band[k], std::abs(uh[k] - u[k]) / 3.0);
  }

  std::vector<ParameterVerdict> out(n);
  const CalibrationOptions& o = ev.options();
  for (int k = 0; k < n; ++k) {
    const double range = o.fit[k].hi - o.fit[k].lo;
    ParameterVerdict& v = out[k];
    if (j.col(k).squaredNorm() == 0.0) {
      v.identifiable = false;
      v.sigma = std::nan("");
      v.note =
          "the replay does not depend on it: every residual is the same to the last bit over " +
          std::to_string(static_cast<int>(std::lround(100 * (hi[k] - lo[k])))) +
          " % of its range about the optimum";
      if (o.fit[k].key == "contact.kinetic_friction")
        v.note +=
            " (kinetic friction acts only where the wire slides on the core: it did not slide)";
      continue;
    }
    // The curvature over +-20 % of the range as well: a parabola through
    // the misfit along the key's line (least squares), which sees the
    // trend through the small jumps of the replay's discrete events that a
    // 5 % stencil takes for curvature; 1 sigma where it rises by the
    // misfit per degree of freedom.
    double secant = std::numeric_limits<double>::infinity();
    {
      Eigen::MatrixXd a(0, 2);
      Eigen::VectorXd y(0);
      auto add = [&](double d, const Evaluation& x) {
        if (!x.ok || std::abs(d) > 0.2 + 1e-12 || d == 0.0) return;
        a.conservativeResize(a.rows() + 1, 2);
        y.conservativeResize(y.size() + 1);
        a.row(a.rows() - 1) << d * d, d;
        y[y.size() - 1] = x.misfit - c.misfit;
      };
      add(lo[k] - u[k], e[1 + 2 * k]);
      add(hi[k] - u[k], e[2 + 2 * k]);
      for (std::size_t i = 0; i < lines.size(); ++i) {
        if (line_key[i] == k) add(lines[i][k] - u[k], e[points.size() + i]);
      }
      const double dof = std::max(1.0, static_cast<double>(m - n));
      if (a.rows() >= 2) {
        const Eigen::Vector2d q = a.colPivHouseholderQr().solve(y);
        secant =
            q[0] > 0.0 ? std::sqrt(c.misfit / dof / q[0]) : std::numeric_limits<double>::infinity();
      }
    }
    const double sigma_curvature =
        std::max(std::sqrt(std::max(0.0, cov(k, k))), std::isfinite(secant) ? secant : 1.0);
    const double sigma_u = std::max(sigma_curvature, band[k]);
    if (band[k] > sigma_curvature) {
      v.note = "an evaluation " + std::to_string(static_cast<int>(std::lround(300 * band[k]))) +
               " % of its range away fits almost as well (chi-square within 9)";
    }
    // The direction the data cannot see: a singular value dropped.
    bool null_direction = false;
    for (int q = 0; q < n; ++q) {
      if (s_inv[q] == 0.0 && std::abs(svd.matrixV()(k, q)) > 0.1) null_direction = true;
    }
    v.sigma = sigma_u * range;
    if (null_direction || sigma_u > kPinnedDown) {
      v.identifiable = false;
      v.note =
          (null_direction ? std::string("the data cannot tell it apart from another key's change")
                          : "the data pin it down only to +-" +
                                std::to_string(static_cast<int>(std::lround(100 * sigma_u))) +
                                " % of its range (1 sigma)") +
          (v.note.empty() ? "" : ": " + v.note);
      v.sigma = std::nan("");
      continue;
    }
    for (int q = 0; q < n; ++q) {
      const double rho = cov(k, q) / std::sqrt(std::max(1e-300, cov(k, k) * cov(q, q)));
      if (q != k && std::abs(rho) > 0.9) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "correlated with %s (%+.2f)", o.fit[q].key.c_str(), rho);
        v.note += (v.note.empty() ? "" : "; ") + std::string(buf);
      }
    }
  }
  return out;
}

}  // namespace cws_tools
