// The bridge's compact form of the wire for recordings, and its reader
// (bridge.hpp).
#include <algorithm>

#include "coil_winding_sim/ros/bridge.hpp"
#include "marker_style.hpp"

namespace cws_ros {

using namespace marker_style;

int carriedBlock(const cws::Simulation& sim) {
  const cws::WireModel& m = sim.model();
  // Point 0 (the fixed end on the core) and the carried points 1..c, the
  // retired wire before them (whole-wire indices).
  const int carried = m.retiredPoints() + m.carriedPoints();
  return m.core() && carried > 0 ? carried + 1 : 0;
}

coil_winding_sim::WireStateCompact toWireStateCompact(const cws::Simulation& sim,
                                                      const ros::Time& stamp, const Frames& frames,
                                                      int carried_from) {
  const cws::WireModel& m = sim.model();
  const int n = m.wirePoints(), carried = carriedBlock(sim);
  coil_winding_sim::WireStateCompact msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = frames.world;
  msg.core_frame = frames.core;
  msg.sim_time = sim.time();
  msg.diameter = static_cast<float>(2.0 * m.constants().radius);
  msg.points = static_cast<uint32_t>(n);
  const int from = std::clamp(carried_from, 0, carried);
  msg.carried_first = static_cast<uint32_t>(from);
  msg.carried_xyz.reserve(3 * (carried - from));
  msg.carried_force.reserve(carried - from);
  for (int i = from; i < carried; ++i) {
    const Eigen::Vector3d p = cws::wirePointCore(m, i);
    for (int a = 0; a < 3; ++a) msg.carried_xyz.push_back(static_cast<float>(p[a]));
    msg.carried_force.push_back(static_cast<float>(cws::wirePoint(m, i).axial_force_N));
  }
  msg.free_first = static_cast<uint32_t>(carried);
  msg.free_xyz.reserve(3 * (n - carried));
  for (int i = carried; i < n; ++i) {
    const cws::PointReport r = cws::wirePoint(m, i);
    for (int a = 0; a < 3; ++a) msg.free_xyz.push_back(static_cast<float>(r.p_world[a]));
    msg.free_force.push_back(static_cast<float>(r.axial_force_N));
    msg.free_flags.push_back(static_cast<uint8_t>((r.in_contact ? 1 : 0) | (r.stick ? 2 : 0)));
  }
  return msg;
}

bool CompactWire::add(const coil_winding_sim::WireStateCompact& msg, std::string& why) {
  const std::size_t first = msg.carried_first, held = carried_force_.size();
  if (first > held) {
    why = "its carried wire starts at point " + std::to_string(first) + ", beyond the " +
          std::to_string(held) + " held (a message was missed: waiting for one from point 0)";
    return false;
  }
  if (msg.carried_xyz.size() != 3 * msg.carried_force.size() ||
      msg.free_xyz.size() != 3 * msg.free_force.size() ||
      msg.free_first != first + msg.carried_force.size() ||
      msg.points != msg.free_first + msg.free_force.size()) {
    why = "its blocks do not add up to its " + std::to_string(msg.points) + " points";
    return false;
  }
  carried_xyz_.resize(3 * first);
  carried_force_.resize(first);
  carried_xyz_.insert(carried_xyz_.end(), msg.carried_xyz.begin(), msg.carried_xyz.end());
  carried_force_.insert(carried_force_.end(), msg.carried_force.begin(), msg.carried_force.end());
  free_xyz_ = msg.free_xyz;
  force_ = carried_force_;
  force_.insert(force_.end(), msg.free_force.begin(), msg.free_force.end());
  world_ = msg.header.frame_id;
  core_ = msg.core_frame;
  diameter_ = msg.diameter;
  return true;
}

visualization_msgs::MarkerArray CompactWire::markers(const ros::Time& stamp,
                                                     double force_scale_N) const {
  visualization_msgs::MarkerArray out;
  const std::size_t carried = carried_force_.size();
  auto strip = [&](const std::string& frame, int id, const std::vector<float>& xyz,
                   std::size_t force_offset) {
    visualization_msgs::Marker w =
        marker(stamp, frame, "wire", id, visualization_msgs::Marker::LINE_STRIP);
    w.scale.x = diameter_;
    for (std::size_t i = 0; 3 * i + 2 < xyz.size(); ++i) {
      geometry_msgs::Point p;
      p.x = xyz[3 * i];
      p.y = xyz[3 * i + 1];
      p.z = xyz[3 * i + 2];
      w.points.push_back(p);
      w.colors.push_back(heat(force_[force_offset + i] / std::max(1e-9, force_scale_N)));
    }
    out.markers.push_back(w);
  };
  strip(core_, 0, carried_xyz_, 0);
  strip(world_, 1, free_xyz_, carried);
  return out;
}

}  // namespace cws_ros
