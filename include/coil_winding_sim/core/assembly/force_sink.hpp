// One force sink for every integrator: an effect written on it states its
// law once, on world positions, velocities and frame angular velocities,
// and each integrator's sink maps what it adds to its own unknowns:
//   ExplicitSink  the explicit model's generalized forces (WireForces),
//   PlanarSink    the planar Newton system (the plane's two coordinates per
//                 point; a frame turns with its segment),
//   SpatialSink   the 3-D Newton system (positions and quaternions).
// The three share one set of calls (a law is a template over the sink):
//   t(), first(), n()          time [s] and the integrated points first..n-1
//   jacobian(i)                whether point i's derivatives are wanted
//   p(i), v(i), omega(i)       position [m], velocity [m/s] and the angular
//                              velocity of frame i [rad/s], world frame
//   addPointForce(i, f, power) force on point i [N], booked as `power` says
//   addPointStiffness(i, K)    d f_i / d p_i [N/m]
//   addPointDamping(i, D)      d f_i / d v_i [N s/m]
//   addFollowerForce(i, f, power)
//                              a force f [N] on point i along frame i's
//                              zeta axis, turning with the frame (the
//                              supply's pull), with its derivative
//   addFrameMoment(i, m, power[, dm_domega])
//                              moment on frame i [N m], and its derivative in
//                              the frame's angular velocity [N m s] where it
//                              has one
// A law between two points far apart along the wire (free-wire contact,
// in the explicit and 3-D sinks):
//   jacobian()                 whether this evaluation wants derivatives
//   flagsFrozen()              contact flags stay as the step's start set
//                              them (Newton: EffectHistory::beginStep and
//                              recheck), else decided at every evaluation
//   velocityGain()             d v / d p of the step, alpha [1/s] (v =
//                              alpha (p - p_hat); 0 in explicit steps)
//   addPointForce(i, f, f_dissipative)
//                              force f [N] on point i, f_dissipative of it
//                              booked as dissipation, the rest conservative
//   addPairCoupling(a, m, t, df)
//                              d f_a / d delta [N/m] of point a against
//                              segment m at t along it (delta = p_a - the
//                              segment's point), its reaction on the
//                              segment's ends (a coupling outside the band)
// A law at the joints between neighbouring frames j and j+1 (j from
// first-1; rotational springs):
//   darboux(j, lambda)         the joint's curvature-twist vector Omega in
//                              frame j [1/m], lambda the wire it stands for
//                              [m]; in the plane kappa n_material
//   jointComponent(c)          whether component c of Omega moves here (the
//                              plane moves only those along its normal)
//   addJointMoment(j, lambda, m, dm)
//                              the moment m(Omega) [N m] on the joint, with
//                              its diagonal tangent dm/dOmega [N m^2]; after
//                              darboux(j, lambda) of the same joint
// A law on the points alone (a spring along a segment) may instead use the
// formulation's own coordinates, the plane's two in a planar scene, else
// the world's three:
//   kDim, Vec, Mat             their size and types
//   segment(j)                 p_j+1 - p_j [m]
//   addForce(i, f)             an internal force [N] (booked by no power)
//   addStiffness(i, j, K)      d f_i / d x_j [N/m]
//   returnMapping()            the laws' lines decided at every evaluation
//                              (explicit steps; a Newton solve's last
//                              rounds), else frozen within the solve
// A law against the moving core (contact, contact.hpp), on every sink:
//   kFlagsFrozen               as flagsFrozen(), known when compiled
//   carried()                  Newton sinks: the scheme velocity of the
//                              core's material (one_leg_step.hpp)
//   dt()                       Newton sinks: the step's length [s]
//   slideAxis()                the one axis a sliding point turns about
//                              (the plane's normal), or nullptr (3-D)
//   addPointForce(i, f, f_dissipative)
//                              as above, in the plane too
//   addDissipation(i, f_dissipative)
//                              a part of a force already added, booked as
//                              dissipation [N]
//   addPower(dissipated, external)
//                              power the law books itself [W]: dissipated,
//                              and done by the moving surface
// SinkEffect<Law> (force_effect.hpp) turns a class with `template <class
// Sink> void law(Sink&) const` into a ForceEffect of all three integrators.
#pragma once

