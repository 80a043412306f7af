// The rigid core: turns about its axis at the commanded angular velocity,
// changing speed at most at max_angular_acceleration.
//
// Between commits the motion is an explicit function of time (constant
// acceleration up to the command, then constant speed), so trial stages of a
// step evaluate it without changing it; commit() moves the reference to an
// accepted time.
//
// A core that starts at speed (core.start_at_speed) is at rest at t = 0 and
// reaches its speed within kInstantRamp_s: the wire, at rest at t = 0, then
// follows the clamp's velocity jump through the constraint solve of one
// short step instead of lagging it (a jump of v at the clamp with no
// acceleration seen would leave the frames off their segments by about
// v / (e nu l)).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

class RotatingCore {
 public:
  static constexpr double kInstantRamp_s = 1.0e-9;

  // omega_command in [rad/s], positive counter-clockwise about the axis;
  // at rest at t = 0 (see above for p.start_at_speed).
  RotatingCore(const CoreParams& p, double omega_command);

  // New commanded speed [rad/s], effective from the last committed time,
  // reached at max_angular_acceleration.
  void setCommand(double omega_command) {
    omega_cmd_ = omega_command;
    alpha_ = alpha_max_;
  }
  double command() const { return omega_cmd_; }

  double omega(double t) const;                // [rad/s]
  double angle(double t) const;                // [rad], 0 at t = 0
  double angularAcceleration(double t) const;  // [rad/s^2]
  // Moves the reference state to time t (an accepted step).
  void commit(double t);
  // Time [s] the present speed change ends (the acceleration drops to 0), or
  // infinity at the commanded speed. Steps end there so that no step spans
  // the kink: a step over a short, steep ramp would miss the acceleration
  // and hand the wire a velocity jump the constraints cannot follow.
  double rampEnd() const;

  // Rotation of the core frame in the world frame at time t.
  Eigen::Matrix3d rotationWorldCore(double t) const;
  // The same as a quaternion, continuous in t (no sign jumps), so that frames
  // carried by the core stay in one hemisphere with the wire's frames.
  Eigen::Quaterniond quaternionWorldCore(double t) const;
  Eigen::Vector3d pointWorld(double t, const Eigen::Vector3d& p_core) const;
  Eigen::Vector3d pointCore(double t, const Eigen::Vector3d& p_world) const;
  // Velocity [m/s] of the core material at the world point p_world.
  Eigen::Vector3d velocityWorld(double t, const Eigen::Vector3d& p_world) const;
  // Acceleration [m/s^2] of the core material at the world point p_world.
  Eigen::Vector3d accelerationWorld(double t, const Eigen::Vector3d& p_world) const;

  // Reference state (t0, angle0, omega0, command) for snapshots.
  void exportState(double out[4]) const {
    out[0] = t0_;
    out[1] = angle0_;
    out[2] = omega0_;
    out[3] = omega_cmd_;
  }
  void restoreState(const double in[4]) {
    t0_ = in[0];
    angle0_ = in[1];
    omega0_ = in[2];
    omega_cmd_ = in[3];
    alpha_ = rampAcceleration();
  }

  const Eigen::Vector3d& axisWorld() const { return axis_world_; }
  const Eigen::Vector3d& originWorld() const { return origin_world_; }

 private:
  Eigen::Vector3d origin_world_, axis_world_;
  Eigen::Matrix3d rot_world_core0_;  // the core frame at angle 0
  Eigen::Quaterniond q_world_core0_;
  // The present ramp's acceleration: the instant start's until it is over,
  // else alpha_max_ [rad/s^2].
  double rampAcceleration() const;

  double alpha_max_;
  bool start_at_speed_;
  double alpha_;  // [rad/s^2] of the present ramp
  double omega_cmd_;
  // Reference state at the last commit.
  double t0_ = 0.0, angle0_ = 0.0, omega0_ = 0.0;
};

}  // namespace cws
