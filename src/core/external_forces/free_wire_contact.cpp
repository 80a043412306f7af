#include "coil_winding_sim/core/external_forces/free_wire_contact.hpp"

#include <algorithm>
#include <cmath>

#include "coil_winding_sim/core/assembly/spatial_assembly.hpp"

namespace cws {

FreeWireContact::FreeWireContact(const WireConstants& c, const Contact& contact)
    : c_(c),
      contact_(contact),
      touch_distance_(2.0 * c.radius),
      reach_(4.0 * c.radius),
      rebuild_move_(0.5 * c.radius),
      skip_(contact.skipPoints()) {
  // A point keeps at most kRuns pairs: the list never outgrows this.
  pairs_.reserve(static_cast<std::size_t>(c.capacity) * kRuns);
  p_built_.setZero(3, c.capacity);
}

template <class Positions>
bool FreeWireContact::geometry(const Positions& p, int first, int a, int b, Geometry& g) const {
  const int lo = std::max(first, b - 1), hi = std::min(b + 1, a - 1 - skip_);
  if (a < first || lo > hi) return false;
  double best = -1.0;
  const Eigen::Vector3d p_a = p(a);
  for (int m = lo; m <= hi; ++m) {
    const Eigen::Vector3d p_m = p(m);
    const Eigen::Vector3d d = p(m + 1) - p_m;
    const double t = std::clamp((p_a - p_m).dot(d) / d.squaredNorm(), 0.0, 1.0);
    const Eigen::Vector3d delta = p_a - (p_m + t * d);
    const double dist = delta.norm();
    if (best >= 0.0 && dist >= best) continue;
    best = dist;
    const bool inside = t > 0.0 && t < 1.0;
    g = Geometry{m, t, delta, inside ? Eigen::Vector3d(d.normalized()) : Eigen::Vector3d::Zero()};
  }
  return best > 0.0;
}

bool FreeWireContact::geometry(const Eigen::Matrix3Xd& p, int first, int a, int b,
                               Geometry& g) const {
  return geometry([&p](int i) -> Eigen::Vector3d { return p.col(i); }, first, a, b, g);
}

FreeWireContact::PairForce FreeWireContact::pairForce(const Geometry& g, const Eigen::Vector3d& r_v,
                                                      double alpha, bool jacobian,
                                                      double floor_speed) const {
  PairForce out;
  const Eigen::Vector3d& delta = g.delta;
  const double dist = delta.norm();
  const Eigen::Vector3d n = delta / dist;
  out.h = touch_distance_ - dist;
  const double vn = r_v.dot(n);
  const Contact::NormalForce law = contact_.normalLaw(out.h, vn);
  const double normal = law.force;
  out.f = normal * n;
  out.f_dissipative = (normal - contact_.stiffness() * out.h) * n;
  // Kinetic friction against the sliding velocity (viscous below
  // floor_speed).
  const double mu = contact_.kineticFriction();
  const Eigen::Vector3d vh = r_v - vn * n;
  const double speed = vh.norm();
  const double scale = std::max({speed, floor_speed, Contact::kTinySlidingSpeed});
  const Eigen::Vector3d e = vh / scale;
  if (mu > 0.0) {
    out.f -= mu * normal * e;
    out.f_dissipative -= mu * normal * e;
  }
  if (!jacobian) return out;
  // d n / d p_a (a point moving along the segment keeps its normal, as on
  // a cylinder; past an end, a sphere's), d N (through h and v_n), and the
  // sliding velocity's derivative, with d r_v / d p_a = alpha I. Taken as
  // the derivative in delta for the segment's ends too (their turning of n
  // and of the nearest point is left out: modified Newton).
  const Eigen::Matrix3d id = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d dn = (id - n * n.transpose() - g.tangent * g.tangent.transpose()) / dist;
  const Eigen::RowVector3d r_dn = r_v.transpose() * dn;
  const Eigen::RowVector3d dnormal =
      -law.d_h * n.transpose() + law.d_vn * (alpha * n.transpose() + r_dn);
  out.df = n * dnormal + normal * dn;
  if (mu > 0.0) {
    const Eigen::Matrix3d dvh = alpha * (id - n * n.transpose()) - n * r_dn - vn * dn;
    const Eigen::Matrix3d proj = (speed >= scale ? id - e * e.transpose() : id) / scale;
    out.df -= mu * (e * dnormal + normal * proj * dvh);
  }
  return out;
}

template <class Sink>
void FreeWireContact::law(Sink& s) const {
  const bool frozen = s.flagsFrozen(), jacobian = s.jacobian();
  const double alpha = s.velocityGain();
  // Newton steps divide friction by at least stick_speed (viscous below
  // it); explicit ones take the sliding direction as it is.
  const double floor_speed = frozen ? contact_.stickSpeed() : 0.0;
  const auto p = [&s](int i) -> Eigen::Vector3d { return s.p(i); };
  for (const Pair& pair : pairs_) {
    if (frozen && !pair.trial_active) continue;
    Geometry g;
    if (!geometry(p, s.first(), pair.a, pair.b, g)) continue;
    // (An active pair's spring stays linear past h = 0 within a solve.)
    if (!frozen && g.delta.norm() >= touch_distance_) continue;
    const int m = g.m;
    const Eigen::Vector3d r_v = s.v(pair.a) - (1.0 - g.t) * s.v(m) - g.t * s.v(m + 1);
    const PairForce pf = pairForce(g, r_v, alpha, jacobian, floor_speed);
    // On the point, and its reaction on the segment's ends.
    s.addPointForce(pair.a, pf.f, pf.f_dissipative);
    s.addPointForce(m, -(1.0 - g.t) * pf.f, -(1.0 - g.t) * pf.f_dissipative);
    s.addPointForce(m + 1, -g.t * pf.f, -g.t * pf.f_dissipative);
    if (jacobian) s.addPairCoupling(pair.a, m, g.t, pf.df);
  }
}
template void FreeWireContact::law(ExplicitSink&) const;
template void FreeWireContact::law(SpatialSink&) const;

void FreeWireContact::beginSpatial(const SpatialState& s0) {
  // (After a restore the list is built here, from the step's start.)
  if (needsBuild(s0.p, s0.first, s0.n)) refresh(s0.p, s0.first, s0.n);
  for (Pair& pair : pairs_) pair.trial_active = pair.active;
}

bool FreeWireContact::recheckSpatial(const SpatialState& s) {
  bool changed = false;
  for (Pair& pair : pairs_) {
    Geometry g;
    const char on = geometry(s.p, s.first, pair.a, pair.b, g) && g.delta.norm() < touch_distance_;
    if (on == pair.trial_active) continue;
    pair.trial_active = on;
    changed = true;
  }
  // The pairs lie outside the band: a change needs no band row factored
  // again beyond the first (the couplings are factored anew with it).
  if (changed) s.flagChangedAt(s.first);
  return changed;
}

bool FreeWireContact::needsBuild(const Eigen::Matrix3Xd& p, int first, int n) const {
  if (first != built_first_ || n != built_n_) return true;
  const int b = std::max(0, first - 1);
  const double limit = rebuild_move_ * rebuild_move_;
  for (int i = b; i < n; ++i) {
    if ((p.col(i) - p_built_.col(i)).squaredNorm() > limit) return true;
  }
  return false;
}

void FreeWireContact::build(const Eigen::Matrix3Xd& p, int first, int n) {
  pairs_.clear();
  const int b0 = std::max(0, first - 1);
  p_built_.middleCols(b0, n - b0) = p.middleCols(b0, n - b0);
  // (Segments from `first` on: the boundary segment joins the carried
  // wire, whose last point's sphere the carried-wire contact already has.)
  built_first_ = first;
  built_n_ = n;
  // A segment is within reach of a point only if its first end is within
  // reach plus its length (segments stretch little: half as long again).
  const double coarse = reach_ + 1.5 * c_.segment_length;
  for (int a = first; a < n; ++a) {
    // The runs of segments within reach, in index order, the nearest of
    // each; the point keeps the kRuns nearest runs. (Taking the first ones
    // in index order lost the turn a landing point was about to pass
    // through, behind two older turns it grazed.)
    int run_b[kCandidateRuns], last_b = -10;
    double run_dist[kCandidateRuns];
    int runs = 0, current = -1;  // the run segment last_b belongs to (-1: one not kept)
    for (int b = first; b <= a - 1 - skip_; ++b) {
      if ((p.col(a) - p.col(b)).squaredNorm() > coarse * coarse) continue;
      const Eigen::Vector3d d = p.col(b + 1) - p.col(b);
      const double t = std::clamp((p.col(a) - p.col(b)).dot(d) / d.squaredNorm(), 0.0, 1.0);
      const double dist = (p.col(a) - p.col(b) - t * d).norm();
      if (dist >= reach_) continue;
      const bool continues = b - last_b <= 2;
      last_b = b;
      if (continues && current >= 0) {
        if (dist < run_dist[current]) {
          run_b[current] = b;
          run_dist[current] = dist;
        }
      } else if (runs < kCandidateRuns) {
        current = runs++;
        run_b[current] = b;
        run_dist[current] = dist;
      } else {
        // More runs than candidates: this one takes the farthest one's
        // place if nearer.
        const int far = static_cast<int>(std::max_element(run_dist, run_dist + runs) - run_dist);
        current = dist < run_dist[far] ? far : -1;
        if (current >= 0) {
          run_b[current] = b;
          run_dist[current] = dist;
        }
      }
    }
    // The kRuns nearest (selection: few).
    for (int kept = 0; kept < kRuns && runs > 0; ++kept) {
      const int near = static_cast<int>(std::min_element(run_dist, run_dist + runs) - run_dist);
      pairs_.push_back(Pair{a, run_b[near], 0, 0});
      run_b[near] = run_b[runs - 1];
      run_dist[near] = run_dist[runs - 1];
      --runs;
    }
  }
}

void FreeWireContact::commit(const AcceptedStep& step) { refresh(step.k.p_world, c_.first, c_.n); }

void FreeWireContact::refresh(const Eigen::Matrix3Xd& p, int first, int n) {
  if (needsBuild(p, first, n)) build(p, first, n);
  elastic_committed_ = 0.0;
  deepest_ = Deepest();
  const double stiffness = contact_.stiffness();
  for (Pair& pair : pairs_) {
    Geometry g;
    pair.active = geometry(p, first, pair.a, pair.b, g) && g.delta.norm() < touch_distance_;
    if (!pair.active) continue;
    const double h = touch_distance_ - g.delta.norm();
    elastic_committed_ += 0.5 * stiffness * h * h;
    if (h > deepest_.depth_m) deepest_ = Deepest{h, pair.a, g.m};
  }
}

void FreeWireContact::shrink(const WireKinematics& /*k*/) {
  // Point n-1 leaves: its pairs go, and the list is built anew at the next
  // commit.
  const int leaving = c_.n - 1;
  pairs_.erase(std::remove_if(pairs_.begin(), pairs_.end(),
                              [&](const Pair& x) { return x.a >= leaving || x.b + 1 >= leaving; }),
               pairs_.end());
  built_n_ = -1;
}

void FreeWireContact::retireFront(int k) {
  // Pairs lie among integrated points, behind which the front retires.
  for (Pair& pair : pairs_) {
    pair.a -= k;
    pair.b -= k;
  }
  const int b0 = std::max(0, built_first_ - 1);
  if (built_first_ >= 0 && built_n_ > b0) {
    // (Column by column, front first: the ranges overlap.)
    for (int i = b0; i < built_n_; ++i) p_built_.col(i - k) = p_built_.col(i);
    built_first_ -= k;
    built_n_ -= k;
  } else {
    built_first_ = built_n_ = -1;
  }
  if (deepest_.point >= 0) {
    deepest_.point -= k;
    deepest_.segment -= k;
  }
}

void FreeWireContact::restoreHistory(HistoryReader& /*in*/) {
  pairs_.clear();
  built_first_ = built_n_ = -1;
  elastic_committed_ = 0.0;
  deepest_ = Deepest();
}

bool FreeWireContact::pairForceAt(const SpatialState& s, int a, int b, Eigen::Vector3d& f_a,
                                  Eigen::Matrix3d& df_a) const {
  Geometry g;
  if (!geometry(s.p, s.first, a, b, g)) return false;
  const Eigen::Vector3d r_v = s.v.col(a) - (1.0 - g.t) * s.v.col(g.m) - g.t * s.v.col(g.m + 1);
  const PairForce pf = pairForce(g, r_v, s.alpha, true, contact_.stickSpeed());
  f_a = pf.f;
  df_a = pf.df;
  return true;
}

int FreeWireContact::touching() const {
  int count = 0;
  for (const Pair& pair : pairs_) count += pair.active;
  return count;
}

}  // namespace cws
