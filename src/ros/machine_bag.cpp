// A machine bag read and checked as compare_bags.py checks it
// (machine_bag.hpp). The messages are compare_bags.py's, word for word, so
// that a bag refused by one tool is refused by the other in the same terms
// (test_replay_machine runs both on the same bad bags).
#include "coil_winding_sim/ros/machine_bag.hpp"

#include <geometry_msgs/PointStamped.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/PointCloud2.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <set>

#include "coil_winding_sim/TensionSetpoint.h"
#include "coil_winding_sim/WireTension.h"
#include "coil_winding_sim/core/base/text_format.hpp"

namespace cws_ros {

namespace {

constexpr int kMinSamples = 10;  // compare_bags.py's MIN_SAMPLES
const char* const kJoint = "spindle";

// The machine's measurements, relative to machine/: type and whether
// required (compare_bags.py reads the first two and the commands). The
// command topics are the setpoint table's (machineCommandTopics).
struct TopicSpec {
  std::string rel;
  std::string type;
  bool required;
  const cws::SetpointRow* row;  // a command's row; null for a measurement
};
std::vector<TopicSpec> machineTopics() {
  std::vector<TopicSpec> topics = {
      {"spindle/state", "sensor_msgs/JointState", true, nullptr},
      {"tension/measured", "coil_winding_sim/WireTension", true, nullptr},
      {"profile", "sensor_msgs/PointCloud2", false, nullptr},
  };
  for (const cws::SetpointRow& row : cws::setpointTable()) {
    const std::string topic = row.machine_topic;
    if (topic.empty()) continue;
    visitRowMessages(row.kind, [&](auto m) {
      using M = typename decltype(m)::machine;
      topics.push_back({topic.substr(std::strlen("machine/")),
                        ros::message_traits::DataType<M>::value(), decltype(m)::machine_required,
                        &row});
    });
  }
  return topics;
}

std::string format(const char* fmt, ...) {
  char buf[1024];
  va_list ap;
  va_start(ap, fmt);
  std::vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  return buf;
}

[[noreturn]] void refuse(const std::string& what) { throw MachineBagError(what); }

std::string norm(const std::string& topic) {
  return !topic.empty() && topic[0] == '/' ? topic.substr(1) : topic;
}

// A list of names as Python prints one: ['a', 'b'].
std::string pythonList(std::vector<std::string> names) {
  std::string s = "[";
  for (std::size_t i = 0; i < names.size(); ++i) s += (i ? ", '" : "'") + names[i] + "'";
  return s + "]";
}

// Header stamps set and strictly increasing (compare_bags.py's check_stamps).
void checkStamps(const std::string& topic, const std::vector<double>& stamps) {
  if (!stamps.empty() && std::all_of(stamps.begin(), stamps.end(), [](double s) { return s == 0; }))
    refuse(format("topic %s: header stamps are all zero (unset)", topic.c_str()));
  for (std::size_t i = 1; i < stamps.size(); ++i) {
    if (!(stamps[i] > stamps[i - 1])) {
      refuse(
          format("topic %s: header stamps not strictly increasing: message %zu has stamp %.6f s, "
                 "message %zu before it %.6f s",
                 topic.c_str(), i, stamps[i], i - 1, stamps[i - 1]));
    }
  }
}

// A field of a cloud's point as double (PointField datatypes 1..8).
double fieldValue(const std::uint8_t* p, std::uint8_t datatype, bool big_endian) {
  std::uint8_t b[8];
  const int size = datatype <= 2 ? 1 : datatype <= 4 ? 2 : datatype <= 7 ? 4 : 8;
  std::memcpy(b, p, size);
  if (big_endian) std::reverse(b, b + size);
  switch (datatype) {
    case 1:
      return static_cast<std::int8_t>(b[0]);
    case 2:
      return b[0];
    case 3: {
      std::int16_t v;
      std::memcpy(&v, b, 2);
      return v;
    }
    case 4: {
      std::uint16_t v;
      std::memcpy(&v, b, 2);
      return v;
    }
    case 5: {
      std::int32_t v;
      std::memcpy(&v, b, 4);
      return v;
    }
    case 6: {
      std::uint32_t v;
      std::memcpy(&v, b, 4);
      return v;
    }
    case 7: {
      float v;
      std::memcpy(&v, b, 4);
      return v;
    }
    default: {
      double v;
      std::memcpy(&v, b, 8);
      return v;
    }
  }
}

}  // namespace

// A cloud's finite points and stand-off (compare_bags.py's cloud_points).
cws::ProfileCloud profileCloud(const sensor_msgs::PointCloud2& msg, double t_s) {
  std::map<std::string, const sensor_msgs::PointField*> fields;
  for (const auto& f : msg.fields) fields[f.name] = &f;
  for (const char* name : {"x", "y", "z"}) {
    if (!fields.count(name)) {
      std::vector<std::string> names;
      for (const auto& [n, f] : fields) names.push_back(n);
      refuse(
          format("profile cloud has no field '%s' (fields: %s)", name, pythonList(names).c_str()));
    }
  }
  const sensor_msgs::PointField* so = fields.count("stand_off") ? fields["stand_off"] : nullptr;
  cws::ProfileCloud c;
  c.t_s = t_s;
  for (std::uint32_t r = 0; r < msg.height; ++r) {
    for (std::uint32_t i = 0; i < msg.width; ++i) {
      const std::size_t at = std::size_t(r) * msg.row_step + std::size_t(i) * msg.point_step;
      if (at + msg.point_step > msg.data.size()) break;
      const std::uint8_t* p = &msg.data[at];
      auto value = [&](const sensor_msgs::PointField* f) {
        return fieldValue(p + f->offset, f->datatype, msg.is_bigendian);
      };
      const Eigen::Vector3d x(value(fields["x"]), value(fields["y"]), value(fields["z"]));
      if (!x.allFinite()) continue;
      c.p_core.push_back(x);
      if (so) c.stand_off_m.push_back(value(so));
    }
  }
  return c;
}

MachineRecording readMachineBag(const std::string& path, const cws::SetpointLimits& limits,
                                const Frames& frames) {
  if (!std::filesystem::is_regular_file(path)) refuse("no such bag: " + path);
  rosbag::Bag bag;
  try {
    bag.open(path, rosbag::bagmode::Read);
  } catch (const std::exception& e) {
    refuse(format("cannot read bag %s: %s", path.c_str(), e.what()));
  }
  const std::vector<TopicSpec> specs = machineTopics();
  std::map<std::string, const TopicSpec*> wanted;
  for (const TopicSpec& s : specs) wanted["machine/" + s.rel] = &s;

  rosbag::View all(bag);
  MachineRecording rec;
  rec.path = path;
  // Types first, as compare_bags.py checks them.
  std::vector<std::string> topics;
  for (const rosbag::ConnectionInfo* c : all.getConnections()) {
    const std::string t = norm(c->topic);
    const auto it = wanted.find(t);
    if (it == wanted.end()) continue;
    if (c->datatype != it->second->type) {
      refuse(format("topic %s in %s has type %s, expected %s", t.c_str(), path.c_str(),
                    c->datatype.c_str(), it->second->type.c_str()));
    }
    topics.push_back(c->topic);
  }

  // The messages, in the bag's order; stamps per topic, in order of each
  // topic's first message.
  std::vector<std::string> order;
  std::map<std::string, std::vector<double>> stamps;
  std::vector<sensor_msgs::JointState::ConstPtr> states;
  std::vector<coil_winding_sim::WireTension::ConstPtr> measured;
  std::vector<sensor_msgs::PointCloud2::ConstPtr> clouds;
  // The commands per row (in the table's order), read as setpoints: time
  // from the bag's start [s], or why the message cannot be used.
  struct Command {
    double t;
    bool ok;
    cws::Setpoint sp;
    std::string why;
  };
  std::map<const cws::SetpointRow*, std::vector<Command>> commands;
  if (all.size() > 0) {
    rec.start = all.getBeginTime();
    rec.end = all.getEndTime();
  }
  rosbag::View view(bag, rosbag::TopicQuery(topics));
  for (const rosbag::MessageInstance& m : view) {
    const std::string t = norm(m.getTopic());
    const std::string rel = t.substr(std::strlen("machine/"));
    ros::Time stamp;
    const cws::SetpointRow* row = wanted.at(t)->row;
    if (row) {
      visitRowMessages(row->kind, [&](auto type) {
        using M = typename decltype(type)::machine;
        const auto msg = m.instantiate<M>();
        stamp = msg->header.stamp;
        Command c{0.0, false, cws::Setpoint(), ""};
        c.ok = setpointOf(*msg, frames, c.sp, c.why);
        c.t = (stamp - rec.start).toSec();
        // (A path sample is reached at its stamp.)
        if (c.ok && row->path_sample) c.sp.value = c.t;
        commands[row].push_back(c);
      });
    } else if (rel == "spindle/state") {
      states.push_back(m.instantiate<sensor_msgs::JointState>());
      stamp = states.back()->header.stamp;
    } else if (rel == "tension/measured") {
      measured.push_back(m.instantiate<coil_winding_sim::WireTension>());
      stamp = measured.back()->header.stamp;
    } else {
      clouds.push_back(m.instantiate<sensor_msgs::PointCloud2>());
      stamp = clouds.back()->header.stamp;
    }
    if (!stamps.count(t)) order.push_back(t);
    stamps[t].push_back(stamp.toSec());
  }
  for (const TopicSpec& s : specs) {
    if (s.required && stamps["machine/" + s.rel].empty()) {
      refuse(
          format("topic machine/%s is missing (no messages in %s)", s.rel.c_str(), path.c_str()));
    }
  }
  for (const std::string& t : order) checkStamps(t, stamps[t]);

  // The spindle's angle (compare_bags.py's joint_series, position needed).
  const std::string state_topic = "machine/spindle/state";
  for (std::size_t k = 0; k < states.size(); ++k) {
    const sensor_msgs::JointState& j = *states[k];
    const auto it = std::find(j.name.begin(), j.name.end(), kJoint);
    if (it == j.name.end()) {
      refuse(format("topic %s: message %zu (stamp %.6f s) has no joint '%s' (names: %s)",
                    state_topic.c_str(), k, j.header.stamp.toSec(), kJoint,
                    pythonList(j.name).c_str()));
    }
  }
  for (std::size_t k = 0; k < states.size(); ++k) {
    const sensor_msgs::JointState& j = *states[k];
    const std::size_t i = std::find(j.name.begin(), j.name.end(), kJoint) - j.name.begin();
    if (i >= j.position.size() || std::isnan(j.position[i])) {
      refuse(format("topic %s: message %zu has no position for joint '%s'", state_topic.c_str(), k,
                    kJoint));
    }
    rec.measured.spindle_t_s.push_back((j.header.stamp - rec.start).toSec());
    rec.measured.spindle_angle_rad.push_back(j.position[i]);
  }
  if (states.size() < kMinSamples) {
    refuse(format("too few samples to align: %s has %zu (need %d)", state_topic.c_str(),
                  states.size(), kMinSamples));
  }
  if (measured.size() < kMinSamples) {
    refuse(format("too few samples to align: machine/tension/measured has %zu (need %d)",
                  measured.size(), kMinSamples));
  }
  for (const auto& m : measured) {
    rec.measured.tension_t_s.push_back((m->header.stamp - rec.start).toSec());
    rec.measured.tension_N.push_back(m->tension);
  }
  for (const auto& c : clouds)
    rec.measured.profiles.push_back(profileCloud(*c, (c->header.stamp - rec.start).toSec()));

  // Commands, refused one by one as the node refuses them: a message that
  // cannot be read, a value beyond its row's limit.
  for (const cws::SetpointRow& row : cws::setpointTable()) {
    const auto it = commands.find(&row);
    if (it == commands.end()) continue;
    const std::string topic = row.machine_topic;
    for (const Command& c : it->second) {
      if (!c.ok) {
        rec.refused.push_back("refused " + topic + ": " + c.why);
        continue;
      }
      const std::string why = row.refusal ? row.refusal(limits, c.sp) : "";
      if (!why.empty()) {
        rec.refused.push_back("refused " + topic + " " + cws::formatNumber(c.sp.value) + " " +
                              row.unit + ", which " + why);
        continue;
      }
      rec.commands.emplace_back(c.t, c.sp);
    }
  }
  return rec;
}

}  // namespace cws_ros
