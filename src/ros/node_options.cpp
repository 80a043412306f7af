#include "coil_winding_sim/ros/node_options.hpp"

#include <ros/node_handle.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace cws_ros {

NodeOptions readNodeOptions(const ros::NodeHandle& pnh, const std::string& default_scene) {
  NodeOptions o;
  pnh.param<std::string>("scene", o.scene, default_scene);
  pnh.param<std::string>("scene_base_dir", o.scene_base_dir, o.scene_base_dir);
  pnh.param("overrides", o.overrides, std::vector<std::string>{});
  pnh.param("real_time_factor", o.real_time_factor, o.real_time_factor);
  pnh.param("state_rate", o.state_rate_hz, o.state_rate_hz);
  pnh.param("marker_rate", o.marker_rate_hz, o.marker_rate_hz);
  pnh.param("tf_rate", o.tf_rate_hz, o.tf_rate_hz);
  pnh.param("wire_rate", o.wire_rate_hz, o.wire_rate_hz);
  pnh.param("profile_turns", o.profile_turns, o.profile_turns);
  pnh.param("publish_clock", o.publish_clock, o.publish_clock);
  pnh.param("publish_tf", o.publish_tf, o.publish_tf);
  pnh.param("force_color_max", o.force_color_max_N, o.force_color_max_N);
  pnh.param<std::string>("coil_color", o.coil_color, o.coil_color);
  pnh.param("profile_magnification", o.profile_magnification, o.profile_magnification);
  pnh.param("stop_at_end", o.stop_at_end, o.stop_at_end);
  pnh.param("exit_at_end", o.exit_at_end, o.exit_at_end);
  pnh.param("max_points", o.max_points, o.max_points);
  pnh.param<std::string>("start", o.start, o.start);
  pnh.param<std::string>("world_frame", o.frames.world, o.frames.world);
  pnh.param<std::string>("core_frame", o.frames.core, o.frames.core);
  pnh.param<std::string>("port_frame", o.frames.port, o.frames.port);
  pnh.param<std::string>("frame_prefix", o.frame_prefix, o.frame_prefix);
  pnh.param("setpoint_stamp_tolerance", o.setpoint_stamp_tolerance_s, o.setpoint_stamp_tolerance_s);
  pnh.param("spindle_rate", o.spindle_rate_hz, o.spindle_rate_hz);
  pnh.param("profile_rate", o.profile_rate_hz, o.profile_rate_hz);
  pnh.param("port_move_time", o.port_move_time_s, o.port_move_time_s);
  pnh.param("follow_clock", o.follow_clock, o.follow_clock);
  pnh.param<std::string>("machine_bag", o.machine_bag, o.machine_bag);
  pnh.param("replay_lag", o.replay_lag_s, o.replay_lag_s);
  pnh.param("machine_inputs", o.machine_inputs, o.machine_inputs);
  pnh.param("wait_for_subscribers", o.wait_for_subscribers_s, o.wait_for_subscribers_s);
  pnh.param("error_estimate", o.error_estimate, o.error_estimate);
  return o;
}

double frameRateHz(const NodeOptions& o, const cws::Scene& scene) {
  if (o.tf_rate_hz > 0.0) return o.tf_rate_hz;
  const double revolutions_per_s = std::abs(scene.process.max_core_speed_rpm) / 60.0;
  return std::max(o.state_rate_hz, 10.0 * revolutions_per_s);
}

