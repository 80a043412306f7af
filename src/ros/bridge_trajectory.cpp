// The bridge's reading of trajectory_msgs/JointTrajectory, the standard
// command of a machine axis, as the cell's setpoints (bridge.hpp).
#include <algorithm>
#include <cmath>
#include <limits>

#include "coil_winding_sim/ros/bridge.hpp"

namespace cws_ros {

bool fromTrajectory(const trajectory_msgs::JointTrajectory& msg, TrajectorySetpoints& out,
                    std::string& why) {
  out = TrajectorySetpoints();
  const std::vector<std::string>& names = msg.joint_names;
  const std::size_t n = names.size();
  if (n == 0) {
    why = "no joint_names";
    return false;
  }
  // The cell's joints, each once.
  int spindle = -1, port[3] = {-1, -1, -1};
  const char* const port_names[3] = {"port_x", "port_y", "port_z"};
  for (std::size_t j = 0; j < n; ++j) {
    int* slot = names[j] == kSpindleJoint ? &spindle : nullptr;
    for (int a = 0; a < 3 && !slot; ++a) {
      if (names[j] == port_names[a]) slot = &port[a];
    }
    if (!slot) {
      why = "joint '" + names[j] + "' is not one of the cell's (spindle, port_x, port_y, port_z)";
      return false;
    }
    if (*slot >= 0) {
      why = "joint '" + names[j] + "' is named twice";
      return false;
    }
    *slot = static_cast<int>(j);
  }
  const std::vector<trajectory_msgs::JointTrajectoryPoint>& pts = msg.points;
  if (pts.empty()) {
    why = "no points";
    return false;
  }
  const bool any_port = port[0] >= 0 || port[1] >= 0 || port[2] >= 0;
  bool velocities = true, positions = true;
  double last_t = -1.0;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const double t = pts[k].time_from_start.toSec();
    if (!(t >= 0.0) || !(t > last_t)) {
      why = "time_from_start must be >= 0 and increase (point " + std::to_string(k) + ")";
      return false;
    }
    last_t = t;
    velocities &= pts[k].velocities.size() == n;
    positions &= pts[k].positions.size() == n;
    for (double v : pts[k].velocities) {
      if (!std::isfinite(v)) positions = velocities = false;
    }
    for (double p : pts[k].positions) {
      if (!std::isfinite(p)) positions = velocities = false;
    }
  }
  if (any_port && !positions) {
    why = "the port's joints need a finite position for every joint at every point";
    return false;
  }
  if (spindle >= 0 && !velocities && !(positions && pts.size() >= 2)) {
    why =
        "the spindle needs a finite velocity for every joint at every point, or positions at "
        "two points or more";
    return false;
  }
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const double t = pts[k].time_from_start.toSec();
    if (spindle >= 0) {
      double w = 0.0;  // (positions alone: the speed to the next point, 0 at the last)
      if (velocities) {
        w = pts[k].velocities[spindle];
      } else if (k + 1 < pts.size()) {
        w = (pts[k + 1].positions[spindle] - pts[k].positions[spindle]) /
            (pts[k + 1].time_from_start.toSec() - t);
      }
      out.spindle.emplace_back(t, w);
    }
    if (any_port) {
      Eigen::Vector3d p = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
      for (int a = 0; a < 3; ++a) {
        if (port[a] >= 0) p[a] = pts[k].positions[port[a]];
      }
      out.port.emplace_back(t, p);
    }
  }
  return true;
}

}  // namespace cws_ros
