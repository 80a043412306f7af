// The winding cell's output: the sim/ series and the frames on their grid
// of simulated time, the state, the wire's compact form, the markers, the
// stamps and /clock, and /diagnostics with the warnings behind them
// (winding_cell.hpp).
#include <rosgraph_msgs/Clock.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "coil_winding_sim/core/time_steppers/implicit_stepper.hpp"
#include "coil_winding_sim/ros/bridge.hpp"
#include "coil_winding_sim/ros/winding_cell.hpp"

namespace cws_ros {

// ---- publishing -------------------------------------------------------------

// The sim/ topics due at the simulated time.
void WindingCell::publishDue() {
  PublishGrid::Due due = grid_.take(sim_->time());
  // The core at rest (~start at_rest): the series stand still, so they go
  // out once a second of simulated time, not at their rates.
  if (at_rest_ && !o_.follow_clock) {
    if (sim_->time() < next_rest_sample_s_) due = PublishGrid::Due();
    if (due.fast || due.frames || due.profile) next_rest_sample_s_ = sim_->time() + 1.0;
  }
  if (due.fast) {
    const ros::Time st = stamp();
    spindle_command_pub_.publish(toSpindleCommand(*sim_, st));
    spindle_state_pub_.publish(toSpindleState(*sim_, st));
    if (sim_->model().supply()) {
      tension_command_pub_.publish(toTensionCommand(*sim_, st));
      tension_measured_pub_.publish(toTensionMeasured(*sim_, st));
    }
    geometry_msgs::PointStamped port;
    if (toPortPosition(*sim_, st, o_.frames, port)) {
      port_command_pub_.publish(port);
      port_position_pub_.publish(port);
    }
  }
  if (due.frames) publishFrames();
  if (due.profile && sim_->model().core())
    profile_pub_.publish(toProfile(*sim_, stamp(), o_.frames, o_.profile_turns));
}

// joint_states and the frames' TF, on their grid of simulated time (lock
// held): fast enough that a sampler sees the spindle turn (~tf_rate).
void WindingCell::publishFrames() {
  const ros::Time t = stamp();
  joints_pub_.publish(toJointStates(*sim_, t));
  // The frames: here, or by robot_state_publisher from joint_states.
  if (!o_.publish_tf) return;
  geometry_msgs::TransformStamped tf;
  if (coreTransform(*sim_, t, o_.frames, tf)) tf_.sendTransform(tf);
  if (portTransform(*sim_, t, o_.frames, tf)) tf_.sendTransform(tf);
}

// With ~publish_clock the node's clock is the simulated time plus an offset
// that keeps it monotonic across reset and restore; otherwise ROS time.
ros::Time WindingCell::stamp() const {
  if (o_.follow_clock) return replay_.origin() + ros::Duration(sim_->time());
  if (o_.publish_clock) return ros::Time(std::max(0.0, clock_offset_ + sim_->time()));
  // Another node's /clock (use_sim_time): its time. On the wall clock: the
  // simulated time from the stamps' origin.
  if (ros::Time::isSimTime()) return ros::Time::now();
  return ros::Time(std::max(0.0, stamp_origin_s_ + sim_->time()));
}

void WindingCell::publishClock() {
  rosgraph_msgs::Clock c;
  {
    std::lock_guard<std::mutex> lock(sim_mutex_);
    c.clock = stamp();
  }
  clock_pub_.publish(c);
}

void WindingCell::publishState() {
  std::lock_guard<std::mutex> lock(sim_mutex_);
  const ros::Time t = stamp();
  Pace pace;
  pace.real_time_factor = realTimeFactor();
  pace.target_real_time_factor = pace_.target();
  pace.keeping_pace = keeping_pace_ || paused_ || finished();
  if (state_pub_.getNumSubscribers() > 0) state_pub_.publish(toWireState(*sim_, t, o_.frames));
  coil_winding_sim::WindingMetrics metrics = toMetrics(*sim_, t, o_.frames, pace);
  metrics.job_done = job_done_;
  metrics_pub_.publish(metrics);
  publishWindFeedback();
  // While the cell takes no steps its frames stand still: sent here, at
  // the state's rate, rather than on the grid of simulated time.
  if (paused_ || failed_ || holding()) publishFrames();
}

// The wire's compact form while someone listens (a recorder): the carried
// points not yet sent, the whole wire every kCompactKeyframeS and for a new
// listener.
void WindingCell::publishCompactWire() {
  const uint32_t listeners = compact_pub_.getNumSubscribers();
  const bool more = listeners > compact_subscribers_;
  compact_subscribers_ = listeners;
  if (listeners == 0) return;
  std::lock_guard<std::mutex> lock(sim_mutex_);
  const double now = wallNow();
  if (more || now >= compact_keyframe_s_) {
    carried_sent_ = 0;
    compact_keyframe_s_ = now + kCompactKeyframeS;
  }
  compact_pub_.publish(toWireStateCompact(*sim_, stamp(), o_.frames, carried_sent_));
  carried_sent_ = carriedBlock(*sim_);
}

void WindingCell::publishMarkers() {
  std::lock_guard<std::mutex> lock(sim_mutex_);
  if (send_delete_all_) {
    marker_pub_.publish(deleteAllMarkers(stamp(), o_.frames));
    send_delete_all_ = false;
    retired_markers_sent_ = 0;
  }
  // Retired wire's strips once (rigid on the core), all of them again every
  // kCompactKeyframeS and for a new subscriber (the topic keeps one array).
  const uint32_t listeners = marker_pub_.getNumSubscribers();
  const double now = wallNow();
  if (listeners > marker_subscribers_ || now >= marker_keyframe_s_) {
    retired_markers_sent_ = 0;
    marker_keyframe_s_ = now + kCompactKeyframeS;
  }
  marker_subscribers_ = listeners;
  marker_pub_.publish(toMarkers(*sim_, stamp(), o_.frames, force_max_N_, 10000,
                                retired_markers_sent_, o_.coil_color == "enamel_risk"));
  retired_markers_sent_ = sim_->model().retiredPoints();
  Overlay overlay;
  std::string words;
  overlay.state = cellState(words);
  std::replace(overlay.state.begin(), overlay.state.end(), '_', ' ');
  overlay.pace.real_time_factor = realTimeFactor();
  overlay.pace.target_real_time_factor = pace_.target();
  overlay.pace.keeping_pace = keeping_pace_ || paused_ || finished();
  overlay.winding = !(paused_ || failed_ || holding());
  overlay.tension_setpoint_N = tension_setpoint_;
  overlay.force_max_N = force_max_N_;
  overlay.profile_magnification = o_.profile_magnification;
  overlay.enamel_risk = o_.coil_color == "enamel_risk";
  marker_pub_.publish(toOverlayMarkers(*sim_, stamp(), o_.frames, overlay));
}

void WindingCell::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  std::lock_guard<std::mutex> lock(sim_mutex_);
  const double rtf = realTimeFactor();
  stat.add("simulated time [s]", sim_->time());
  stat.add("real-time factor", rtf);
  stat.add("target real-time factor", pace_.target());
  stat.add("step size [s]", sim_->stepper().lastStep());
  stat.add("max constraint residual", sim_->model().maxConstraintResidual());
  stat.add("points", sim_->model().wirePoints());
  const cws::NewtonCounts* newton = sim_->stepper().newtonCounts();
  if (newton) stat.add("explicit fallback stretches", newton->fallback_stretches);
  stat.add("static friction", sim_->scene().contact.static_friction);
  stat.add("kinetic friction", sim_->scene().contact.kinetic_friction);
  stat.add("damping translational [N s/m^2]", sim_->scene().damping.translational);
  stat.add("damping rotational [N m s/m]", sim_->scene().damping.rotational);
  if (estimator_) estimator_->diagnose(stat);
  if (failed_) {
    stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "stopped: " + failure_);
  } else if (paused_) {
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "paused");
  } else if (job_done_) {
    std::string message;
    cellState(message);
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, message);
  } else if (storage_full_) {
    std::string message;
    cellState(message);
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, message);
  } else if (finished()) {
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "replay done");
  } else if (newton && fallbackRecent()) {
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::WARN,
                  "explicit steps where Newton could not go on (%ld stretches; last: %s)",
                  fallback_seen_, newton->fallback_cause);
  } else if (!keeping_pace_) {
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::WARN,
                  "slow: real-time factor %.3g over the last second, target %.3g; %s", rtf,
                  pace_.target(), slow_cause_.c_str());
  } else if (at_rest_) {
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "at rest until a speed setpoint");
  } else {
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "running");
  }
}

void WindingCell::noteFallback() {
  const cws::NewtonCounts* n = sim_->stepper().newtonCounts();
  const long count = n ? n->fallback_stretches : 0;
  if (count == fallback_seen_) return;
  // A reset or a restore starts the count again (or a method without
  // Newton steps has none): what came before no longer warns.
  if (count < fallback_seen_) {
    fallback_seen_ = count;
    fallback_wall_s_ = -1e300;
    return;
  }
  fallback_seen_ = count;
  fallback_wall_s_ = wallNow();
  char text[256];
  std::snprintf(text, sizeof text,
                "%s: %g ms of explicit steps carry the run on (%ld such stretches so far)",
                n->fallback_cause, 1e3 * cws::ImplicitStepper::kFallbackStretch, fallback_seen_);
  warn(fallback_warning_, text);
}

void WindingCell::warn(WallThrottle& throttle, const std::string& text) const {
  int skipped = 0;
  if (!throttle.due(wallNow(), skipped, text)) return;
  if (skipped > 0) {
    ROS_WARN("winding_cell: %s (and %d more like it since the last report)", text.c_str(), skipped);
  } else {
    ROS_WARN("winding_cell: %s", text.c_str());
  }
}

}  // namespace cws_ros