void validateNodeOptions(NodeOptions& o, bool sim_time) {
  // A relative scene path: against ~scene_base_dir (the launch's directory)
  // when given, else the node's working directory (ROS_HOME).
  if (!o.scene.empty() && !o.scene_base_dir.empty() &&
      std::filesystem::path(o.scene).is_relative()) {
    o.scene = (std::filesystem::path(o.scene_base_dir) / o.scene).lexically_normal().string();
  }
  if (!(o.spindle_rate_hz > 0.0) || !(o.profile_rate_hz > 0.0) ||
      !std::isfinite(o.spindle_rate_hz) || !std::isfinite(o.profile_rate_hz)) {
    throw std::invalid_argument("~spindle_rate and ~profile_rate must be positive [Hz]");
  }
  if (!(o.port_move_time_s > 0.0) || !std::isfinite(o.port_move_time_s)) {
    throw std::invalid_argument("~port_move_time must be a positive number [s]");
  }
  if (!(o.replay_lag_s >= 0.0) || !std::isfinite(o.replay_lag_s)) {
    throw std::invalid_argument("~replay_lag must be a finite number >= 0 [s]");
  }
  if (o.follow_clock) {
    if (o.publish_clock) {
      throw std::invalid_argument(
          "~follow_clock follows another node's /clock: set ~publish_clock false");
    }
    if (!sim_time) {
      throw std::invalid_argument("~follow_clock needs /use_sim_time true (rosbag play --clock)");
    }
    o.real_time_factor = 0.0;  // as fast as the clock allows
  }
  if (!(o.real_time_factor >= 0.0) || !std::isfinite(o.real_time_factor)) {
    throw std::invalid_argument("~real_time_factor must be >= 0 (0: as fast as possible)");
  }
  if (!(o.setpoint_stamp_tolerance_s >= 0.0) || !std::isfinite(o.setpoint_stamp_tolerance_s)) {
    throw std::invalid_argument("~setpoint_stamp_tolerance must be a finite number >= 0 [s]");
  }
  if (o.coil_color != "layer" && o.coil_color != "enamel_risk") {
    throw std::invalid_argument("~coil_color must be layer or enamel_risk, not '" + o.coil_color +
                                "'");
  }
  if (!(o.force_color_max_N >= 0.0) || !std::isfinite(o.force_color_max_N)) {
    throw std::invalid_argument(
        "~force_color_max must be >= 0 [N] (0: twice the tension at start)");
  }
  if (!(o.profile_magnification >= 0.0) || !std::isfinite(o.profile_magnification)) {
    throw std::invalid_argument("~profile_magnification must be >= 0 (0: no profile marker)");
  }
  if (o.start != "running" && o.start != "paused" && o.start != "at_rest") {
    throw std::invalid_argument("~start must be running, paused or at_rest, not '" + o.start + "'");
  }
  if (o.exit_at_end && !o.stop_at_end && !o.follow_clock) {
    throw std::invalid_argument(
        "~exit_at_end needs a job that ends: set ~stop_at_end true (or leave ~exit_at_end false)");
  }
  if (!(o.state_rate_hz > 0.0) || !(o.marker_rate_hz > 0.0) || !std::isfinite(o.state_rate_hz) ||
      !std::isfinite(o.marker_rate_hz)) {
    throw std::invalid_argument("~state_rate and ~marker_rate must be positive [Hz]");
  }
  if (!(o.wire_rate_hz > 0.0) || !std::isfinite(o.wire_rate_hz)) {
    throw std::invalid_argument("~wire_rate must be positive [Hz]");
  }
  if (!(o.profile_turns >= 0.0) || !std::isfinite(o.profile_turns)) {
    throw std::invalid_argument("~profile_turns must be >= 0 (0: the whole wound wire)");
  }
  if (!(o.tf_rate_hz >= 0.0) || !std::isfinite(o.tf_rate_hz)) {
    throw std::invalid_argument(
        "~tf_rate must be >= 0 [Hz] (0: ten a revolution at process.max_core_speed_rpm)");
  }
  // The cell's own frames under a prefix (as tf2 names them: no leading
  // slash); the world stays shared.
  while (!o.frame_prefix.empty() && o.frame_prefix.back() == '/') o.frame_prefix.pop_back();
  if (!o.frame_prefix.empty()) {
    if (o.frame_prefix.front() == '/' ||
        o.frame_prefix.find_first_of(" \t\n\"'") != std::string::npos) {
      throw std::invalid_argument("~frame_prefix '" + o.frame_prefix +
                                  "' must be a frame name without a leading '/' or spaces, "
                                  "e.g. spindle1");
    }
    o.frames.core = o.frame_prefix + "/" + o.frames.core;
    o.frames.port = o.frame_prefix + "/" + o.frames.port;
  }
  if (o.max_points < 2 || o.max_points > cws::kMaxScenePoints) {
    throw std::invalid_argument("~max_points must be 2 to " + std::to_string(cws::kMaxScenePoints) +
                                " points, not " + std::to_string(o.max_points));
  }
}

}  // namespace cws_ros
