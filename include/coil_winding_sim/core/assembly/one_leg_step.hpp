// One step of a one-leg scheme (backward Euler, BDF2) as the time stepper
// hands it to a formulation, and the velocity that scheme gives the core's
// material.
//
// The scheme's velocity of a point is v = alpha (x - x_hat), with x_hat the
// combination sum_j w_j x(t_j) of its committed past. A point the core
// carries is at o + R(theta_j - theta_1) (p - o) at t_j if it is at p at the
// step's end t_1, so its scheme velocity is linear in p:
//   u(p) = alpha (I - M) (p - o),  M = sum_j w_j R(theta_j - theta_1).
// This, not the tangent omega a x (p - o), is the velocity a wire point
// resting on the core has in the scheme (for backward Euler the chord of
// the arc: the two differ by omega^2 r h / 2 along the radius). Friction
// compares the wire's velocity with it, so a point at rest on the core is at
// rest in the friction law too (docs/MODEL.md, "Implicit integration").
// The work the core does is booked with the exact tangent velocity: the
// chord's radial part would book work of the normal force that no motion
// of the core does.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "coil_winding_sim/core/base/quaternion.hpp"

namespace cws {

struct OneLegStep {
  static constexpr int kMaxPast = 2;
  double t1 = 0.0;     // the step's end [s]
  double alpha = 0.0;  // d v / d x [1/s]
  // x_hat = sum_j w[j] x(t_past[j]) over the committed past (weights sum
  // to 1).
  int past = 1;
  double t_past[kMaxPast] = {0.0, 0.0};  // [s]
  double w_past[kMaxPast] = {1.0, 0.0};
};

// The scheme velocity of the core's material (see above).
struct CarriedRate {
  Eigen::Matrix3d g_world = Eigen::Matrix3d::Zero();  // alpha (I - M) [1/s]
  double omega_exact = 0.0;                           // the core's angular velocity at t1 [rad/s]
  Eigen::Vector3d origin_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_world = Eigen::Vector3d::UnitZ();  // the core axis
  // x_hat of a frame the core carries: Q q (quaternions, scalar first).
  Eigen::Quaterniond q_past = Eigen::Quaterniond::Identity();
  double alpha = 0.0;  // 0: the exact rates (tangent velocity)

  // [m/s] of the core material at p_world.
  Eigen::Vector3d velocity(const Eigen::Vector3d& p_world) const {
    return g_world * (p_world - origin_world);
  }
  // [m/s] the exact velocity of the core material at p_world.
  Eigen::Vector3d exactVelocity(const Eigen::Vector3d& p_world) const {
    return omega_exact * axis_world.cross(p_world - origin_world);
  }

  // The exact rates of a core turning at omega [rad/s] about axis_world
  // (before a run's first step, when there is no scheme yet).
  static CarriedRate tangent(const Eigen::Vector3d& origin_world, const Eigen::Vector3d& axis_world,
                             double omega) {
    CarriedRate c;
    c.origin_world = origin_world;
    c.axis_world = axis_world;
    c.g_world = omega * quat::skew(axis_world);
    c.omega_exact = omega;
    return c;
  }

  // The scheme's: the core turned by theta_past[j] - theta1 [rad] about
  // axis_world at the past times of `step`, turning at omega1 [rad/s] at
  // its end.
  static CarriedRate scheme(const OneLegStep& step, const Eigen::Vector3d& origin_world,
                            const Eigen::Vector3d& axis_world, double theta1, double omega1,
                            const double* theta_past) {
    CarriedRate c;
    c.omega_exact = omega1;
    c.origin_world = origin_world;
    c.axis_world = axis_world;
    c.alpha = step.alpha;
    Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
    Eigen::Vector4d q = Eigen::Vector4d::Zero();  // w, x, y, z
    for (int j = 0; j < step.past; ++j) {
      const double turn = theta_past[j] - theta1;
      m += step.w_past[j] * Eigen::AngleAxisd(turn, axis_world).toRotationMatrix();
      const double s = std::sin(0.5 * turn);
      q += step.w_past[j] * Eigen::Vector4d(std::cos(0.5 * turn), s * axis_world.x(),
                                            s * axis_world.y(), s * axis_world.z());
    }
    c.g_world = step.alpha * (Eigen::Matrix3d::Identity() - m);
    c.q_past = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);  // not unit: a combination
    return c;
  }

  // The scheme rate of a frame q (scalar first) the core carries, or the
  // exact one omega_world x for the tangent rate.
  Eigen::Vector4d quaternionRate(const Eigen::Vector4d& q, const Eigen::Vector4d& qd_exact) const {
    if (alpha == 0.0) return qd_exact;
    const Eigen::Quaterniond qq(q[0], q[1], q[2], q[3]);
    const Eigen::Quaterniond hat = q_past * qq;
    return alpha * (q - Eigen::Vector4d(hat.w(), hat.x(), hat.y(), hat.z()));
  }
};

// The core's angle at the last two committed times a formulation loaded,
// for the scheme's past (RotatingCore::angle extrapolates the present ramp
// backwards, which is wrong across a change of the command).
class CoreAngleHistory {
 public:
  // At a committed time t [s] with the core at angle [rad]. A time before
  // the last one (a restored snapshot, a reset) starts the history anew.
  void record(double t, double angle) {
    if (count_ > 0 && t == t_[0]) return;
    if (count_ > 0 && t < t_[0]) count_ = 0;
    t_[1] = t_[0];
    angle_[1] = angle_[0];
    t_[0] = t;
    angle_[0] = angle;
    if (count_ < 2) ++count_;
  }
  // The recorded angle at t, or `fallback` where t was not recorded.
  double at(double t, double fallback) const {
    for (int j = 0; j < count_; ++j) {
      if (std::abs(t - t_[j]) <= 1e-12 * std::max(1.0, std::abs(t))) return angle_[j];
    }
    return fallback;
  }

 private:
  int count_ = 0;
  double t_[2] = {0.0, 0.0}, angle_[2] = {0.0, 0.0};
};

class RotatingCore;

// The carried rate of each step: the scheme's for a trial step, and the
// accepted step's for the committed state (its velocities come from that
// scheme). Without a core, every rate is zero.
class CarriedMotion {
 public:
  explicit CarriedMotion(const RotatingCore* core) : core_(core) {}
  // The committed state at t0 [s]: the rate its velocities have (the exact
  // one before the first accepted step, and after a restore).
  const CarriedRate& load(double t0);
  // The rate of a trial step.
  const CarriedRate& trial(const OneLegStep& step);
  // The last trial's step was accepted.
  void accept() {
    accepted_ = trial_;
    t_accepted_ = t_trial_;
    have_accepted_ = true;
  }

 private:
  const RotatingCore* core_;
  CoreAngleHistory angles_;
  CarriedRate trial_, accepted_, loaded_;
  bool have_accepted_ = false;
  double t_accepted_ = 0.0, t_trial_ = 0.0;
};

}  // namespace cws
