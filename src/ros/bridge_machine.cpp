// Setpoint messages to setpoints (bridge.hpp): the messages of the setpoint
// table's topics and of the machine interface's command topics, checked
// and read as their rows' setpoints.
#include <algorithm>
#include <cmath>
#include <limits>

#include "coil_winding_sim/ros/bridge.hpp"

namespace cws_ros {

bool spindleVelocity(const sensor_msgs::JointState& msg, double& omega, std::string& why) {
  const auto it = std::find(msg.name.begin(), msg.name.end(), kSpindleJoint);
  if (it == msg.name.end()) {
    why = "no joint named 'spindle'";
    return false;
  }
  const std::size_t i = static_cast<std::size_t>(it - msg.name.begin());
  if (i >= msg.velocity.size()) {
    why = "no velocity for joint 'spindle' (" + std::to_string(msg.velocity.size()) +
          " velocities for " + std::to_string(msg.name.size()) + " joints)";
    return false;
  }
  if (!std::isfinite(msg.velocity[i])) {
    why = "the velocity of joint 'spindle' is not finite";
    return false;
  }
  omega = msg.velocity[i];
  return true;
}

bool portPoint(const geometry_msgs::PointStamped& msg, const Frames& frames,
               Eigen::Vector3d& p_world, std::string& why) {
  if (!msg.header.frame_id.empty() && msg.header.frame_id != frames.world) {
    why = "frame '" + msg.header.frame_id + "' is not '" + frames.world + "'";
    return false;
  }
  const Eigen::Vector3d p(msg.point.x, msg.point.y, msg.point.z);
  if (!p.allFinite()) {
    why = "the point is not finite";
    return false;
  }
  p_world = p;
  return true;
}

bool setpointOf(const coil_winding_sim::CoreSpeedSetpoint& msg, const Frames&, cws::Setpoint& sp,
                std::string&) {
  sp = cws::Setpoint::coreSpeed(msg.angular_velocity);
  return true;
}

bool setpointOf(const sensor_msgs::JointState& msg, const Frames&, cws::Setpoint& sp,
                std::string& why) {
  double omega = 0.0;
  if (!spindleVelocity(msg, omega, why)) return false;
  sp = cws::Setpoint::coreSpeed(omega);
  return true;
}

bool setpointOf(const coil_winding_sim::TensionSetpoint& msg, const Frames&, cws::Setpoint& sp,
                std::string&) {
  sp = cws::Setpoint::supplyTension(msg.tension);
  return true;
}

bool setpointOf(const geometry_msgs::PointStamped& msg, const Frames& frames, cws::Setpoint& sp,
                std::string& why) {
  Eigen::Vector3d p_world;
  if (!portPoint(msg, frames, p_world, why)) return false;
  sp = cws::Setpoint::portPosition(p_world, std::numeric_limits<double>::quiet_NaN());
  return true;
}

}  // namespace cws_ros
