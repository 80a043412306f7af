#include "coil_winding_sim/ros/bridge.hpp"

#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "coil_winding_sim/core/core_geometry.hpp"

namespace cws_ros {

const char* const kSnapshotFormat = "coil_winding_sim/snapshot/2";
const char* const kSnapshotTopic = "/coil_winding_sim/snapshot";

namespace {
geometry_msgs::Point point(const Eigen::Vector3d& p) {
  geometry_msgs::Point m;
  m.x = p.x();
  m.y = p.y();
  m.z = p.z();
  return m;
}

std_msgs::ColorRGBA color(double r, double g, double b, double a = 1.0) {
  std_msgs::ColorRGBA c;
  c.r = static_cast<float>(r);
  c.g = static_cast<float>(g);
  c.b = static_cast<float>(b);
  c.a = static_cast<float>(a);
  return c;
}

// Blue (0) -> green -> red (1).
std_msgs::ColorRGBA heat(double s) {
  s = std::clamp(s, 0.0, 1.0);
  return s < 0.5 ? color(0.0, 2.0 * s, 1.0 - 2.0 * s) : color(2.0 * s - 1.0, 2.0 - 2.0 * s, 0.0);
}

// A marker with its header, namespace, id, type and ADD set.
visualization_msgs::Marker marker(const ros::Time& stamp, const std::string& frame, const char* ns,
                                  int id, int type) {
  visualization_msgs::Marker k;
  k.header.stamp = stamp;
  k.header.frame_id = frame;
  k.ns = ns;
  k.id = id;
  k.type = type;
  k.action = visualization_msgs::Marker::ADD;
  k.pose.orientation.w = 1.0;
  return k;
}

int lastInContact(const cws::WireModel& m) {
  int last = -1;
  if (!m.contact()) return last;
  for (int i = 1; i < m.constants().n; ++i) {
    if (m.contact()->inContact(i)) last = i;
  }
  return last;
}
}  // namespace

coil_winding_sim::WireState toWireState(const cws::Simulation& sim, const ros::Time& stamp,
                                        const Frames& frames) {
  const cws::WireModel& m = sim.model();
  const int n = m.constants().n;
  coil_winding_sim::WireState msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = frames.world;
  msg.sim_time = sim.time();
  msg.positions.reserve(n);
  const bool core = m.core() && !sim.scene().core.cylinders.empty();
  for (int i = 0; i < n; ++i) {
    const cws::PointReport r = m.point(i);
    msg.positions.push_back(point(r.p_world));
    msg.axial_force.push_back(r.axial_force_N);
    msg.curvature.push_back(r.curvature_1pm);
    msg.plastic_curvature.push_back(r.plastic_curvature_1pm);
    msg.twist.push_back(r.twist_rad_per_m);
    msg.stand_off.push_back(core ? m.standOff(i) : std::numeric_limits<double>::quiet_NaN());
    msg.in_contact.push_back(r.in_contact);
    msg.stick.push_back(r.stick);
  }
  return msg;
}

coil_winding_sim::WindingMetrics toMetrics(const cws::Simulation& sim, const ros::Time& stamp,
                                           const Frames& frames, const Pace& pace) {
  const cws::WireModel& m = sim.model();
  coil_winding_sim::WindingMetrics msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = frames.world;
  msg.sim_time = sim.time();
  const cws::BulgeReport b = m.bulging();
  msg.bulging_height = b.valid ? b.height_m : std::numeric_limits<double>::quiet_NaN();
  msg.bulging_index = b.valid ? b.index : -1;
  const int last = lastInContact(m);
  msg.wound_length = last > 0 ? last * m.constants().segment_length : 0.0;
  msg.fed_length = m.fedLength();
  msg.core_turns = sim.coreTurns();
  msg.core_angular_velocity = m.core() ? m.core()->omega(sim.time()) : 0.0;
  msg.core_angular_velocity_setpoint = m.core() ? m.core()->command() : 0.0;
  msg.supply_tension = m.supply() ? m.supply()->tension() : 0.0;
  msg.port_axial_force = m.supply() ? m.axialForce(m.constants().n - 2) : 0.0;
  msg.real_time_factor = pace.real_time_factor;
  msg.target_real_time_factor = pace.target_real_time_factor;
  msg.keeping_pace = pace.keeping_pace;
  msg.steps_accepted = sim.stepper().counts().accepted;
  msg.steps_rejected = sim.stepper().counts().rejected;
  msg.step_size = sim.stepper().lastStep();
  msg.max_constraint_residual = m.maxConstraintResidual();
  msg.points = m.constants().n;
  return msg;
}

visualization_msgs::MarkerArray toMarkers(const cws::Simulation& sim, const ros::Time& stamp,
                                          const Frames& frames, double force_scale_N,
                                          std::size_t max_points_per_marker) {
  visualization_msgs::MarkerArray out;
  const cws::WireModel& m = sim.model();
  const int n = m.constants().n;
  const double diameter = 2.0 * m.constants().radius;
  // The wire: consecutive strips share their end point.
  const std::size_t per = std::max<std::size_t>(2, max_points_per_marker);
  int id = 0;
  for (int start = 0; start < n - 1; start += static_cast<int>(per) - 1) {
    visualization_msgs::Marker w =
        marker(stamp, frames.world, "wire", id++, visualization_msgs::Marker::LINE_STRIP);
    w.scale.x = diameter;
    const int end = std::min(n, start + static_cast<int>(per));
    for (int i = start; i < end; ++i) {
      const cws::PointReport r = m.point(i);
      w.points.push_back(point(r.p_world));
      w.colors.push_back(heat(r.axial_force_N / std::max(1e-9, force_scale_N)));
    }
    out.markers.push_back(w);
  }
  // The core: cylinders and faces in the core frame, 20 mm tall.
  if (m.core()) {
    const cws::CoreParams& core = sim.scene().core;
    const double height = 0.02;
    int cid = 0;
    for (const cws::CylinderParams& c : core.cylinders) {
      visualization_msgs::Marker k =
          marker(stamp, frames.core, "core", cid++, visualization_msgs::Marker::CYLINDER);
      k.pose.position.x = c.center_core.x();
      k.pose.position.y = c.center_core.y();
      k.scale.x = k.scale.y = 2.0 * c.radius;
      k.scale.z = height;
      k.color = color(0.55, 0.55, 0.6, 0.9);
      out.markers.push_back(k);
    }
    for (const cws::FaceParams& f : cws::coreFaces(core)) {
      visualization_msgs::Marker k =
          marker(stamp, frames.core, "core", cid++, visualization_msgs::Marker::CUBE);
      const Eigen::Vector2d d = f.to_core - f.from_core;
      const Eigen::Vector2d mid = 0.5 * (f.from_core + f.to_core);
      const Eigen::Vector2d in(-d.y() / d.norm(), d.x() / d.norm());  // left: inside
      k.pose.position.x = mid.x() + 0.5e-3 * in.x();
      k.pose.position.y = mid.y() + 0.5e-3 * in.y();
      const double yaw = std::atan2(d.y(), d.x());
      k.pose.orientation.z = std::sin(0.5 * yaw);
      k.pose.orientation.w = std::cos(0.5 * yaw);
      k.scale.x = d.norm();
      k.scale.y = 1e-3;
      k.scale.z = height;
      k.color = color(0.55, 0.55, 0.6, 0.9);
      out.markers.push_back(k);
    }
  }
  if (m.supply()) {
    visualization_msgs::Marker p =
        marker(stamp, frames.port, "supply_port", 0, visualization_msgs::Marker::SPHERE);
    p.scale.x = p.scale.y = p.scale.z = 3.0 * diameter;
    p.color = color(1.0, 0.8, 0.0, 0.8);
    out.markers.push_back(p);
  }
  return out;
}

visualization_msgs::MarkerArray deleteAllMarkers(const ros::Time& stamp, const Frames& frames) {
  visualization_msgs::MarkerArray out;
  visualization_msgs::Marker d;
  d.header.stamp = stamp;
  d.header.frame_id = frames.world;
  d.action = visualization_msgs::Marker::DELETEALL;
  out.markers.push_back(d);
  return out;
}

bool coreTransform(const cws::Simulation& sim, const ros::Time& stamp, const Frames& frames,
                   geometry_msgs::TransformStamped& out) {
  const cws::RotatingCore* core = sim.model().core();
  if (!core) return false;
  out = geometry_msgs::TransformStamped();
  out.header.stamp = stamp;
  out.header.frame_id = frames.world;
  out.child_frame_id = frames.core;
  out.transform.translation.x = core->originWorld().x();
  out.transform.translation.y = core->originWorld().y();
  out.transform.translation.z = core->originWorld().z();
  const Eigen::Quaterniond q = core->quaternionWorldCore(sim.time()).normalized();
  out.transform.rotation.w = q.w();
  out.transform.rotation.x = q.x();
  out.transform.rotation.y = q.y();
  out.transform.rotation.z = q.z();
  return true;
}

bool portTransform(const cws::Simulation& sim, const ros::Time& stamp, const Frames& frames,
                   geometry_msgs::TransformStamped& out) {
  const cws::Supply* supply = sim.model().supply();
  if (!supply) return false;
  const Eigen::Vector3d p = supply->port(sim.time()).p_world;
  out = geometry_msgs::TransformStamped();
  out.header.stamp = stamp;
  out.header.frame_id = frames.world;
  out.child_frame_id = frames.port;
  out.transform.translation.x = p.x();
  out.transform.translation.y = p.y();
  out.transform.translation.z = p.z();
  out.transform.rotation.w = 1.0;
  return true;
}

coil_winding_sim::SimulationSnapshot toSnapshotMsg(const cws::SimulationState& s,
                                                   const ros::Time& stamp) {
  coil_winding_sim::SimulationSnapshot m;
  m.header.stamp = stamp;
  m.format = kSnapshotFormat;
  m.scene_yaml = s.scene_yaml;
  m.time = s.time_s;
  m.points = s.model.points;
  m.state = s.model.y;
  m.history = s.model.history;
  for (int i = 0; i < 4; ++i) m.core[i] = s.model.core[i];
  m.tension = s.model.tension_N;
  m.points_added = s.model.points_added;
  m.committed_time = s.model.committed_time_s;
  m.port_distance0 = s.model.port_distance0_m;
  m.carried_points = s.model.carried;
  m.carried_poses = s.model.carried_pose;
  m.next_step = s.next_step_s;
  m.last_step = s.last_step_s;
  m.steps_accepted = s.counts.accepted;
  m.steps_rejected = s.counts.rejected;
  m.derivative_evaluations = s.counts.derivative_evaluations;
  m.max_residual = s.max_residual;
  m.max_axial_force = s.max_axial_force_N;
  m.max_penetration = s.max_penetration_m;
  m.wall_time = s.wall_time_s;
  return m;
}

cws::SimulationState fromSnapshotMsg(const coil_winding_sim::SimulationSnapshot& m) {
  if (m.format != kSnapshotFormat) {
    throw std::runtime_error("not a coil_winding_sim snapshot (format '" + m.format + "')");
  }
  cws::SimulationState s;
  s.scene_yaml = m.scene_yaml;
  s.time_s = m.time;
  s.model.points = m.points;
  s.model.y = m.state;
  s.model.history = m.history;
  for (int i = 0; i < 4; ++i) s.model.core[i] = m.core[i];
  s.model.tension_N = m.tension;
  s.model.points_added = m.points_added;
  s.model.committed_time_s = m.committed_time;
  s.model.port_distance0_m = m.port_distance0;
  s.model.carried = m.carried_points;
  s.model.carried_pose = m.carried_poses;
  s.next_step_s = m.next_step;
  s.last_step_s = m.last_step;
  s.counts.accepted = m.steps_accepted;
  s.counts.rejected = m.steps_rejected;
  s.counts.derivative_evaluations = m.derivative_evaluations;
  s.max_residual = m.max_residual;
  s.max_axial_force_N = m.max_axial_force;
  s.max_penetration_m = m.max_penetration;
  s.wall_time_s = m.wall_time;
  return s;
}

void writeSnapshotBag(const std::string& path, const coil_winding_sim::SimulationSnapshot& msg) {
  // Written under a temporary name and renamed: a failed write leaves no
  // file that looks like a snapshot.
  const std::string tmp = path + ".partial";
  try {
    rosbag::Bag bag(tmp, rosbag::bagmode::Write);
    const ros::Time t = msg.header.stamp.isZero() ? ros::TIME_MIN : msg.header.stamp;
    bag.write(kSnapshotTopic, t, msg);
    bag.close();
  } catch (const std::exception& e) {
    std::remove(tmp.c_str());
    throw std::runtime_error("cannot write snapshot '" + path + "': " + e.what());
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw std::runtime_error("cannot write snapshot '" + path + "': " + ec.message());
  }
}

coil_winding_sim::SimulationSnapshot readSnapshotBag(const std::string& path) {
  if (!std::filesystem::exists(path)) {
    throw std::runtime_error("snapshot file '" + path + "' does not exist");
  }
  try {
    rosbag::Bag bag(path, rosbag::bagmode::Read);
    rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{kSnapshotTopic}));
    for (const rosbag::MessageInstance& mi : view) {
      auto msg = mi.instantiate<coil_winding_sim::SimulationSnapshot>();
      if (msg) return *msg;
      throw std::runtime_error("topic " + std::string(kSnapshotTopic) + " holds " +
                               mi.getDataType() + ", not a snapshot");
    }
    throw std::runtime_error("no snapshot (topic " + std::string(kSnapshotTopic) + ") in it");
  } catch (const rosbag::BagException& e) {
    throw std::runtime_error("'" + path + "' is not a readable bag: " + e.what());
  } catch (const std::runtime_error& e) {
    throw std::runtime_error("'" + path + "': " + e.what());
  }
}

}  // namespace cws_ros