#include <Eigen/Core>

#include "coil_winding_sim/core/assembly/planar_assembly.hpp"
#include "coil_winding_sim/core/assembly/spatial_assembly.hpp"
#include "coil_winding_sim/core/base/quaternion.hpp"
#include "coil_winding_sim/core/base/wire_types.hpp"

namespace cws {

// How the energy balance books a force: as work an applied load does, or
// as dissipation (friction, damping).
enum class ForcePower { kApplied, kDissipative };

class ExplicitSink {
 public:
  ExplicitSink(double t, const WireConstants& c, const WireKinematics& k, WireForces& f)
      : t_(t), c_(c), k_(k), f_(f) {}
  double t() const { return t_; }
  int first() const { return c_.first; }
  int n() const { return c_.n; }
  bool jacobian(int) const { return false; }
  Eigen::Vector3d p(int i) const { return k_.p_world.col(i); }
  Eigen::Vector3d v(int i) const { return k_.v_world.col(i); }
  Eigen::Vector3d omega(int i) const { return 2.0 * quat::E(k_.q.col(i)) * k_.qd.col(i); }

  static constexpr int kDim = 3;
  using Vec = Eigen::Vector3d;
  using Mat = Eigen::Matrix3d;
  Vec segment(int j) const { return k_.p_world.col(j + 1) - k_.p_world.col(j); }
  void addForce(int i, const Vec& f) { f_.f_world.col(i) += f; }
  void addStiffness(int, int, const Mat&) {}
  bool returnMapping() const { return true; }

  void addPointForce(int i, const Eigen::Vector3d& f, ForcePower power) {
    f_.f_world.col(i) += f;
    (power == ForcePower::kApplied ? f_.f_work_world : f_.f_dissipative_world).col(i) += f;
  }
  void addPointStiffness(int, const Eigen::Matrix3d&) {}
  void addPointDamping(int, const Eigen::Matrix3d&) {}
  void addFollowerForce(int i, double f, ForcePower power) {
    addPointForce(i, f * quat::zeta(k_.q.col(i)), power);
  }

  bool jacobian() const { return false; }
  static constexpr bool kFlagsFrozen = false;
  bool flagsFrozen() const { return kFlagsFrozen; }
  double velocityGain() const { return 0.0; }
  void addPointForce(int i, const Eigen::Vector3d& f, const Eigen::Vector3d& f_dissipative) {
    f_.f_world.col(i) += f;
    f_.f_dissipative_world.col(i) += f_dissipative;
  }
  void addDissipation(int i, const Eigen::Vector3d& f_dissipative) {
    f_.f_dissipative_world.col(i) += f_dissipative;
  }
  const Eigen::Vector3d* slideAxis() const { return nullptr; }
  void addPower(double dissipated, double external) {
    f_.power_dissipated += dissipated;
    f_.power_external += external;
  }
  void addPairCoupling(int, int, double, const Eigen::Matrix3d&) {}

  // Omega = (2 / lambda) G(q_j) q_j+1; the moment's generalized forces
  // -lambda m . dOmega/dq: 2 G(q_j+1)^T m on q_j, -2 G(q_j)^T m on q_j+1
  // (lambda cancels).
  Eigen::Vector3d darboux(int j, double lambda) const {
    return (2.0 / lambda) * quat::gTimes(k_.q.col(j), k_.q.col(j + 1));
  }
  bool jointComponent(int) const { return true; }
  void addJointMoment(int j, double, const Eigen::Vector3d& m, const Eigen::Vector3d&) {
    f_.f_q.col(j) += 2.0 * quat::G(k_.q.col(j + 1)).transpose() * m;
    f_.f_q.col(j + 1) -= 2.0 * quat::G(k_.q.col(j)).transpose() * m;
  }

