// The winding_cell node's options: its private parameters (~name), read in
// one place and validated in one place, as a plain struct (the node, its
// tests and a launch file's reader share it).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "coil_winding_sim/core/scene/scene.hpp"
#include "coil_winding_sim/ros/bridge.hpp"

namespace ros {
class NodeHandle;
}

namespace cws_ros {

struct NodeOptions {
  std::string scene;                   // ~scene: scene file (empty: the defaults)
  std::string scene_base_dir;          // ~scene_base_dir: what a relative ~scene is relative to
  std::vector<std::string> overrides;  // ~overrides: key.path=value
  double real_time_factor = 1.0;       // ~real_time_factor; 0: as fast as possible
  double state_rate_hz = 20.0;         // ~state_rate: wire_state, metrics
  // ~tf_rate: TF and joint_states on a grid of simulated time [Hz]; 0: ten
  // a revolution at the scene's process.max_core_speed_rpm (frameRateHz).
  double tf_rate_hz = 0.0;
  double marker_rate_hz = 10.0;         // ~marker_rate
  double wire_rate_hz = 5.0;            // ~wire_rate: wire_state_compact (recordings) [Hz]
  double profile_turns = 2.0;           // ~profile_turns: sim/profile's last turns; 0: all
  bool publish_clock = false;           // ~publish_clock: the simulated time as /clock
  bool publish_tf = true;               // ~publish_tf: false when robot_state_publisher does
  double force_color_max_N = 0.0;       // ~force_color_max: red [N]; 0: 2 x the tension at start
  std::string coil_color = "layer";     // ~coil_color: the wound wire by layer or enamel_risk
  double profile_magnification = 10.0;  // ~profile_magnification: 0 hides the profile marker
  // ~stop_at_end: hold at the job's end (scripted runs); false: the cell
  // runs until it is stopped, feeding wire while the core turns.
  bool stop_at_end = false;
  bool exit_at_end = false;  // ~exit_at_end: exit (status 0) at the job's end
  // ~max_points: the storage of live points while the cell runs without a
  // job end (it replaces the scene's supply.max_points). Wire buried under
  // later turns retires from it (WireModel::retireBuriedWire), so a coil
  // of any length fits; the cell holds only when the live wire fills it.
  int max_points = cws::kAutoLivePoints;
  // ~start: "running" (winding at the scene's speed), "paused" (until
  // ~pause false) or "at_rest" (the core at 0 until a speed setpoint).
  std::string start = "running";
  Frames frames;  // ~world_frame, ~core_frame, ~port_frame
  // ~frame_prefix: several cells on one TF tree (multi_spindle.launch): the
  // core and port frames become <prefix>/<frame>; the world frame is shared.
  std::string frame_prefix;
  double setpoint_stamp_tolerance_s = 1.0;  // ~setpoint_stamp_tolerance
  double spindle_rate_hz = 100.0;           // ~spindle_rate: the fast sim/ topics
  double profile_rate_hz = 5.0;             // ~profile_rate: sim/profile
  double port_move_time_s = 0.01;           // ~port_move_time
  bool follow_clock = false;                // ~follow_clock: replay a machine bag
  std::string machine_bag;                  // ~machine_bag
  double replay_lag_s = 0.05;               // ~replay_lag
  bool machine_inputs = false;              // ~machine_inputs
  double wait_for_subscribers_s = 0.0;      // ~wait_for_subscribers [s of wall time]
  bool error_estimate = false;              // ~error_estimate
};

// Reads the private parameters; a missing one keeps its default
// (default_scene for ~scene).
NodeOptions readNodeOptions(const ros::NodeHandle& pnh, const std::string& default_scene);

// TF and joint_states' rate [Hz]: ~tf_rate, or ten a revolution at the
// scene's largest core speed (and never below ~state_rate).
double frameRateHz(const NodeOptions& o, const cws::Scene& scene);

// Throws std::invalid_argument naming the parameter and what it must be.
// `sim_time`: /use_sim_time is set. With ~follow_clock the target real-time
// factor becomes 0 (as fast as the clock allows).
void validateNodeOptions(NodeOptions& o, bool sim_time);

}  // namespace cws_ros
