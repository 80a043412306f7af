// Snapshots as messages and bag files (snapshot_bag.hpp).
#include "coil_winding_sim/ros/snapshot_bag.hpp"

#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <cstdio>
#include <filesystem>
#include <mutex>
#include <new>

#include "coil_winding_sim/core/base/checksum.hpp"

namespace cws_ros {

const char* const kSnapshotFormat = "coil_winding_sim/snapshot/7";
const char* const kSnapshotTopic = "/coil_winding_sim/snapshot";

namespace {
// rosbag::Bag loads its encryption plugin through class_loader, which is not
// thread-safe: two bags opened at once in one process can fail ("no factory
// exists for it") or crash. Every bag of the bridge is used under this lock.
std::mutex bag_mutex;
}  // namespace

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
  for (const cws::Setpoint& sp : s.held) {
    coil_winding_sim::HeldSetpoint h;
    h.kind = sp.name();
    h.value = sp.value;
    h.value2 = sp.value2;
    m.setpoints.push_back(h);
  }
  m.points_added = s.model.points_added;
  m.committed_time = s.model.committed_time_s;
  m.port_distance0 = s.model.port_distance0_m;
  m.carried_points = s.model.carried;
  m.carried_poses = s.model.carried_pose;
  m.port_command = s.model.port_command;
  m.retired_points = s.model.retired;
  m.retired_wire = s.model.retired_points;
  for (int i = 0; i < 4; ++i) m.retired_energy[i] = s.model.retired_energy[i];
  for (int i = 0; i < 8; ++i) m.clamp_core[i] = s.model.clamp_core[i];
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
  // The core's motion reference is not checked by the core library's
  // restore: a non-finite value would only show as a failed step. (The
  // setpoints held pass their rows' checks there.)
  for (int i = 0; i < 4; ++i) {
    if (!std::isfinite(m.core[i])) {
      throw std::runtime_error("snapshot core motion reference is not finite");
    }
  }
  cws::SimulationState s;
  for (const coil_winding_sim::HeldSetpoint& h : m.setpoints) {
    const cws::SetpointRow* row = cws::setpointRowNamed(h.kind);
    if (!row) throw std::runtime_error("snapshot holds an unknown setpoint '" + h.kind + "'");
    cws::Setpoint sp;
    sp.kind = row->kind;
    sp.value = h.value;
    sp.value2 = h.value2;
    s.held.push_back(sp);
  }
  s.scene_yaml = m.scene_yaml;
  s.time_s = m.time;
  s.model.points = m.points;
  s.model.y = m.state;
  s.model.history = m.history;
  for (int i = 0; i < 4; ++i) s.model.core[i] = m.core[i];
  s.model.points_added = m.points_added;
  s.model.committed_time_s = m.committed_time;
  s.model.port_distance0_m = m.port_distance0;
  s.model.carried = m.carried_points;
  s.model.carried_pose = m.carried_poses;
  s.model.port_command = m.port_command;
  s.model.retired = m.retired_points;
  s.model.retired_points = m.retired_wire;
  for (int i = 0; i < 4; ++i) s.model.retired_energy[i] = m.retired_energy[i];
  for (int i = 0; i < 8; ++i) s.model.clamp_core[i] = m.clamp_core[i];
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

}  // namespace cws_ros
