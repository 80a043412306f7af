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
  double kappa = 0.0;  // d a / d v [1/s]
  // x_hat = sum_j w[j] x(t_past[j]) over the committed past (weights sum
  // to 1), plus w_rate v(t_past[0]) + w_acc a(t_past[0]) (generalized-alpha:
  // the start's velocity and pseudo-acceleration).
  int past = 1;
  double t_past[kMaxPast] = {0.0, 0.0};  // [s]
  double w_past[kMaxPast] = {1.0, 0.0};
  double w_rate = 0.0;  // [s]
  double w_acc = 0.0;   // [s^2]
  // The weight of the last step's power in this step's work and
  // dissipation (generalized-alpha: alpha_f; 0: this step's end power).
  double w_power_prev = 0.0;
};

// The work and dissipation a Newton step books: h times its power at the
// point where the scheme balances the forces. Generalized-alpha blends
// the end forces with the last step's as (1 - alpha_f) F1 + alpha_f F0, so
// its power is blended alike; booked at the end power alone, a force that
// rings from step to step (a clamp jerked at t = 0) booked up to 1.7 % of
// the work as energy created (docs/history/2026-11-27-dashpot-energy-booking.md).
class PowerBooking {
 public:
  // Adds the step's work and dissipation [J] to `work` and `dissipated`
  // from its end powers [W] (the last accepted step's are kept).
  void book(const OneLegStep& step, double h, double work_power, double dissipated_power,
            double& work, double& dissipated) {
    const double w = step.w_power_prev;
    work += h * ((1.0 - w) * work_power + w * last_[0]);
    dissipated += h * ((1.0 - w) * dissipated_power + w * last_[1]);
    last_[0] = work_power;
    last_[1] = dissipated_power;
  }

 private:
  double last_[2] = {0.0, 0.0};  // the last accepted step's end powers [W]
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
  // its end and omega0 [rad/s] at its start (for the start's velocity and
  // acceleration terms: omega0 a x r and -omega0^2 r_perp, the core's
  // angular acceleration left out).
  static CarriedRate scheme(const OneLegStep& step, const Eigen::Vector3d& origin_world,
                            const Eigen::Vector3d& axis_world, double theta1, double omega1,
                            const double* theta_past, double omega0 = 0.0) {
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
    if (step.w_rate != 0.0 || step.w_acc != 0.0) {
      const Eigen::Matrix3d cross = quat::skew(axis_world);
      const double turn = theta_past[0] - theta1;
      m += (step.w_rate * omega0 * cross + step.w_acc * omega0 * omega0 * cross * cross) *
           Eigen::AngleAxisd(turn, axis_world).toRotationMatrix();
      // A carried frame: q(t0) = Q0 q, dq/dt = (omega0 / 2) (0, a) Q0 q,
      // d2q/dt2 = -(omega0^2 / 4) Q0 q.
      const double s0 = std::sin(0.5 * turn);
      const Eigen::Quaterniond q0(std::cos(0.5 * turn), s0 * axis_world.x(), s0 * axis_world.y(),
                                  s0 * axis_world.z());
      const Eigen::Quaterniond aq0 =
          Eigen::Quaterniond(0.0, axis_world.x(), axis_world.y(), axis_world.z()) * q0;
      q += -step.w_acc * 0.25 * omega0 * omega0 * Eigen::Vector4d(q0.w(), q0.x(), q0.y(), q0.z()) +
           step.w_rate * 0.5 * omega0 * Eigen::Vector4d(aq0.w(), aq0.x(), aq0.y(), aq0.z());
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
