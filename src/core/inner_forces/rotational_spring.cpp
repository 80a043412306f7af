#include "coil_winding_sim/core/inner_forces/rotational_spring.hpp"

#include <algorithm>
#include <cmath>

#include "coil_winding_sim/core/assembly/planar_assembly.hpp"
#include "coil_winding_sim/core/assembly/spatial_assembly.hpp"
#include "coil_winding_sim/core/base/quaternion.hpp"

namespace cws {

RotationalSpring::RotationalSpring(const char* name, const WireConstants& c,
                                   const HysteresisParams& p, bool plastic, int first, int count)
    : name_(name), c_(c), law_(p), plastic_(plastic), first_(first), count_(count) {
  if (plastic_) {
    upper_.assign(static_cast<std::size_t>(c_.capacity - 1) * count_, law_.initialUpper());
    x_committed_.assign(static_cast<std::size_t>(c_.capacity - 1) * count_, 0.0);
    line_.assign(static_cast<std::size_t>(c_.capacity - 1) * count_, TwoLineLaw::kElastic);
    line_committed_ = line_;
  }
}

double RotationalSpring::jointLength(int j) const {
  // (Joint 0 of the whole wire, at the fixed end, stands for half a segment.)
  return j + c_.retired == 0 ? 0.5 * c_.segment_length : c_.segment_length;
}

Eigen::Vector3d RotationalSpring::darboux(const WireKinematics& k, int j) const {
  return (2.0 / jointLength(j)) * quat::gTimes(k.q.col(j), k.q.col(j + 1));
}

double RotationalSpring::stressOf(double x, int idx) const {
  return plastic_ ? law_.stress(x, upper_[idx]) : law_.elasticRigidity() * x;
}

double RotationalSpring::stressTangent(double x, int idx, bool mapped, double& tangent) const {
  if (!plastic_) {
    tangent = law_.elasticRigidity();
    return tangent * x;
  }
  if (mapped) {
    tangent = law_.tangent(x, upper_[idx]);
    return law_.stress(x, upper_[idx]);
  }
  return law_.stressOnBranch(x, upper_[idx], line_[idx], tangent);
}

void RotationalSpring::beginLines(int first, int n) {
  if (!plastic_) return;
  from_ = (first - 1) * count_;
  to_ = (n - 1) * count_;
  // Every solve of a step (a retried one too) starts from the lines of the
  // last accepted step (a snapshot carries them); see Stretching::beginLines.
  std::copy(line_committed_.begin() + from_, line_committed_.begin() + to_, line_.begin() + from_);
}

template <class Argument>
int RotationalSpring::recheckLines(int first, int n, bool mapped, Argument argument) {
  if (!plastic_) return -1;
  int changed = -1;
  for (int j = first - 1; j + 1 < n; ++j) {
    for (int c = 0; c < count_; ++c) {
      double x;
      if (!argument(j, c, x)) continue;
      const int idx = j * count_ + c;
      // Return-mapped: the line the solve used, recorded for the commit.
      if (mapped) {
        line_[idx] = static_cast<signed char>(law_.branch(x, upper_[idx]));
        continue;
      }
      if (!law_.lineHolds(x, upper_[idx], line_[idx])) {
        line_[idx] = static_cast<signed char>(law_.branch(x, upper_[idx]));
        changed = j;
      }
    }
  }
  return changed;
}

Eigen::Vector3d RotationalSpring::darboux(const SpatialState& s, int j) const {
  return (2.0 / jointLength(j)) * quat::gTimes(s.q.col(j), s.q.col(j + 1));
}

// The laws' arguments: in the plane, kappa n_material[c] (none for a
// component with no part about n); in 3-D, the Darboux vector's components.
void RotationalSpring::beginImplicitStep(const PlanarState& s0) { beginLines(s0.first, s0.n); }

bool RotationalSpring::recheckFlags(const PlanarState& s) {
  // The joints in order: segment j serves joints j and j+1 (as in
  // addPlanarForces).
  int joint = s.first - 2;
  double kappa = 0.0;
  planar::SegmentGeometry ga, gb;
  gb.setPrescribed(s.boundary_tangent);
  return recheckLines(s.first, s.n, s.return_mapping, [&](int j, int c, double& x) {
           const double w = s.n_material[first_ + c];
           if (w == 0.0) return false;
           if (j != joint) {
             ga = gb;
             if (j != joint + 1) ga.set(s.segment(j - 1), false);
             gb.set(s.segment(j), false);
             double sin_half, cos_half;
             kappa = planar::jointCurvature(ga, gb, jointLength(j), sin_half, cos_half);
             joint = j;
           }
           x = kappa * w;
           return true;
         }) >= 0;
}

void RotationalSpring::beginSpatialStep(const SpatialState& s0) { beginLines(s0.first, s0.n); }

bool RotationalSpring::recheckSpatialFlags(const SpatialState& s) {
  // One Darboux vector per joint for all of its components.
  int joint = -1;
  Eigen::Vector3d omega;
  const int changed = recheckLines(s.first, s.n, s.return_mapping, [&](int j, int c, double& x) {
    if (j != joint) {
      joint = j;
      omega = darboux(s, j);
    }
    x = omega[first_ + c];
    return true;
  });
  // (The highest joint changed, j to j + 1.)
  if (changed >= 0) s.flagChangedAt(changed + 1);
  return changed >= 0;
}

void RotationalSpring::adoptFlags() {
  if (!plastic_) return;
  std::copy(line_.begin() + from_, line_.begin() + to_, line_committed_.begin() + from_);
}

double RotationalSpring::moment(const WireKinematics& k, int j, int m) const {
  return stressOf(darboux(k, j)[first_ + m], j * count_ + m);
}

double RotationalSpring::plasticValue(int j, int m) const {
  return plastic_ ? law_.plasticStrain(upper_[j * count_ + m]) : 0.0;
}

void RotationalSpring::addForces(double, const WireKinematics& k, WireForces& f) const {
  for (int j = c_.first - 1; j + 1 < c_.n; ++j) {
    const quat::Vec4 qa = k.q.col(j);
    const quat::Vec4 qb = k.q.col(j + 1);
    const Eigen::Vector3d omega = (2.0 / jointLength(j)) * quat::gTimes(qa, qb);
    Eigen::Vector3d m = Eigen::Vector3d::Zero();
    for (int i = 0; i < count_; ++i) m[first_ + i] = stressOf(omega[first_ + i], j * count_ + i);
    // -lambda m . dOmega/dq with dOmega/dq_b = (2/lambda) G(q_a) and
    // dOmega/dq_a = -(2/lambda) G(q_b): the joint length lambda cancels.
    f.f_q.col(j) += 2.0 * quat::G(qb).transpose() * m;
    f.f_q.col(j + 1) -= 2.0 * quat::G(qa).transpose() * m;
  }
}

void RotationalSpring::addPlanarForces(const PlanarState& s, PlanarAssembly& a) const {
  // In the plane, joint j turns by dphi about n from frame j to frame j+1
  // (segment j), so Omega = (2 / lambda) sin(dphi / 2) n_material: each of
  // this spring's components is kappa n_material[c] with its own law, and
  // the moment about n is m = sum_c s_c n_material[c]. Nothing to do for a
  // spring with no component about n (torsion).
  double weight = 0.0;
  for (int c = 0; c < count_; ++c) weight += std::abs(s.n_material[first_ + c]);
  if (weight == 0.0) return;
  const bool jacobian = a.wantsJacobian();
  // Each segment's geometry is worked out once and serves both joints it
  // belongs to: segment j is joint j's b and joint j+1's a. Frame first-1
  // is the prescribed one (a unit tangent, no unknowns).
  planar::SegmentGeometry ga, gb;
  ga.setPrescribed(s.boundary_tangent);
  for (int j = s.first - 1; j + 1 < s.n; ++j) {
    const double lambda = jointLength(j);
    const bool prescribed = j == s.first - 1;
    gb.set(s.segment(j), jacobian);
    double sin_half, cos_half;
    const double kappa = planar::jointCurvature(ga, gb, lambda, sin_half, cos_half);
    double m = 0.0, dm = 0.0;
    for (int c = 0; c < count_; ++c) {
      const double w = s.n_material[first_ + c];
      if (w == 0.0) continue;
      double k;
      m += w * stressTangent(kappa * w, j * count_ + c, s.return_mapping, k);
      dm += w * w * k;
    }
    // Generalized force on dphi: Q = -d(lambda W)/d dphi = -m cos(dphi / 2);
    // d dphi / dx is gb on point j+1, -gb - ga on j and ga on j-1.
    const double q = -m * cos_half;
    const Eigen::Vector2d g_mid = -gb.gradient - ga.gradient;
    a.addForce(j + 1, q * gb.gradient);
    a.addForce(j, q * g_mid);
    if (prescribed) {
      a.addBoundaryTorque(-q);
    } else {
      a.addForce(j - 1, q * ga.gradient);
    }
    if (jacobian) {
      // dq g_r g_c^T + q d^2 dphi / dx_r dx_c over points j-1, j, j+1;
      // dphi = phi_b - phi_a, whose second derivatives are +-hb and +-ha.
      const double dq = -dm * cos_half * cos_half / lambda + 0.5 * m * sin_half;
      const Eigen::Matrix2d qhb = q * gb.hessian;
      const Eigen::Matrix2d k_bb = dq * gb.gradient * gb.gradient.transpose() + qhb;
      const Eigen::Matrix2d k_bm = dq * gb.gradient * g_mid.transpose() - qhb;
      a.addStiffness(j + 1, j + 1, k_bb);
      a.addStiffness(j + 1, j, k_bm);
      a.addStiffness(j, j + 1, k_bm.transpose());
      if (prescribed) {
        a.addStiffness(j, j, dq * g_mid * g_mid.transpose() + qhb);
      } else {
        const Eigen::Matrix2d qha = q * ga.hessian;
        const Eigen::Matrix2d k_ma = dq * g_mid * ga.gradient.transpose() + qha;
        const Eigen::Matrix2d k_ba = dq * gb.gradient * ga.gradient.transpose();
        a.addStiffness(j, j, dq * g_mid * g_mid.transpose() + qhb - qha);
        a.addStiffness(j, j - 1, k_ma);
        a.addStiffness(j - 1, j, k_ma.transpose());
        a.addStiffness(j - 1, j - 1, dq * ga.gradient * ga.gradient.transpose() - qha);
        a.addStiffness(j + 1, j - 1, k_ba);
        a.addStiffness(j - 1, j + 1, k_ba.transpose());
      }
    }
    ga = gb;
  }
}

void RotationalSpring::commit(double, const WireKinematics& k) {
  if (!plastic_) return;
  // Carried joints do not deform: nothing to commit.
  for (int j = c_.first - 1; j + 1 < c_.n; ++j) {
    const Eigen::Vector3d omega = darboux(k, j);
    for (int i = 0; i < count_; ++i) {
      const int idx = j * count_ + i;
      const double x = omega[first_ + i];
      work_committed_ += jointLength(j) * law_.work(x_committed_[idx], x, upper_[idx]);
      upper_[idx] = law_.movedUpper(x, upper_[idx]);
      x_committed_[idx] = x;
    }
  }
}

void RotationalSpring::addSpatialForces(const SpatialState& s, SpatialAssembly& a) const {
  // The explicit model's generalized forces (addForces) on q_j and q_j+1,
  // f_a = 2 G(q_b)^T m and f_b = -2 G(q_a)^T m, with m(Omega) the laws'
  // moments and Omega = (2 / lambda) G(q_a) q_b, whose derivatives are
  // -(2 / lambda) G(q_b) and (2 / lambda) G(q_a). G(q)^T m is linear in q
  // (quat::gTransposeTimes), and everything is linear in m and dm: a
  // partner's components join this pass.
  if (in_shared_pass_) return;
  for (int j = s.first - 1; j + 1 < s.n; ++j) {
    const quat::Vec4 qa = s.q.col(j);
    const quat::Vec4 qb = s.q.col(j + 1);
    const double lambda = jointLength(j);
    const Eigen::Vector3d omega = (2.0 / lambda) * quat::gTimes(qa, qb);
    Eigen::Vector3d m = Eigen::Vector3d::Zero(), dm = Eigen::Vector3d::Zero();
    // Each spring's components: moment and tangent from its own laws.
    auto laws = [&](const RotationalSpring& r) {
      for (int i = 0; i < r.count_; ++i) {
        double k;
        m[r.first_ + i] =
            r.stressTangent(omega[r.first_ + i], j * r.count_ + i, s.return_mapping, k);
        dm[r.first_ + i] = k;
      }
    };
    laws(*this);
    if (partner_) laws(*partner_);
    a.addQForce(j, 2.0 * quat::gTransposeApply(qb, m));
    a.addQForce(j + 1, -2.0 * quat::gTransposeApply(qa, m));
    if (!a.wantsJacobianAt(j)) continue;
    const quat::Mat34 ga = quat::G(qa), gb = quat::G(qb);
    const Eigen::Matrix4d gm = quat::gTransposeTimes(m);
    const Eigen::Matrix<double, 4, 3> gad = ga.transpose() * dm.asDiagonal();
    const Eigen::Matrix<double, 4, 3> gbd = gb.transpose() * dm.asDiagonal();
    const double s2 = 4.0 / lambda;
    a.addStiffnessQQ(j, j, -s2 * gbd * gb);
    a.addStiffnessQQ(j, j + 1, 2.0 * gm + s2 * gbd * ga);
    a.addStiffnessQQ(j + 1, j, -2.0 * gm + s2 * gad * gb);
    a.addStiffnessQQ(j + 1, j + 1, -s2 * gad * ga);
  }
}

void RotationalSpring::shrink(const WireKinematics& k) {
  if (!plastic_) return;
  const int j = c_.n - 2;
  for (int i = 0; i < count_; ++i) {
    const int idx = j * count_ + i;
    work_committed_ -= jointLength(j) * law_.elasticEnergy(moment(k, j, i));
    upper_[idx] = law_.initialUpper();
    line_[idx] = line_committed_[idx] = TwoLineLaw::kElastic;
    x_committed_[idx] = 0.0;
  }
}

void RotationalSpring::retireFront(int k) {
  if (!plastic_) return;
  const std::size_t drop = static_cast<std::size_t>(k) * count_;
  const std::size_t used = static_cast<std::size_t>(c_.n - 1) * count_;
  dropFront(upper_, drop, used, law_.initialUpper());
  dropFront(x_committed_, drop, used, 0.0);
  dropFront(line_, drop, used, static_cast<signed char>(TwoLineLaw::kElastic));
  dropFront(line_committed_, drop, used, static_cast<signed char>(TwoLineLaw::kElastic));
}

double RotationalSpring::elasticEnergy(const WireKinematics& k) const {
  double e = 0.0;
  for (int j = 0; j + 1 < c_.n; ++j) {
    for (int i = 0; i < count_; ++i) e += jointLength(j) * law_.elasticEnergy(moment(k, j, i));
  }
  return e;
}

double RotationalSpring::plasticWork(const WireKinematics& k) const {
  return plastic_ ? work_committed_ - elasticEnergy(k) : 0.0;
}

void RotationalSpring::appendHistory(std::vector<double>& out) const {
  if (!plastic_) return;
  const std::size_t used = static_cast<std::size_t>(c_.n - 1) * count_;
  out.insert(out.end(), upper_.begin(), upper_.begin() + used);
  out.insert(out.end(), x_committed_.begin(), x_committed_.begin() + used);
  out.push_back(work_committed_);
  // The implicit steps' lines: a continued run starts from the same ones.
  out.insert(out.end(), line_committed_.begin(), line_committed_.begin() + used);
}

void RotationalSpring::restoreHistory(HistoryReader& in) {
  if (!plastic_) return;
  const std::size_t used = static_cast<std::size_t>(c_.n - 1) * count_;
  for (std::size_t i = 0; i < used; ++i) upper_[i] = in.next();
  for (std::size_t i = 0; i < used; ++i) x_committed_[i] = in.next();
  work_committed_ = in.next();
  std::fill(line_committed_.begin(), line_committed_.end(), TwoLineLaw::kElastic);
  const std::string what = std::string(name_) + " hysteresis line";
  for (std::size_t i = 0; i < used; ++i) {
    line_committed_[i] = static_cast<signed char>(
        in.nextInteger(TwoLineLaw::kLower, TwoLineLaw::kUpper, what.c_str()));
  }
  line_ = line_committed_;
}

}  // namespace cws