  // A moment m as the generalized force 2 E(q)^T m on the quaternion.
  void addFrameMoment(int i, const Eigen::Vector3d& m, ForcePower power, const Eigen::Matrix3d&) {
    addFrameMoment(i, m, power);
  }
  void addFrameMoment(int i, const Eigen::Vector3d& m, ForcePower power) {
    const Eigen::Vector4d fq = 2.0 * quat::E(k_.q.col(i)).transpose() * m;
    f_.f_q.col(i) += fq;
    (power == ForcePower::kApplied ? f_.fq_work : f_.fq_dissipative).col(i) += fq;
  }

 private:
  double t_;
  const WireConstants& c_;
  const WireKinematics& k_;
  WireForces& f_;
};

class PlanarSink {
 public:
  PlanarSink(const PlanarState& s, PlanarAssembly& a) : s_(s), a_(a) {
    e_.col(0) = s.plane.e1_world;
    e_.col(1) = s.plane.e2_world;
  }
  double t() const { return s_.t; }
  int first() const { return s_.first; }
  int n() const { return s_.n; }
  bool jacobian(int i) const { return a_.wantsJacobianAt(i); }
  Eigen::Vector3d p(int i) const { return s_.plane.toWorld(s_.x.col(i)); }
  Eigen::Vector3d v(int i) const { return s_.plane.vectorToWorld(s_.v.col(i)); }
  // Frame i >= 1 turns with segment i-1 about the plane normal.
  Eigen::Vector3d omega(int i) const {
    const Eigen::Vector2d g = planar::angleGradient(s_.segment(i - 1));
    return g.dot(s_.v.col(i) - s_.v.col(i - 1)) * s_.plane.n_world;
  }

  static constexpr int kDim = 2;
  using Vec = Eigen::Vector2d;
  using Mat = Eigen::Matrix2d;
  Vec segment(int j) const { return s_.segment(j); }
  void addForce(int i, const Vec& f) { a_.addForce(i, f); }
  void addStiffness(int i, int j, const Mat& k) { a_.addStiffness(i, j, k); }
  bool returnMapping() const { return s_.return_mapping; }

  static constexpr bool kFlagsFrozen = true;
  bool flagsFrozen() const { return kFlagsFrozen; }
  const CarriedRate& carried() const { return s_.carried; }
  double dt() const { return s_.dt; }
  const Eigen::Vector3d* slideAxis() const { return &s_.plane.n_world; }
  void addPointForce(int i, const Eigen::Vector3d& f_world,
                     const Eigen::Vector3d& f_dissipative_world) {
    a_.addForce(i, s_.plane.vectorToPlane(f_world));
    a_.f_dissipative.col(i) += s_.plane.vectorToPlane(f_dissipative_world);
  }
  void addDissipation(int i, const Eigen::Vector3d& f_dissipative_world) {
    a_.f_dissipative.col(i) += s_.plane.vectorToPlane(f_dissipative_world);
  }
  void addPower(double dissipated, double external) {
    a_.power_dissipated += dissipated;
    a_.power_external += external;
  }

  // World to plane: f = E^T f_world, K = E^T K_world E (nothing along the
  // normal moves a planar wire).
  void addPointForce(int i, const Eigen::Vector3d& f_world, ForcePower power) {
    const Eigen::Vector2d f = s_.plane.vectorToPlane(f_world);
    a_.addForce(i, f);
    (power == ForcePower::kApplied ? a_.f_work : a_.f_dissipative).col(i) += f;
  }
  void addPointStiffness(int i, const Eigen::Matrix3d& k) {
    a_.addStiffness(i, i, e_.transpose() * k * e_);
  }
  void addPointDamping(int i, const Eigen::Matrix3d& d) {
    a_.addDamping(i, i, e_.transpose() * d * e_);
  }
  // Frame i's zeta is segment i-1's direction u: d(f u)/dx_i = f (I - u
  // u^T) / |d|, and the opposite on point i-1.
  void addFollowerForce(int i, double f, ForcePower power) {
    const Eigen::Vector2d d = s_.segment(i - 1);
    const double len = d.norm();
    const Eigen::Vector2d u = d / len;
    a_.addForce(i, f * u);
    (power == ForcePower::kApplied ? a_.f_work : a_.f_dissipative).col(i) += f * u;
    const Eigen::Matrix2d k = (f / len) * (Eigen::Matrix2d::Identity() - u * u.transpose());
    a_.addStiffness(i, i, k);
    a_.addStiffness(i, i - 1, -k);
  }

