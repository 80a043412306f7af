#include "coil_winding_sim/core/machine/rotating_core.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "coil_winding_sim/core/base/quaternion.hpp"

namespace cws {

RotatingCore::RotatingCore(const CoreParams& p, double omega_command)
    : origin_world_(p.position_world),
      axis_world_(p.axis_world.normalized()),
      alpha_max_(p.max_angular_acceleration),
      start_at_speed_(p.start_at_speed),
      alpha_(0.0),
      omega_cmd_(omega_command) {
  alpha_ = rampAcceleration();
  // Core z is the axis; x, y as the quaternion frame with zeta = axis.
  const quat::Vec4 q = quat::fromZetaDirection(axis_world_);
  rot_world_core0_.col(0) = quat::xi(q);
  rot_world_core0_.col(1) = quat::eta(q);
  rot_world_core0_.col(2) = quat::zeta(q);
  q_world_core0_ = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
}

Eigen::Quaterniond RotatingCore::quaternionWorldCore(double t) const {
  const double half = 0.5 * angle(t);
  const Eigen::Vector3d v = std::sin(half) * axis_world_;
  return Eigen::Quaterniond(std::cos(half), v.x(), v.y(), v.z()) * q_world_core0_;
}

double RotatingCore::rampAcceleration() const {
  // The instant start lasts from t = 0 at rest to its first commit.
  if (start_at_speed_ && t0_ == 0.0 && omega0_ == 0.0) {
    return std::max(alpha_max_, std::abs(omega_cmd_) / kInstantRamp_s);
  }
  return alpha_max_;
}

double RotatingCore::rampEnd() const {
  const double dw = omega_cmd_ - omega0_;
  if (dw == 0.0) return std::numeric_limits<double>::infinity();
  return t0_ + std::abs(dw) / alpha_;
}

double RotatingCore::omega(double t) const {
  const double dt = t - t0_;
  const double dw = omega_cmd_ - omega0_;
  const double t_ramp = std::abs(dw) / alpha_;
  if (dt >= t_ramp) return omega_cmd_;
  return omega0_ + std::copysign(alpha_, dw) * dt;
}

double RotatingCore::angularAcceleration(double t) const {
  const double dw = omega_cmd_ - omega0_;
  if (t - t0_ >= std::abs(dw) / alpha_) return 0.0;
  return std::copysign(alpha_, dw);
}

double RotatingCore::angle(double t) const {
  const double dt = t - t0_;
  const double dw = omega_cmd_ - omega0_;
  const double t_ramp = std::abs(dw) / alpha_;
  if (dt <= t_ramp) return angle0_ + omega0_ * dt + 0.5 * std::copysign(alpha_, dw) * dt * dt;
  // Ramp to the command, then constant speed.
  return angle0_ + 0.5 * (omega0_ + omega_cmd_) * t_ramp + omega_cmd_ * (dt - t_ramp);
}

void RotatingCore::commit(double t) {
  angle0_ = angle(t);
  omega0_ = omega(t);
  t0_ = t;
  if (omega0_ == omega_cmd_) alpha_ = alpha_max_;
}

Eigen::Matrix3d RotatingCore::rotationWorldCore(double t) const {
  return Eigen::AngleAxisd(angle(t), axis_world_).toRotationMatrix() * rot_world_core0_;
}

Eigen::Vector3d RotatingCore::pointWorld(double t, const Eigen::Vector3d& p_core) const {
  return origin_world_ + rotationWorldCore(t) * p_core;
}

Eigen::Vector3d RotatingCore::pointCore(double t, const Eigen::Vector3d& p_world) const {
  return rotationWorldCore(t).transpose() * (p_world - origin_world_);
}

Eigen::Vector3d RotatingCore::velocityWorld(double t, const Eigen::Vector3d& p_world) const {
  return omega(t) * axis_world_.cross(p_world - origin_world_);
}

Eigen::Vector3d RotatingCore::accelerationWorld(double t, const Eigen::Vector3d& p_world) const {
  const Eigen::Vector3d r = p_world - origin_world_;
  const double w = omega(t);
  return angularAcceleration(t) * axis_world_.cross(r) +
         w * w * axis_world_.cross(axis_world_.cross(r));
}

}  // namespace cws
