#include "coil_winding_sim/ros/bridge.hpp"

#include <fcntl.h>
#include <poll.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <mutex>
#include <new>

#include "coil_winding_sim/core/checksum.hpp"
#include "coil_winding_sim/core/core_geometry.hpp"

namespace cws_ros {

const char* const kSnapshotFormat = "coil_winding_sim/snapshot/4";
const char* const kSnapshotTopic = "/coil_winding_sim/snapshot";
const char* const kReadSnapshotArg = "--read-snapshot";
const char* const kSpindleJoint = "spindle";

namespace {
// The wire's axial force at the supply port [N] (the last integrated
// segment's), what a load cell at the nozzle measures; 0 without a supply.
double portAxialForce(const cws::WireModel& m) {
  return m.supply() ? m.axialForce(m.constants().n - 2) : 0.0;
}

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

// rosbag::Bag loads its encryption plugin through class_loader, which is not
// thread-safe: two bags opened at once in one process can fail ("no factory
// exists for it") or crash. Every bag of the bridge is used under this lock.
std::mutex bag_mutex;

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
  msg.port_axial_force = portAxialForce(m);
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

coil_winding_sim::ErrorEstimate toErrorEstimateMsg(const cws::ErrorEstimate& e, double sim_time_s,
                                                   int inputs, const std::string& failure,
                                                   const ros::Time& stamp) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  coil_winding_sim::ErrorEstimate m;
  m.header.stamp = stamp;
  m.sim_time = sim_time_s;
  m.inputs = inputs;
  m.failure = failure;
  const bool ok = failure.empty();
  m.refinement = e.refinement;
  m.shape_error = ok ? e.shape_error_rel_diameter : nan;
  m.bulging_error = ok && e.bulging_valid ? e.bulging_error_rel : nan;
  m.compute_time = ok ? e.wall_s : nan;
  m.refined_compute_time = ok ? e.refined_wall_s : nan;
  return m;
}

sensor_msgs::JointState toSpindleCommand(const cws::Simulation& sim, const ros::Time& stamp) {
  sensor_msgs::JointState msg;
  msg.header.stamp = stamp;
  msg.name = {kSpindleJoint};
  const cws::RotatingCore* core = sim.model().core();
  msg.velocity = {core ? core->command() : 0.0};
  return msg;
}

sensor_msgs::JointState toSpindleState(const cws::Simulation& sim, const ros::Time& stamp) {
  sensor_msgs::JointState msg;
  msg.header.stamp = stamp;
  msg.name = {kSpindleJoint};
  const cws::RotatingCore* core = sim.model().core();
  msg.position = {core ? core->angle(sim.time()) : 0.0};
  msg.velocity = {core ? core->omega(sim.time()) : 0.0};
  return msg;
}

coil_winding_sim::TensionSetpoint toTensionCommand(const cws::Simulation& sim,
                                                   const ros::Time& stamp) {
  coil_winding_sim::TensionSetpoint msg;
  msg.header.stamp = stamp;
  msg.tension = sim.model().supply() ? sim.model().supply()->tension() : 0.0;
  return msg;
}

coil_winding_sim::WireTension toTensionMeasured(const cws::Simulation& sim,
                                                const ros::Time& stamp) {
  coil_winding_sim::WireTension msg;
  msg.header.stamp = stamp;
  msg.tension = portAxialForce(sim.model());
  return msg;
}

bool toPortPosition(const cws::Simulation& sim, const ros::Time& stamp, const Frames& frames,
                    geometry_msgs::PointStamped& out) {
  const cws::Supply* supply = sim.model().supply();
  if (!supply) return false;
  out = geometry_msgs::PointStamped();
  out.header.stamp = stamp;
  out.header.frame_id = frames.world;
  out.point = point(supply->port(sim.time()).p_world);
  return true;
}

sensor_msgs::PointCloud2 toProfile(const cws::Simulation& sim, const ros::Time& stamp,
                                   const Frames& frames) {
  sensor_msgs::PointCloud2 cloud;
  cloud.header.stamp = stamp;
  cloud.header.frame_id = frames.core;
  const cws::WireModel& m = sim.model();
  const cws::RotatingCore* core = m.core();
  // The wound part: up to the last point touching the core.
  const int last = m.contact() ? lastInContact(m) : m.constants().n - 1;
  const int count = core ? last + 1 : 0;
  sensor_msgs::PointCloud2Modifier mod(cloud);
  mod.setPointCloud2Fields(
      4, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1, sensor_msgs::PointField::FLOAT32, "z", 1,
      sensor_msgs::PointField::FLOAT32, "stand_off", 1, sensor_msgs::PointField::FLOAT32);
  mod.resize(count);
  cloud.height = 1;
  cloud.width = count;
  cloud.is_dense = false;
  if (count == 0) return cloud;
  const bool section = !sim.scene().core.cylinders.empty();
  sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z"),
      h(cloud, "stand_off");
  for (int i = 0; i < count; ++i, ++x, ++y, ++z, ++h) {
    const Eigen::Vector3d p_core = core->pointCore(sim.time(), m.committed().p_world.col(i));
    *x = static_cast<float>(p_core.x());
    *y = static_cast<float>(p_core.y());
    *z = static_cast<float>(p_core.z());
    *h = section ? static_cast<float>(m.standOff(i)) : std::numeric_limits<float>::quiet_NaN();
  }
  return cloud;
}

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

void bagTimeRange(const std::string& path, ros::Time& start, ros::Time& end) {
  std::lock_guard<std::mutex> lock(bag_mutex);
  try {
    rosbag::Bag bag(path, rosbag::bagmode::Read);
    rosbag::View view(bag);
    if (view.size() == 0) throw std::runtime_error("it holds no messages");
    start = view.getBeginTime();
    end = view.getEndTime();
  } catch (const rosbag::BagException& e) {
    throw std::runtime_error("cannot read bag '" + path + "': " + e.what());
  } catch (const std::runtime_error& e) {
    throw std::runtime_error("bag '" + path + "': " + e.what());
  }
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
  m.port_command = s.model.port_command;
  m.next_step = s.next_step_s;
  m.last_step = s.last_step_s;
  m.steps_accepted = s.counts.accepted;
  m.steps_rejected = s.counts.rejected;
  m.derivative_evaluations = s.counts.derivative_evaluations;
  m.max_residual = s.max_residual;
  m.max_axial_force = s.max_axial_force_N;
  m.max_penetration = s.max_penetration_m;
  m.wall_time = s.wall_time_s;
  m.checksum = snapshotChecksum(m);
  return m;
}

uint64_t snapshotChecksum(const coil_winding_sim::SimulationSnapshot& msg) {
  coil_winding_sim::SimulationSnapshot m = msg;
  m.checksum = 0;
  std::vector<uint8_t> bytes(ros::serialization::serializationLength(m));
  ros::serialization::OStream stream(bytes.data(), static_cast<uint32_t>(bytes.size()));
  ros::serialization::serialize(stream, m);
  return cws::fnv1a(bytes.data(), bytes.size());
}

cws::SimulationState fromSnapshotMsg(const coil_winding_sim::SimulationSnapshot& m) {
  if (m.format != kSnapshotFormat) {
    throw std::runtime_error("not a coil_winding_sim snapshot of this version (format '" +
                             m.format + "', this version reads '" + kSnapshotFormat + "')");
  }
  // Any changed byte: a flipped bit in a number would otherwise restore.
  const uint64_t sum = snapshotChecksum(m);
  if (sum != m.checksum) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "snapshot checksum %016llx does not match its contents (%016llx): the file is "
                  "corrupt",
                  static_cast<unsigned long long>(m.checksum),
                  static_cast<unsigned long long>(sum));
    throw std::runtime_error(text);
  }
  // The core's motion reference and the tension are not checked by the core
  // library's restore: a non-finite value would only show as a failed step.
  for (int i = 0; i < 4; ++i) {
    if (!std::isfinite(m.core[i])) {
      throw std::runtime_error("snapshot core motion reference is not finite");
    }
  }
  if (!std::isfinite(m.tension) || m.tension < 0.0) {
    throw std::runtime_error("snapshot tension " + std::to_string(m.tension) +
                             " N is not a finite, non-negative number");
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
  s.model.port_command = m.port_command;
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
  if (path.empty()) throw std::runtime_error("cannot write snapshot: the path is empty");
  // Written under a temporary name and renamed: a failed write leaves no
  // file that looks like a snapshot. The name is unique to this call, so
  // that concurrent snapshots to one path never write into one file.
  static std::atomic<unsigned> serial{0};
  const std::string tmp =
      path + ".partial." + std::to_string(::getpid()) + "." + std::to_string(serial++);
  try {
    std::lock_guard<std::mutex> lock(bag_mutex);
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
  // A FIFO or a device would block the reader or never end.
  if (!std::filesystem::is_regular_file(path)) {
    throw std::runtime_error("snapshot file '" + path + "' is not a regular file");
  }
  try {
    std::lock_guard<std::mutex> lock(bag_mutex);
    rosbag::Bag bag(path, rosbag::bagmode::Read);
    rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{kSnapshotTopic}));
    for (const rosbag::MessageInstance& mi : view) {
      auto msg = mi.instantiate<coil_winding_sim::SimulationSnapshot>();
      if (msg) return *msg;
      using Traits = ros::message_traits::DataType<coil_winding_sim::SimulationSnapshot>;
      if (mi.getDataType() == Traits::value()) {
        throw std::runtime_error(
            "a snapshot of another version of coil_winding_sim (message definition " +
            mi.getMD5Sum() + "; this version reads " + std::string(kSnapshotFormat) + ", " +
            ros::message_traits::MD5Sum<coil_winding_sim::SimulationSnapshot>::value() +
            "): it cannot be restored");
      }
      throw std::runtime_error("topic " + std::string(kSnapshotTopic) + " holds " +
                               mi.getDataType() + ", not a snapshot");
    }
    throw std::runtime_error("no snapshot (topic " + std::string(kSnapshotTopic) + ") in it");
  } catch (const rosbag::BagIOException& e) {
    // rosbag's read error ("wanted n bytes, read m bytes"): the file ends
    // before the records that its header points to.
    const bool short_read = std::string(e.what()).find("wanted") != std::string::npos;
    throw std::runtime_error("'" + path + "' is not a readable bag" +
                             (short_read ? ", it ends early (truncated?): " : ": ") + e.what());
  } catch (const rosbag::BagException& e) {
    throw std::runtime_error("'" + path + "' is not a readable bag: " + e.what());
  } catch (const ros::serialization::StreamOverrunException& e) {
    // A record's length field says more than its data holds.
    throw std::runtime_error(
        "'" + path + "' is corrupt: a record is shorter than its length says (" + e.what() + ")");
  } catch (const std::runtime_error& e) {
    throw std::runtime_error("'" + path + "': " + e.what());
  }
}