  // Joint j turns by dphi about n from frame j to frame j+1 (segment j;
  // frame first-1 is the prescribed one, a unit tangent with no unknowns):
  // Omega = (2 / lambda) sin(dphi / 2) n_material. Each segment's geometry
  // is worked out once and serves both joints it belongs to.
  Eigen::Vector3d darboux(int j, double lambda) {
    if (j != joint_) {
      if (j == s_.first - 1) {
        ga_.setPrescribed(s_.boundary_tangent);
      } else if (j == joint_ + 1) {
        ga_ = gb_;
      } else {
        ga_.set(s_.segment(j - 1), a_.wantsJacobian());
      }
      gb_.set(s_.segment(j), a_.wantsJacobian());
      joint_ = j;
    }
    kappa_ = planar::jointCurvature(ga_, gb_, lambda, sin_half_, cos_half_);
    return kappa_ * s_.n_material;
  }
  bool jointComponent(int c) const { return s_.n_material[c] != 0.0; }
  void addJointMoment(int j, double lambda, const Eigen::Vector3d& m_vec,
                      const Eigen::Vector3d& dm_vec);
  // A moment about the normal on frame i, as forces m g on point i and -m g
  // on point i-1 (g the gradient of the angle of segment i-1); its
  // derivatives through omega = g . (v_i - v_i-1) and through g.
  void addFrameMoment(int i, const Eigen::Vector3d& m_world, ForcePower power) {
    frameMoment(i, m_world, power, nullptr);
  }
  void addFrameMoment(int i, const Eigen::Vector3d& m_world, ForcePower power,
                      const Eigen::Matrix3d& dm_domega) {
    frameMoment(i, m_world, power, &dm_domega);
  }

 private:
  void frameMoment(int i, const Eigen::Vector3d& m_world, ForcePower power,
                   const Eigen::Matrix3d* dm_domega) {
    const Eigen::Vector2d d = s_.segment(i - 1);
    const Eigen::Vector2d g = planar::angleGradient(d);
    const double m = m_world.dot(s_.plane.n_world);
    a_.addForce(i, m * g);
    a_.addForce(i - 1, -m * g);
    Eigen::Matrix2Xd& booked = power == ForcePower::kApplied ? a_.f_work : a_.f_dissipative;
    booked.col(i) += m * g;
    if (i - 1 >= s_.first) booked.col(i - 1) -= m * g;
    if (!a_.wantsJacobianAt(i)) return;
    const Eigen::Matrix2d hs = planar::angleHessian(d);
    Eigen::Matrix2d dx = m * hs, dv = Eigen::Matrix2d::Zero();
    if (dm_domega) {
      const double dm = s_.plane.n_world.dot(*dm_domega * s_.plane.n_world);
      const Eigen::Vector2d w = s_.v.col(i) - s_.v.col(i - 1);
      dv = dm * g * g.transpose();
      dx += dm * g * (hs * w).transpose();
    }
    const int pts[2] = {i - 1, i};
    const double sgn[2] = {-1.0, 1.0};
    for (int r = 0; r < 2; ++r) {
      for (int c = 0; c < 2; ++c) {
        if (dm_domega) a_.addDamping(pts[r], pts[c], sgn[r] * sgn[c] * dv);
        a_.addStiffness(pts[r], pts[c], sgn[r] * sgn[c] * dx);
      }
    }
  }

  const PlanarState& s_;
  PlanarAssembly& a_;
  Eigen::Matrix<double, 3, 2> e_;
  // The joint darboux() last worked out: its segments' geometry, curvature
  // [1/m] and half turn.
  int joint_ = -2;
  planar::SegmentGeometry ga_, gb_;
  double kappa_ = 0.0, sin_half_ = 0.0, cos_half_ = 1.0;
};

class SpatialSink {
 public:
  SpatialSink(const SpatialState& s, SpatialAssembly& a) : s_(s), a_(a) {}
  double t() const { return s_.t; }
  int first() const { return s_.first; }
  int n() const { return s_.n; }
  bool jacobian(int i) const { return a_.wantsJacobianAt(i); }
  Eigen::Vector3d p(int i) const { return s_.p.col(i); }
  Eigen::Vector3d v(int i) const { return s_.v.col(i); }
  Eigen::Vector3d omega(int i) const { return 2.0 * quat::E(s_.q.col(i)) * s_.qd.col(i); }

