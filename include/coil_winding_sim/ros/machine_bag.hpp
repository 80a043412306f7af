// A winding machine's recording (docs/MACHINE_INTERFACE.md) read from its
// bag with rosbag's C++ API, no master needed: its commands, to replay them
// through the simulation (offline_replay.hpp), and what it measured, to
// compare the replay with it (calibration). The bag is checked as
// compare_bags.py checks a machine bag, and refused with the same messages.
#pragma once

#include <ros/time.h>
#include <sensor_msgs/PointCloud2.h>

#include <Eigen/Core>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "coil_winding_sim/core/run/recording_misfit.hpp"
#include "coil_winding_sim/core/scene/setpoint_limits.hpp"
#include "coil_winding_sim/ros/bridge.hpp"

namespace cws_ros {

// A bag that cannot be used; what() names the topic, the message and what is
// wrong, in compare_bags.py's words.
class MachineBagError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A recording's series, times from the bag's start (its first message's
// record time) [s]: the simulation's time 0 in a replay.
struct MachineRecording {
  std::string path;
  ros::Time start, end;  // the first and last messages' record times
  double duration_s() const { return (end - start).toSec(); }

  // Commands: the setpoint table's machine topics (SetpointRow::
  // machine_topic), each as its row's setpoint at its stamp, in the
  // table's order and then the bag's; checked as the node checks them (a
  // refused one is left out, with a line in `refused`).
  std::vector<std::pair<double, cws::Setpoint>> commands;
  std::vector<std::string> refused;

  // Measurements: machine/spindle/state, machine/tension/measured,
  // machine/profile.
  cws::RecordedSeries measured;
};

// A profile cloud's finite points and stand-off, any field type; throws
// MachineBagError for a cloud without x, y or z.
cws::ProfileCloud profileCloud(const sensor_msgs::PointCloud2& msg, double t_s);

// Reads and checks `path`. Throws MachineBagError, as compare_bags.py
// refuses a machine bag: no such bag, an unreadable one, a topic of the
// wrong type, a required topic missing (machine/spindle/state,
// machine/tension/measured, and for a replay machine/spindle/command and
// machine/tension/command), header stamps unset or not strictly
// increasing, no joint `spindle` or no angle in the spindle's state, fewer
// than 10 spindle or tension samples. Commands beyond `limits` are refused
// one by one, as the node refuses them.
MachineRecording readMachineBag(const std::string& path, const cws::SetpointLimits& limits,
                                const Frames& frames);

}  // namespace cws_ros