namespace {
// The reader's first output byte: a snapshot follows, or an error message.
constexpr char kReaderOk = 'K';
constexpr char kReaderError = 'E';
// Address space of the reader process [bytes]: a corrupt array length makes
// the deserializer allocate up to 32 GiB; under this limit it fails instead.
constexpr rlim_t kReaderAddressSpace = rlim_t{2} << 30;

bool writeAll(int fd, const std::string& data) {
  std::size_t done = 0;
  while (done < data.size()) {
    const ssize_t n = ::write(fd, data.data() + done, data.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

// Closes a descriptor when it goes out of scope.
struct Fd {
  int fd = -1;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};
}  // namespace

int snapshotReaderMain(const std::string& path, int out_fd) {
  rlimit limit;
  limit.rlim_cur = limit.rlim_max = kReaderAddressSpace;
  ::setrlimit(RLIMIT_AS, &limit);
  std::string out;
  int rc = 0;
  try {
    const coil_winding_sim::SimulationSnapshot msg = readSnapshotBag(path);  // names the path
    // The whole restore, so that a scene or state that cannot be built
    // fails here, within the limits, and not in the caller.
    try {
      cws::Simulation::fromState(fromSnapshotMsg(msg));
    } catch (const std::bad_alloc&) {
      throw;
    } catch (const std::exception& e) {
      throw std::runtime_error("'" + path + "': " + e.what());
    }
    // Serialized anew: the caller gets array lengths that match the data.
    const uint32_t n = ros::serialization::serializationLength(msg);
    out.assign(1 + n, kReaderOk);
    ros::serialization::OStream stream(reinterpret_cast<uint8_t*>(&out[1]), n);
    ros::serialization::serialize(stream, msg);
  } catch (const std::bad_alloc&) {
    out = std::string(1, kReaderError) + "'" + path + "' is corrupt: reading it needs more than " +
          std::to_string(kReaderAddressSpace >> 30) + " GiB of memory";
    rc = 1;
  } catch (const std::exception& e) {
    out = std::string(1, kReaderError) + e.what();
    rc = 1;
  }
  return writeAll(out_fd, out) ? rc : 1;
}

coil_winding_sim::SimulationSnapshot readSnapshotBagIsolated(const std::string& path,
                                                             const std::string& reader_exe,
                                                             double timeout_s) {
  const auto fail = [&](const std::string& why) {
    return std::runtime_error("'" + path + "': " + why);
  };
  // Cheap checks here, so that their messages need no child.
  if (!std::filesystem::exists(path)) {
    throw std::runtime_error("snapshot file '" + path + "' does not exist");
  }
  if (!std::filesystem::is_regular_file(path)) {
    throw std::runtime_error("snapshot file '" + path + "' is not a regular file");
  }

  // The child: stdin, stdout and stderr on /dev/null (rosbag's complaints
  // about a corrupt file would read like network trouble in our log), the
  // result on descriptor kSnapshotReaderFd, nothing else of ours open.
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw fail(std::string("pipe: ") + std::strerror(errno));
  Fd read_end{fds[0]}, write_end{fds[1]};
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, write_end.fd, kSnapshotReaderFd);
  posix_spawn_file_actions_addclosefrom_np(&actions, kSnapshotReaderFd + 1);
  std::vector<std::string> args = {reader_exe, kReadSnapshotArg, path};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int spawn_error =
      ::posix_spawn(&pid, reader_exe.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawn_error != 0) {
    throw fail("cannot start the snapshot reader '" + reader_exe +
               "': " + std::strerror(spawn_error));
  }
  ::close(write_end.fd);
  write_end.fd = -1;

  // Read until end of file, the time limit or the size limit.
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(timeout_s));
  const std::size_t max_bytes = kReaderAddressSpace / 2;
  std::string out;
  std::string problem;
  char buffer[65536];
  while (true) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    if (left.count() <= 0) {
      char text[128];
      std::snprintf(text, sizeof text, "reading it took longer than %g s (corrupt?)", timeout_s);
      problem = text;
      break;
    }
    pollfd p{read_end.fd, POLLIN, 0};
    const int ready = ::poll(&p, 1, static_cast<int>(std::min<long long>(left.count(), 1000)));
    if (ready < 0 && errno != EINTR) {
      problem = std::string("poll: ") + std::strerror(errno);
      break;
    }
    if (ready <= 0) continue;
    const ssize_t n = ::read(read_end.fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // end of file (or an error: judged by the exit status)
    out.append(buffer, static_cast<std::size_t>(n));
    if (out.size() > max_bytes) {
      problem = "the snapshot reader's output exceeds " + std::to_string(max_bytes) + " bytes";
      break;
    }
  }
  if (!problem.empty()) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!problem.empty()) throw fail(problem);
  if (WIFSIGNALED(status)) {
    throw std::runtime_error("'" + path + "' is corrupt: reading it crashed the bag reader (" +
                             strsignal(WTERMSIG(status)) + ")");
  }
  if (out.empty()) {
    throw fail("the snapshot reader '" + reader_exe + "' exited with status " +
               std::to_string(WEXITSTATUS(status)) + " and no result");
  }
  if (out[0] == kReaderError) throw std::runtime_error(out.substr(1));
  if (out[0] != kReaderOk || WEXITSTATUS(status) != 0) {
    throw fail("the snapshot reader '" + reader_exe + "' gave no readable result");
  }
  coil_winding_sim::SimulationSnapshot msg;
  try {
    ros::serialization::IStream stream(reinterpret_cast<uint8_t*>(&out[1]),
                                       static_cast<uint32_t>(out.size() - 1));
    ros::serialization::deserialize(stream, msg);
  } catch (const std::exception& e) {
    throw fail(std::string("the snapshot reader's result does not deserialize: ") + e.what());
  }
  return msg;
}

}  // namespace cws_ros