  static constexpr int kDim = 3;
  using Vec = Eigen::Vector3d;
  using Mat = Eigen::Matrix3d;
  Vec segment(int j) const { return s_.segment(j); }
  void addForce(int i, const Vec& f) { a_.addForce(i, f); }
  void addStiffness(int i, int j, const Mat& k) { a_.addStiffnessPP(i, j, k); }
  bool returnMapping() const { return s_.return_mapping; }
  const CarriedRate& carried() const { return s_.carried; }
  double dt() const { return s_.dt; }
  const Eigen::Vector3d* slideAxis() const { return nullptr; }

  void addPointForce(int i, const Eigen::Vector3d& f, ForcePower power) {
    a_.addForce(i, f);
    (power == ForcePower::kApplied ? a_.f_work : a_.f_dissipative).col(i) += f;
  }
  void addPointStiffness(int i, const Eigen::Matrix3d& k) { a_.addStiffnessPP(i, i, k); }
  void addPointDamping(int i, const Eigen::Matrix3d& d) { a_.addDampingPP(i, i, d); }
  void addFollowerForce(int i, double f, ForcePower power) {
    const quat::Vec4 q = s_.q.col(i);
    addPointForce(i, f * quat::zeta(q), power);
    if (a_.wantsJacobian()) a_.addStiffnessPQ(i, i, f * quat::zetaJacobian(q));
  }

  bool jacobian() const { return a_.wantsJacobian(); }
  static constexpr bool kFlagsFrozen = true;
  bool flagsFrozen() const { return kFlagsFrozen; }
  double velocityGain() const { return s_.alpha; }
  void addPointForce(int i, const Eigen::Vector3d& f, const Eigen::Vector3d& f_dissipative) {
    a_.addForce(i, f);
    a_.f_dissipative.col(i) += f_dissipative;
  }
  void addDissipation(int i, const Eigen::Vector3d& f_dissipative) {
    a_.f_dissipative.col(i) += f_dissipative;
  }
  void addPower(double dissipated, double external) {
    a_.power_dissipated += dissipated;
    a_.power_external += external;
  }
  // (The matrix holds -dF/dx: the pair's block in delta is -df.)
  void addPairCoupling(int a, int m, double t, const Eigen::Matrix3d& df) {
    if (a_.wantsJacobian()) a_.addPairCoupling(a, m, t, -df);
  }

  // As the explicit sink's; the derivatives of Omega are -(2 / lambda)
  // G(q_j+1) and (2 / lambda) G(q_j), and G(q)^T m is linear in q.
  Eigen::Vector3d darboux(int j, double lambda) const {
    return (2.0 / lambda) * quat::gTimes(s_.q.col(j), s_.q.col(j + 1));
  }
  bool jointComponent(int) const { return true; }
  void addJointMoment(int j, double lambda, const Eigen::Vector3d& m, const Eigen::Vector3d& dm);
  // A moment m as the generalized force f_q = 2 E(q)^T m; with omega =
  // 2 E(q) qd, d f_q / d qd = 4 E^T D E and d f_q / d q column k =
  // 2 E(e_k)^T m + 4 E^T D E(e_k) qd (E is linear in q), D = d m / d omega.
  void addFrameMoment(int i, const Eigen::Vector3d& m, ForcePower power) {
    frameMoment(i, m, power, nullptr);
  }
  void addFrameMoment(int i, const Eigen::Vector3d& m, ForcePower power,
                      const Eigen::Matrix3d& dm_domega) {
    frameMoment(i, m, power, &dm_domega);
  }

 private:
  void frameMoment(int i, const Eigen::Vector3d& m, ForcePower power,
                   const Eigen::Matrix3d* dm_domega) {
    const quat::Vec4 q = s_.q.col(i), qd = s_.qd.col(i);
    const quat::Mat34 e = quat::E(q);
    const Eigen::Vector4d fq = 2.0 * e.transpose() * m;
    a_.addQForce(i, fq);
    (power == ForcePower::kApplied ? a_.fq_work : a_.fq_dissipative).col(i) += fq;
    if (!a_.wantsJacobianAt(i)) return;
    Eigen::Matrix4d dq;
    for (int k = 0; k < 4; ++k) {
      const quat::Mat34 ek = quat::E(quat::Vec4::Unit(k));
      dq.col(k) = 2.0 * ek.transpose() * m;
      if (dm_domega) dq.col(k) += 4.0 * e.transpose() * (*dm_domega * (ek * qd));
    }
    a_.addStiffnessQQ(i, i, dq);
    if (dm_domega) a_.addDampingQQ(i, i, 4.0 * e.transpose() * (*dm_domega * e));
  }

  const SpatialState& s_;
  SpatialAssembly& a_;
};

// (Forced inline: the plane's bending law calls it once per joint, and
// through memory m_vec and dm_vec cost about 1 % of a planar run, measured.)
inline __attribute__((always_inline)) void PlanarSink::addJointMoment(
    int j, double lambda, const Eigen::Vector3d& m_vec, const Eigen::Vector3d& dm_vec) {
  // The moment about n, m = sum_c m_c n_material[c], and its tangent in
  // kappa, sum_c dm_c n_material[c]^2 (the components the plane moves).
  double m = 0.0, dm = 0.0;
  for (int c = 0; c < 3; ++c) {
    const double w = s_.n_material[c];
    if (w == 0.0) continue;
    m += w * m_vec[c];
    dm += w * w * dm_vec[c];
  }
  // Generalized force on dphi: Q = -d(lambda W)/d dphi = -m cos(dphi / 2);
  // d dphi / dx is gb on point j+1, -gb - ga on j and ga on j-1.
  const bool prescribed = j == s_.first - 1;
  const double q = -m * cos_half_;
  const Eigen::Vector2d g_mid = -gb_.gradient - ga_.gradient;
  a_.addForce(j + 1, q * gb_.gradient);
  a_.addForce(j, q * g_mid);
  if (prescribed) {
    a_.addBoundaryTorque(-q);
  } else {
    a_.addForce(j - 1, q * ga_.gradient);
  }
  if (!a_.wantsJacobian()) return;
  // dq g_r g_c^T + q d^2 dphi / dx_r dx_c over points j-1, j, j+1; dphi =
  // phi_b - phi_a, whose second derivatives are +-hb and +-ha.
  const double dq = -dm * cos_half_ * cos_half_ / lambda + 0.5 * m * sin_half_;
  const Eigen::Matrix2d qhb = q * gb_.hessian;
  const Eigen::Matrix2d k_bb = dq * gb_.gradient * gb_.gradient.transpose() + qhb;
  const Eigen::Matrix2d k_bm = dq * gb_.gradient * g_mid.transpose() - qhb;
  a_.addStiffness(j + 1, j + 1, k_bb);
  a_.addStiffness(j + 1, j, k_bm);
  a_.addStiffness(j, j + 1, k_bm.transpose());
  if (prescribed) {
    a_.addStiffness(j, j, dq * g_mid * g_mid.transpose() + qhb);
    return;
  }
  const Eigen::Matrix2d qha = q * ga_.hessian;
  const Eigen::Matrix2d k_ma = dq * g_mid * ga_.gradient.transpose() + qha;
  const Eigen::Matrix2d k_ba = dq * gb_.gradient * ga_.gradient.transpose();
  a_.addStiffness(j, j, dq * g_mid * g_mid.transpose() + qhb - qha);
  a_.addStiffness(j, j - 1, k_ma);
  a_.addStiffness(j - 1, j, k_ma.transpose());
  a_.addStiffness(j - 1, j - 1, dq * ga_.gradient * ga_.gradient.transpose() - qha);
  a_.addStiffness(j + 1, j - 1, k_ba);
  a_.addStiffness(j - 1, j + 1, k_ba.transpose());
}

}  // namespace cws
