// winding_cell: the simulated winding cell as a ROS node.
//
// A thin shell over the simulation core: the simulation advances in this
// process's main thread in short chunks (at most ~10 ms of wall time each),
// paced to a target real-time factor; setpoints and services are served by
// an AsyncSpinner between chunks, so none waits behind a long computation.
// All conversions to messages and TF live in the bridge (bridge.hpp).
//
// Replay mode (~follow_clock): the simulated time follows the ROS clock
// that `rosbag play --clock` publishes, from the machine bag's start
// (~machine_bag) up to (clock - origin - ~replay_lag), never beyond; the
// setpoints are queued by stamp and applied when the simulated time reaches
// them (steps end there), port samples are handed to the simulation ahead
// of time as a path, and the `sim/` topics are published on a grid of
// simulated time: the replay is the same whatever the pace. At the bag's
// end the node shuts down.
#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <std_srvs/SetBool.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/transform_broadcaster.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <deque>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "coil_winding_sim/CoreSpeedSetpoint.h"
#include "coil_winding_sim/Restore.h"
#include "coil_winding_sim/RunUntil.h"
#include "coil_winding_sim/Snapshot.h"
#include "coil_winding_sim/TensionSetpoint.h"
#include "coil_winding_sim/ros/bridge.hpp"
#include "coil_winding_sim/ros/job_error_estimate.hpp"
#include "coil_winding_sim/ros/snapshot_bag.hpp"
#include "coil_winding_sim/ros/snapshot_reader.hpp"

#ifndef CWS_DEFAULT_SCENE
#define CWS_DEFAULT_SCENE ""
#endif

namespace {

using Clock = std::chrono::steady_clock;
double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

// Wall-time limit of reading a snapshot in the reader process [s].
constexpr double kRestoreTimeout = 20.0;

// This executable, which also reads snapshots (main: --read-snapshot). The
// link of the process itself: it still works after a rebuild replaced the file.
const char* const kThisExecutable = "/proc/self/exe";

class WindingCell {
 public:
  WindingCell(ros::NodeHandle nh, ros::NodeHandle pnh) : nh_(nh), pnh_(pnh), diagnostics_(nh, pnh) {
    pnh_.param<std::string>("scene", scene_path_, CWS_DEFAULT_SCENE);
    pnh_.param("overrides", overrides_, std::vector<std::string>{});
    pnh_.param("real_time_factor", target_rtf_, 1.0);
    pnh_.param("state_rate", state_rate_, 20.0);
    pnh_.param("marker_rate", marker_rate_, 10.0);
    pnh_.param("publish_clock", publish_clock_, false);
    pnh_.param("stop_at_end", stop_at_end_, true);
    pnh_.param<std::string>("world_frame", frames_.world, "world");
    pnh_.param<std::string>("core_frame", frames_.core, "core");
    pnh_.param<std::string>("port_frame", frames_.port, "supply_port");
    pnh_.param("setpoint_stamp_tolerance", stamp_tolerance_, 1.0);
    pnh_.param("spindle_rate", spindle_rate_, 100.0);
    pnh_.param("profile_rate", profile_rate_, 5.0);
    pnh_.param("port_move_time", port_move_time_, 0.01);
    pnh_.param("follow_clock", follow_clock_, false);
    pnh_.param<std::string>("machine_bag", machine_bag_, "");
    pnh_.param("replay_lag", replay_lag_, 0.05);
    pnh_.param("machine_inputs", machine_inputs_, false);
    pnh_.param("wait_for_subscribers", wait_subscribers_s_, 0.0);
    pnh_.param("error_estimate", error_estimate_, false);
    node_start_ = Clock::now();
    if (!(spindle_rate_ > 0.0) || !(profile_rate_ > 0.0) || !std::isfinite(spindle_rate_) ||
        !std::isfinite(profile_rate_)) {
      throw std::invalid_argument("~spindle_rate and ~profile_rate must be positive [Hz]");
    }
    if (!(port_move_time_ > 0.0) || !std::isfinite(port_move_time_)) {
      throw std::invalid_argument("~port_move_time must be a positive number [s]");
    }
    if (!(replay_lag_ >= 0.0) || !std::isfinite(replay_lag_)) {
      throw std::invalid_argument("~replay_lag must be a finite number >= 0 [s]");
    }
    if (follow_clock_) {
      if (publish_clock_) {
        throw std::invalid_argument(
            "~follow_clock follows another node's /clock: set ~publish_clock false");
      }
      if (!ros::Time::isSimTime()) {
        throw std::invalid_argument("~follow_clock needs /use_sim_time true (rosbag play --clock)");
      }
      target_rtf_ = 0.0;  // as fast as the clock allows
      if (!machine_bag_.empty()) {
        ros::Time start, end;
        cws_ros::bagTimeRange(machine_bag_, start, end);
        origin_ = start;
        have_origin_ = true;
        bag_end_s_ = (end - start).toSec();
      }
    }
    if (!(target_rtf_ >= 0.0) || !std::isfinite(target_rtf_)) {
      throw std::invalid_argument("~real_time_factor must be >= 0 (0: as fast as possible)");
    }
    if (!(stamp_tolerance_ >= 0.0) || !std::isfinite(stamp_tolerance_)) {
      throw std::invalid_argument("~setpoint_stamp_tolerance must be a finite number >= 0 [s]");
    }
    if (!(state_rate_ > 0.0) || !(marker_rate_ > 0.0)) {
      throw std::invalid_argument("~state_rate and ~marker_rate must be positive [Hz]");
    }
    setScene(cws::loadScene(scene_path_, overrides_));
    sim_ = std::make_unique<cws::Simulation>(scene_);
    if (error_estimate_) {
      if (follow_clock_ || !stop_at_end_) {
        ROS_WARN(
            "winding_cell: ~error_estimate needs jobs that end: not with ~follow_clock or "
            "without ~stop_at_end; no estimates");
      } else {
        estimator_ = std::make_unique<cws_ros::JobErrorEstimator>(nh_);
        estimator_->startJob(sim_->saveState());
      }
    }
    speed_setpoint_ = cws::rpmToRadPerSec(scene_.process.core_speed_rpm);
    tension_setpoint_ = scene_.process.tension;

    state_pub_ = nh_.advertise<coil_winding_sim::WireState>("wire_state", 5);
    metrics_pub_ = nh_.advertise<coil_winding_sim::WindingMetrics>("winding_metrics", 5);
    marker_pub_ = nh_.advertise<visualization_msgs::MarkerArray>("wire_markers", 2, true);
    if (publish_clock_) clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
    speed_sub_ = nh_.subscribe("core_speed_setpoint", 100, &WindingCell::onSpeed, this);
    tension_sub_ = nh_.subscribe("tension_setpoint", 100, &WindingCell::onTension, this);
    port_sub_ = nh_.subscribe("port_position_setpoint", 100, &WindingCell::onPort, this);
    if (machine_inputs_) {
      // The machine's commands (docs/MACHINE_INTERFACE.md) as setpoints.
      machine_spindle_sub_ =
          nh_.subscribe("machine/spindle/command", 1000, &WindingCell::onMachineSpindle, this);
      machine_tension_sub_ =
          nh_.subscribe("machine/tension/command", 1000, &WindingCell::onMachineTension, this);
      machine_port_sub_ =
          nh_.subscribe("machine/port/command", 1000, &WindingCell::onMachinePort, this);
    }
    spindle_command_pub_ = nh_.advertise<sensor_msgs::JointState>("sim/spindle/command", 100);
    spindle_state_pub_ = nh_.advertise<sensor_msgs::JointState>("sim/spindle/state", 100);
    tension_command_pub_ =
        nh_.advertise<coil_winding_sim::TensionSetpoint>("sim/tension/command", 100);
    tension_measured_pub_ =
        nh_.advertise<coil_winding_sim::WireTension>("sim/tension/measured", 100);
    port_command_pub_ = nh_.advertise<geometry_msgs::PointStamped>("sim/port/command", 100);
    port_position_pub_ = nh_.advertise<geometry_msgs::PointStamped>("sim/port/position", 100);
    profile_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("sim/profile", 10);
    reset_srv_ = pnh_.advertiseService("reset", &WindingCell::onReset, this);
    pause_srv_ = pnh_.advertiseService("pause", &WindingCell::onPause, this);
    snapshot_srv_ = pnh_.advertiseService("snapshot", &WindingCell::onSnapshot, this);
    restore_srv_ = pnh_.advertiseService("restore", &WindingCell::onRestore, this);
    run_until_srv_ = pnh_.advertiseService("run_until", &WindingCell::onRunUntil, this);

    diagnostics_.setHardwareID("coil_winding_sim");
    diagnostics_.add("simulation", this, &WindingCell::diagnose);
    ROS_INFO("winding_cell: scene '%s', %d points, target real-time factor %g%s",
             scene_path_.c_str(), sim_->model().constants().n, target_rtf_,
             publish_clock_ ? ", publishing /clock" : "");
    if (follow_clock_) {
      if (bag_end_s_) {
        ROS_INFO("winding_cell: replaying '%s': %.6f s from %.9f s, lag %g s", machine_bag_.c_str(),
                 *bag_end_s_, origin_.toSec(), replay_lag_);
      } else {
        ROS_INFO("winding_cell: following /clock from its first value, lag %g s", replay_lag_);
      }
    }
  }

  // The simulation loop; returns when ROS shuts down.
  void run() {
    restartPace();
    auto next_state = Clock::now(), next_marker = Clock::now(), next_clock = Clock::now(),
         next_diagnostics = Clock::now();
    while (ros::ok()) {
      bool done = false;
      {
        std::lock_guard<std::mutex> lock(sim_mutex_);
        applySetpoints();
        drainInputs();
        if (follow_clock_) {
          if (!failed_ && !replay_done_) advanceReplay();
        } else if (!paused_ && !failed_ && !finished()) {
          advanceChunk();
        }
        done = paused_ || failed_ || finished();
        clock_s_ = stamp().toSec();
        // The job's end: its refined twin runs on the estimator's worker.
        if (estimator_ && finished()) estimator_->finishJob(*sim_, compute_s_, stamp());
      }
      const auto now = Clock::now();
      if (publish_clock_ && now >= next_clock) {
        publishClock();
        next_clock = now + std::chrono::milliseconds(1);
      }
      if (now >= next_state) {
        publishState();
        next_state = now + std::chrono::duration_cast<Clock::duration>(
                               std::chrono::duration<double>(1.0 / state_rate_));
      }
      if (now >= next_marker) {
        publishMarkers();
        next_marker = now + std::chrono::duration_cast<Clock::duration>(
                                std::chrono::duration<double>(1.0 / marker_rate_));
      }
      // Once a second of wall time: the updater's own period counts ROS
      // time, with ~publish_clock the simulated time (100 s of wall time
      // between reports at a real-time factor of 0.01).
      if (now >= next_diagnostics) {
        diagnostics_.force_update();
        next_diagnostics = now + std::chrono::seconds(1);
      }
      if (replay_done_) {
        // The bag's end: the last state out, then a clean shutdown (a
        // required node ends the launch, rosbag record closes its bag).
        publishState();
        ROS_INFO("winding_cell: replay done at t = %.6f s (the machine bag's end)", sim_->time());
        ros::shutdown();
        break;
      }
      // Ahead of the target pace (or idle): wait a little.
      const double ahead_s = aheadOfPace();
      if (done || ahead_s > 0.0) {
        std::this_thread::sleep_for(std::chrono::duration<double>(
            done ? 0.005 : std::min(0.005, ahead_s / std::max(target_rtf_, 1e-9))));
      }
    }
  }

 private:
  // ---- pacing ---------------------------------------------------------------
  void restartPace() {
    pace_wall0_ = Clock::now();
    pace_sim0_ = sim_->time();
    rtf_wall_ = pace_wall0_;
    rtf_sim_ = sim_->time();
  }

  // Simulated seconds the run is ahead of the target pace (negative: behind).
  double aheadOfPace() const {
    if (target_rtf_ <= 0.0) return -1.0;
    const double target = pace_sim0_ + target_rtf_ * seconds(Clock::now() - pace_wall0_);
    return sim_->time() - target;
  }

  bool finished() const {
    if (follow_clock_) return replay_done_;
    return stop_at_end_ && sim_->time() >= sim_->endTime();
  }

  // Steps until the pace target, the scene's end, a ~run_until time or
  // ~10 ms of wall time.
  void advanceChunk() {
    const auto start = Clock::now();
    double t_limit = stop_at_end_ ? sim_->endTime() : 1e300;
    if (run_until_) t_limit = std::min(t_limit, *run_until_);
    try {
      publishDue();
      while (sim_->time() < t_limit && aheadOfPace() < 0.0 &&
             Clock::now() - start < std::chrono::milliseconds(10)) {
        feedPort();
        const auto step_start = Clock::now();
        sim_->step(std::min(t_limit, nextPublishTime()));
        compute_s_ += seconds(Clock::now() - step_start);
        publishDue();
      }
    } catch (const std::exception& e) {
      failed_ = true;
      failure_ = e.what();
      ROS_ERROR("winding_cell: the simulation stopped: %s (reset or restore to go on)", e.what());
    }
    if (run_until_ && sim_->time() >= *run_until_) {
      run_until_.reset();
      paused_ = true;
    }
    // Behind the target by more than 50 ms of wall time: not keeping pace.
    keeping_pace_ = target_rtf_ <= 0.0 || aheadOfPace() > -0.05 * target_rtf_;
  }

  // ---- replay (~follow_clock) ----------------------------------------------------
  // Simulated time the replay may advance to now [s]: the clock since the
  // origin less ~replay_lag (so that setpoints stamped up to there have
  // arrived), never beyond the bag's end; the whole bag once its clock has
  // reached the end (or stalled within the lag of it for 5 s of wall time)
  // and 0.5 s of wall time has passed for the last messages to arrive.
  double replayTarget() {
    const ros::Time now = ros::Time::now();
    if (now.isZero()) return -1.0;  // no /clock yet
    if (!have_origin_) {
      origin_ = now;
      have_origin_ = true;
    }
    const auto wall = Clock::now();
    if (now != last_clock_) {
      last_clock_ = now;
      last_clock_wall_ = wall;
    }
    const double clock_s = (now - origin_).toSec();
    double target = clock_s - replay_lag_;
    if (bag_end_s_) {
      const double end = *bag_end_s_;
      const bool at_end = clock_s >= end - 1e-9;
      const bool stalled =
          clock_s >= end - replay_lag_ - 1e-9 && seconds(wall - last_clock_wall_) > 5.0;
      if ((at_end || stalled) && !end_seen_) {
        end_seen_ = true;
        end_seen_wall_ = wall;
      }
      if (end_seen_ && seconds(wall - end_seen_wall_) >= 0.5) target = end;
      target = std::min(target, end);
    }
    return target;
  }

  // Before the replay's first output: every sim/ topic has a subscriber
  // (rosbag record), or ~wait_for_subscribers of wall time has passed since
  // the node started. Waiting costs nothing but wall time: the steps do not
  // depend on the pace.
  bool recorderReady() {
    if (replay_started_) return true;
    const bool all = spindle_command_pub_.getNumSubscribers() > 0 &&
                     spindle_state_pub_.getNumSubscribers() > 0 &&
                     tension_command_pub_.getNumSubscribers() > 0 &&
                     tension_measured_pub_.getNumSubscribers() > 0 &&
                     port_command_pub_.getNumSubscribers() > 0 &&
                     port_position_pub_.getNumSubscribers() > 0 &&
                     profile_pub_.getNumSubscribers() > 0;
    if (!all && seconds(Clock::now() - node_start_) < wait_subscribers_s_) return false;
    if (!all) {
      ROS_WARN(
          "winding_cell: replay starts with sim/ topics nobody subscribed to after %g s "
          "(~wait_for_subscribers)",
          wait_subscribers_s_);
    }
    replay_started_ = true;
    return true;
  }

  // Steps towards replayTarget() for at most ~10 ms of wall time, ending
  // steps at setpoint stamps and at the publishing grid.
  void advanceReplay() {
    const double target = replayTarget();
    if (target < 0.0) return;  // no clock yet, or not yet past the lag
    if (!recorderReady()) return;
    const auto start = Clock::now();
    try {
      applyDue();
      publishDue();
      while (sim_->time() < target && Clock::now() - start < std::chrono::milliseconds(10)) {
        feedPort();
        // Steps end at events only (setpoints, the publishing grid, the
        // bag's end), never at the clock: a step that would end beyond the
        // clock's target waits for it. So the steps are the same whatever
        // the pace.
        double limit = nextPublishTime();
        if (bag_end_s_) limit = std::min(limit, *bag_end_s_);
        if (!pending_.empty()) limit = std::min(limit, pending_.begin()->first);
        // Port samples still waiting for room: not past the queued path.
        if (!port_queue_.empty()) limit = std::min(limit, sim_->portCommandEnd());
        const double t = sim_->time();
        if (!(limit > t) || std::min(limit, t + sim_->stepper().nextStep()) > target) break;
        sim_->step(limit);
        applyDue();
        publishDue();
      }
    } catch (const std::exception& e) {
      failed_ = true;
      failure_ = e.what();
      ROS_ERROR("winding_cell: the simulation stopped: %s (reset or restore to go on)", e.what());
    }
    if (bag_end_s_ &&
        sim_->time() >= *bag_end_s_ - cws::PortTrajectory::timeTolerance(*bag_end_s_)) {
      replay_done_ = true;
    }
  }

  // Moves the setpoints the callbacks received into the loop's queues (with
  // ~follow_clock once the origin is known): speed and tension by the
  // simulated time of their stamp (zero: now), port samples in arrival
  // order (stamps only grow: admitStamp drops older ones).
  void drainInputs() {
    std::lock_guard<std::mutex> lock(input_mutex_);
    if (follow_clock_ && !have_origin_) return;
    for (const Incoming& in : incoming_) {
      const double t_s = in.stamp.isZero() ? -std::numeric_limits<double>::infinity()
                                           : (in.stamp - origin_).toSec();
      pending_.emplace(t_s, in);  // after equal times: arrival order kept
    }
    incoming_.clear();
    for (const IncomingPort& in : incoming_port_) {
      double t_s = std::numeric_limits<double>::quiet_NaN();  // reached ~port_move_time from now
      if (follow_clock_ && !in.stamp.isZero()) {
        t_s = (in.stamp - origin_).toSec();
      } else if (publish_clock_ && in.stamp.toSec() > clock_offset_ + sim_->time()) {
        t_s = in.stamp.toSec() - clock_offset_;
      }
      port_queue_.push_back({t_s, in.p_world, in.topic});
    }
    incoming_port_.clear();
  }

  // Applies the queued speed and tension setpoints whose time has come.
  void applyDue() {
    const double t = sim_->time();
    const double tol = cws::PortTrajectory::timeTolerance(t);
    while (!pending_.empty() && pending_.begin()->first <= t + tol) {
      const Incoming& in = pending_.begin()->second;
      if (in.tension) {
        tension_setpoint_ = in.value;
        sim_->setSupplyTension(in.value);
        if (estimator_) estimator_->inputs().supplyTension(t, in.value);
      } else {
        speed_setpoint_ = in.value;
        sim_->setCoreSpeed(in.value);
        if (estimator_) estimator_->inputs().coreSpeed(t, in.value);
      }
      pending_.erase(pending_.begin());
    }
  }

  // Hands queued port samples to the simulation's path while it has room.
  void feedPort() {
    while (!port_queue_.empty() && sim_->portCommandRoom() > 1) {
      const PortSample& s = port_queue_.front();
      const double t_s = std::isnan(s.t_s) ? sim_->time() + port_move_time_ : s.t_s;
      try {
        sim_->setPortCommand(s.p_world, t_s);
        if (estimator_) estimator_->inputs().portCommand(sim_->time(), s.p_world, t_s);
      } catch (const std::invalid_argument& e) {
        warn(port_gate_.value_warning, "refused " + s.topic + ": " + e.what());
      }
      port_queue_.pop_front();
    }
  }

  // ---- the sim/ topics on a grid of simulated time ---------------------------------
  double nextPublishTime() const { return std::min(next_fast_s_, next_profile_s_); }

  // Publishes what is due at the simulated time and moves the grid on.
  void publishDue() {
    const double t = sim_->time();
    const double tol = cws::PortTrajectory::timeTolerance(t);
    if (t >= next_fast_s_ - tol) {
      const ros::Time st = stamp();
      spindle_command_pub_.publish(cws_ros::toSpindleCommand(*sim_, st));
      spindle_state_pub_.publish(cws_ros::toSpindleState(*sim_, st));
      if (sim_->model().supply()) {
        tension_command_pub_.publish(cws_ros::toTensionCommand(*sim_, st));
        tension_measured_pub_.publish(cws_ros::toTensionMeasured(*sim_, st));
      }
      geometry_msgs::PointStamped port;
      if (cws_ros::toPortPosition(*sim_, st, frames_, port)) {
        port_command_pub_.publish(port);
        port_position_pub_.publish(port);
      }
      while (next_fast_s_ <= t + tol)
        next_fast_s_ = static_cast<double>(++fast_index_) / spindle_rate_;
    }
    if (t >= next_profile_s_ - tol) {
      if (sim_->model().core()) profile_pub_.publish(cws_ros::toProfile(*sim_, stamp(), frames_));
      while (next_profile_s_ <= t + tol) {
        next_profile_s_ = static_cast<double>(++profile_index_) / profile_rate_;
      }
    }
  }

  // The grid from the present simulated time on (a new run).
  void restartPublishGrid() {
    const double t = sim_->time();
    fast_index_ = static_cast<long>(std::ceil(t * spindle_rate_));
    profile_index_ = static_cast<long>(std::ceil(t * profile_rate_));
    next_fast_s_ = static_cast<double>(fast_index_) / spindle_rate_;
    next_profile_s_ = static_cast<double>(profile_index_) / profile_rate_;
  }

  // ---- time stamps -------------------------------------------------------------
  // With ~publish_clock the node's clock is the simulated time plus an offset
  // that keeps it monotonic across reset and restore; otherwise ROS time.
  ros::Time stamp() const {
    if (follow_clock_) return origin_ + ros::Duration(sim_->time());
    if (publish_clock_) return ros::Time(std::max(0.0, clock_offset_ + sim_->time()));
    return ros::Time::now();
  }

  void publishClock() {
    rosgraph_msgs::Clock c;
    {
      std::lock_guard<std::mutex> lock(sim_mutex_);
      c.clock = stamp();
    }
    clock_pub_.publish(c);
  }

  // ---- publishing --------------------------------------------------------------
  void publishState() {
    std::lock_guard<std::mutex> lock(sim_mutex_);
    const ros::Time t = stamp();
    const auto now = Clock::now();
    const double dw = seconds(now - rtf_wall_);
    if (dw > 0.0) measured_rtf_ = (sim_->time() - rtf_sim_) / dw;
    rtf_wall_ = now;
    rtf_sim_ = sim_->time();
    cws_ros::Pace pace;
    pace.real_time_factor = measured_rtf_;
    pace.target_real_time_factor = target_rtf_;
    pace.keeping_pace = keeping_pace_ || paused_ || finished();
    if (state_pub_.getNumSubscribers() > 0) {
      state_pub_.publish(cws_ros::toWireState(*sim_, t, frames_));
    }
    metrics_pub_.publish(cws_ros::toMetrics(*sim_, t, frames_, pace));
    geometry_msgs::TransformStamped tf;
    if (cws_ros::coreTransform(*sim_, t, frames_, tf)) tf_.sendTransform(tf);
    if (cws_ros::portTransform(*sim_, t, frames_, tf)) tf_.sendTransform(tf);
  }

  void publishMarkers() {
    std::lock_guard<std::mutex> lock(sim_mutex_);
    if (send_delete_all_) {
      marker_pub_.publish(cws_ros::deleteAllMarkers(stamp(), frames_));
      send_delete_all_ = false;
    }
    const double scale = std::max(1.0, 1.5 * tension_setpoint_);
    marker_pub_.publish(cws_ros::toMarkers(*sim_, stamp(), frames_, scale));
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
    std::lock_guard<std::mutex> lock(sim_mutex_);
    stat.add("simulated time [s]", sim_->time());
    stat.add("real-time factor", measured_rtf_);
    stat.add("target real-time factor", target_rtf_);
    stat.add("step size [s]", sim_->stepper().lastStep());
    stat.add("max constraint residual", sim_->model().maxConstraintResidual());
    stat.add("points", sim_->model().constants().n);
    if (estimator_) estimator_->diagnose(stat);
    if (failed_) {
      stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "stopped: " + failure_);
    } else if (paused_) {
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "paused");
    } else if (finished()) {
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "scene finished (process.turns)");
    } else if (!keeping_pace_) {
      stat.summaryf(diagnostic_msgs::DiagnosticStatus::WARN,
                    "not keeping pace: real-time factor %.3g, target %.3g", measured_rtf_,
                    target_rtf_);
    } else {
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "running");
    }
  }

  // Warnings at most once a second of wall time, with the number left out.
  // (ROS_WARN_THROTTLE counts ROS time: with ~publish_clock that is the
  // simulated time, and one second of it can take minutes.)
  class WallThrottle {
   public:
    // True when a warning is due; `skipped` is the number suppressed since.
    bool due(int& skipped) {
      std::lock_guard<std::mutex> lock(mutex_);
      const auto now = Clock::now();
      if (warned_ && now - last_ < std::chrono::seconds(1)) {
        ++skipped_;
        return false;
      }
      warned_ = true;
      last_ = now;
      skipped = skipped_;
      skipped_ = 0;
      return true;
    }

   private:
    std::mutex mutex_;
    bool warned_ = false;
    Clock::time_point last_;
    int skipped_ = 0;
  };

  static void warn(WallThrottle& throttle, const std::string& text) {
    int skipped = 0;
    if (!throttle.due(skipped)) return;
    if (skipped > 0) {
      ROS_WARN("winding_cell: %s (and %d more like it since the last report)", text.c_str(),
               skipped);
    } else {
      ROS_WARN("winding_cell: %s", text.c_str());
    }
  }

  static std::string number(double v, const char* format = "%g") {
    char text[64];
    std::snprintf(text, sizeof text, format, v);
    return text;
  }

  // A setpoint topic's memory of stamps and its warnings.
  struct SetpointGate {
    ros::Time last_stamp;  // of the last applied setpoint (stamp_mutex_)
    WallThrottle value_warning, future_warning, order_warning;
  };

  // ---- setpoints ---------------------------------------------------------------
  // Checked here, applied by the simulation loop between chunks. Neither
  // takes the simulation's lock: a burst of setpoints cannot hold up the
  // simulation or the services.
  void onSpeed(const coil_winding_sim::CoreSpeedSetpoint::ConstPtr& msg) {
    speedInput("core_speed_setpoint", msg->angular_velocity, msg->header.stamp, speed_gate_);
  }

  void onTension(const coil_winding_sim::TensionSetpoint::ConstPtr& msg) {
    tensionInput("tension_setpoint", msg->tension, msg->header.stamp, tension_gate_);
  }

  void onPort(const geometry_msgs::PointStamped::ConstPtr& msg) {
    portInput("port_position_setpoint", *msg, port_gate_);
  }

  // The machine's commands (~machine_inputs): converted by the bridge, then
  // checked as the setpoint topics are.
  void onMachineSpindle(const sensor_msgs::JointState::ConstPtr& msg) {
    double w = 0.0;
    std::string why;
    if (!cws_ros::spindleVelocity(*msg, w, why)) {
      warn(machine_spindle_gate_.value_warning, "refused machine/spindle/command: " + why +
                                                    "; keeping " + number(speed_setpoint_) +
                                                    " rad/s");
      return;
    }
    speedInput("machine/spindle/command", w, msg->header.stamp, machine_spindle_gate_);
  }

  void onMachineTension(const coil_winding_sim::TensionSetpoint::ConstPtr& msg) {
    tensionInput("machine/tension/command", msg->tension, msg->header.stamp, machine_tension_gate_);
  }

  void onMachinePort(const geometry_msgs::PointStamped::ConstPtr& msg) {
    portInput("machine/port/command", *msg, machine_port_gate_);
  }

  void speedInput(const char* topic, double w, const ros::Time& stamp, SetpointGate& gate) {
    const double limit = max_speed_;
    if (!std::isfinite(w) || std::abs(w) > limit) {
      warn(gate.value_warning, "refused " + std::string(topic) + " " + number(w) +
                                   " rad/s (finite, |w| <= " + number(limit) +
                                   " rad/s = process.max_core_speed_rpm); keeping " +
                                   number(speed_setpoint_) + " rad/s");
      return;
    }
    if (admitStamp(topic, stamp, gate)) deliver(false, w, stamp);
  }

  void tensionInput(const char* topic, double f, const ros::Time& stamp, SetpointGate& gate) {
    const double limit = max_tension_;
    if (!std::isfinite(f) || f < 0.0 || f > limit) {
      warn(gate.value_warning,
           "refused " + std::string(topic) + " " + number(f) + " N (finite, 0 .. " + number(limit) +
               " N = process.max_tension); keeping " + number(tension_setpoint_) + " N");
      return;
    }
    if (admitStamp(topic, stamp, gate)) deliver(true, f, stamp);
  }

  // A port position: finite, in the world frame, stamps as for the other
  // setpoints; the simulation refuses a port inside the core or in the past
  // (feedPort) with a warning.
  void portInput(const char* topic, const geometry_msgs::PointStamped& msg, SetpointGate& gate) {
    Eigen::Vector3d p_world;
    std::string why;
    if (!cws_ros::portPoint(msg, frames_, p_world, why)) {
      warn(gate.value_warning, "refused " + std::string(topic) + ": " + why);
      return;
    }
    if (!admitStamp(topic, msg.header.stamp, gate)) return;
    std::lock_guard<std::mutex> lock(input_mutex_);
    incoming_port_.push_back({p_world, msg.header.stamp, topic});
  }

  // An admitted speed or tension: applied between chunks, or with
  // ~follow_clock queued to be applied at its stamp.
  void deliver(bool tension, double value, const ros::Time& stamp) {
    if (follow_clock_) {
      std::lock_guard<std::mutex> lock(input_mutex_);
      incoming_.push_back({tension, value, stamp});
      return;
    }
    (tension ? tension_setpoint_ : speed_setpoint_) = value;
    setpoints_changed_ = true;
  }

  // The node's clock: its own /clock with ~publish_clock, else ROS time.
  ros::Time nodeClock() const {
    return publish_clock_ ? ros::Time(clock_s_.load()) : ros::Time::now();
  }

  // Setpoint stamps (README, "Setpoint stamps"): zero is always admitted; a
  // stamp more than ~setpoint_stamp_tolerance ahead of the node's clock is
  // refused, and so is one older than that of the topic's last applied
  // setpoint. An admitted stamp becomes the topic's last.
  bool admitStamp(const char* topic, const ros::Time& stamp, SetpointGate& gate) {
    if (stamp.isZero()) return true;
    std::lock_guard<std::mutex> lock(stamp_mutex_);
    const ros::Time clock = nodeClock();
    // The clock went back (another node's /clock, e.g. a looping bag):
    // stamps of the new time line must not lose against the old one.
    if (clock < last_clock_seen_) clearStamps();
    last_clock_seen_ = clock;
    // Without ~publish_clock and before the first /clock, ROS time is zero:
    // there is no clock to compare with yet.
    const bool have_clock = publish_clock_ || !clock.isZero();
    if (have_clock && stamp.toSec() > clock.toSec() + stamp_tolerance_) {
      warn(gate.future_warning, "refused " + std::string(topic) + " stamped " +
                                    number(stamp.toSec(), "%.6f") + " s: more than " +
                                    number(stamp_tolerance_) +
                                    " s (~setpoint_stamp_tolerance) ahead of the node's clock " +
                                    number(clock.toSec(), "%.6f") + " s");
      return false;
    }
    if (stamp < gate.last_stamp) {
      warn(gate.order_warning, "dropped " + std::string(topic) + " stamped " +
                                   number(stamp.toSec(), "%.6f") +
                                   " s: out of order, older than the last applied one (" +
                                   number(gate.last_stamp.toSec(), "%.6f") + " s)");
      return false;
    }
    gate.last_stamp = stamp;
    return true;
  }

  // Forgets the stamps of the last applied setpoints (stamp_mutex_ held).
  void clearStamps() {
    for (SetpointGate* g : {&speed_gate_, &tension_gate_, &port_gate_, &machine_spindle_gate_,
                            &machine_tension_gate_, &machine_port_gate_}) {
      g->last_stamp = ros::Time();
    }
  }

  // Makes `scene` the scene in use (its limits apply to the setpoints).
  void setScene(const cws::Scene& scene) {
    scene_ = scene;
    max_speed_ = cws::rpmToRadPerSec(scene_.process.max_core_speed_rpm);
    max_tension_ = scene_.process.max_tension;
  }

  void applySetpoints() {
    if (!setpoints_changed_.exchange(false)) return;
    const double speed = speed_setpoint_, tension = tension_setpoint_;
    sim_->setCoreSpeed(speed);
    sim_->setSupplyTension(tension);
    if (estimator_) {
      estimator_->inputs().coreSpeed(sim_->time(), speed);
      estimator_->inputs().supplyTension(sim_->time(), tension);
    }
  }

  // ---- services ----------------------------------------------------------------
  bool onReset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    try {
      // A copy of the scene: a concurrent restore may replace it.
      cws::Scene scene;
      {
        std::lock_guard<std::mutex> lock(sim_mutex_);
        scene = scene_;
      }
      auto fresh = std::make_unique<cws::Simulation>(scene);
      std::lock_guard<std::mutex> lock(sim_mutex_);
      setScene(scene);
      replace(std::move(fresh));
      speed_setpoint_ = cws::rpmToRadPerSec(scene_.process.core_speed_rpm);
      tension_setpoint_ = scene_.process.tension;
      res.success = true;
      res.message = "reset to the scene's initial state";
    } catch (const std::exception& e) {
      res.success = false;
      res.message = std::string("reset failed: ") + e.what();
    }
    return true;
  }

  bool onPause(std_srvs::SetBool::Request& req, std_srvs::SetBool::Response& res) {
    std::lock_guard<std::mutex> lock(sim_mutex_);
    paused_ = req.data;
    restartPace();
    res.success = true;
    res.message = paused_ ? "paused" : "running";
    return true;
  }

  bool onRunUntil(coil_winding_sim::RunUntil::Request& req,
                  coil_winding_sim::RunUntil::Response& res) {
    std::lock_guard<std::mutex> lock(sim_mutex_);
    if (!std::isfinite(req.time) || req.time <= sim_->time()) {
      res.success = false;
      res.message = "time " + std::to_string(req.time) + " s is not ahead of the simulated time " +
                    std::to_string(sim_->time()) + " s";
      return true;
    }
    run_until_ = req.time;
    paused_ = false;
    restartPace();
    res.success = true;
    res.message = "running until t = " + std::to_string(req.time) + " s, then pausing";
    return true;
  }

  bool onSnapshot(coil_winding_sim::Snapshot::Request& req,
                  coil_winding_sim::Snapshot::Response& res) {
    cws::SimulationState state;
    ros::Time t;
    {
      std::lock_guard<std::mutex> lock(sim_mutex_);
      state = sim_->saveState();
      // The setpoints not yet applied belong to the state too.
      state.model.core[3] = sim_->model().core() ? speed_setpoint_.load() : state.model.core[3];
      if (sim_->model().supply()) state.model.tension_N = tension_setpoint_;
      t = stamp();
    }
    try {
      cws_ros::writeSnapshotBag(req.path, cws_ros::toSnapshotMsg(state, t));
      res.success = true;
      res.message = "snapshot at t = " + std::to_string(state.time_s) + " s written to " + req.path;
    } catch (const std::exception& e) {
      res.success = false;
      res.message = e.what();
    }
    return true;
  }

  bool onRestore(coil_winding_sim::Restore::Request& req,
                 coil_winding_sim::Restore::Response& res) {
    // Read and rebuild outside the lock; swap only a complete simulation.
    // The file is read in a child process: a corrupt bag can crash rosbag's
    // reader or exhaust the memory, which must not take this node with it.
    try {
      const cws::SimulationState state = cws_ros::fromSnapshotMsg(
          cws_ros::readSnapshotBagIsolated(req.path, kThisExecutable, kRestoreTimeout));
      auto restored = cws::Simulation::fromState(state);
      // Its setpoints pass the checks of the setpoint topics.
      const cws::Scene& scene = restored->scene();
      const double speed = state.model.core[3];
      const double speed_limit = cws::rpmToRadPerSec(scene.process.max_core_speed_rpm);
      if (restored->model().core() && std::abs(speed) > speed_limit) {
        throw std::runtime_error("'" + req.path + "': its core speed setpoint " + number(speed) +
                                 " rad/s exceeds its scene's process.max_core_speed_rpm (" +
                                 number(speed_limit) + " rad/s)");
      }
      if (restored->model().supply() && state.model.tension_N > scene.process.max_tension) {
        throw std::runtime_error("'" + req.path + "': its tension " +
                                 number(state.model.tension_N) +
                                 " N exceeds its scene's process.max_tension (" +
                                 number(scene.process.max_tension) + " N)");
      }
      std::lock_guard<std::mutex> lock(sim_mutex_);
      setScene(scene);
      replace(std::move(restored));
      speed_setpoint_ = state.model.core[3];
      tension_setpoint_ = sim_->model().supply() ? state.model.tension_N : scene_.process.tension;
      res.success = true;
      res.message = "restored t = " + std::to_string(state.time_s) + " s from " + req.path;
    } catch (const std::exception& e) {
      res.success = false;
      res.message = std::string("restore failed, state unchanged: ") + e.what();
    }
    return true;
  }

  // Swaps in a new simulation (lock held): the clock stays monotonic, rviz
  // gets a DELETEALL, pacing restarts, the pause state stays, a pending
  // ~run_until is dropped and the setpoint stamps are forgotten (a new run:
  // a client may start its stamps anew).
  void replace(std::unique_ptr<cws::Simulation> next) {
    clock_offset_ += sim_->time() - next->time();
    sim_ = std::move(next);
    clock_s_ = stamp().toSec();
    {
      std::lock_guard<std::mutex> lock(stamp_mutex_);
      clearStamps();
    }
    run_until_.reset();
    failed_ = false;
    failure_.clear();
    send_delete_all_ = true;
    port_queue_.clear();
    restartPublishGrid();
    restartPace();
    compute_s_ = 0.0;
    if (estimator_) estimator_->startJob(sim_->saveState());
  }

  ros::NodeHandle nh_, pnh_;
  std::string scene_path_;
  std::vector<std::string> overrides_;
  double target_rtf_ = 1.0, state_rate_ = 20.0, marker_rate_ = 10.0;
  double stamp_tolerance_ = 1.0;  // [s] of the node's clock
  bool publish_clock_ = false, stop_at_end_ = true;
  cws_ros::Frames frames_;

  std::mutex sim_mutex_;  // guards everything below but the atomics
  cws::Scene scene_;
  std::unique_ptr<cws::Simulation> sim_;
  bool paused_ = false, failed_ = false, keeping_pace_ = true, send_delete_all_ = false;
  std::optional<double> run_until_;  // pause when the simulated time reaches it [s]
  double compute_s_ = 0.0;           // wall time in the present job's steps [s]
  bool error_estimate_ = false;
  std::unique_ptr<cws_ros::JobErrorEstimator> estimator_;  // with ~error_estimate
  std::string failure_;
  double clock_offset_ = 0.0;
  Clock::time_point pace_wall0_, rtf_wall_;
  double pace_sim0_ = 0.0, rtf_sim_ = 0.0, measured_rtf_ = 0.0;
  std::atomic<double> speed_setpoint_{0.0}, tension_setpoint_{0.0};
  std::atomic<bool> setpoints_changed_{false};
  // Limits of the scene in use: |speed| [rad/s], tension [N].
  std::atomic<double> max_speed_{0.0}, max_tension_{0.0};
  // The node's clock with ~publish_clock [s] (read by the setpoint callbacks).
  std::atomic<double> clock_s_{0.0};

  std::mutex stamp_mutex_;  // guards the stamps below
  SetpointGate speed_gate_, tension_gate_, port_gate_, machine_spindle_gate_, machine_tension_gate_,
      machine_port_gate_;
  ros::Time last_clock_seen_;

  // Replay (~follow_clock): the bag's start on the ROS clock and its length
  // [s]; the clock's last value and when it came (wall time).
  bool follow_clock_ = false, machine_inputs_ = false;
  std::string machine_bag_;
  double replay_lag_ = 0.05;  // [s] of the bag's clock
  bool have_origin_ = false, end_seen_ = false, replay_done_ = false, replay_started_ = false;
  double wait_subscribers_s_ = 0.0;  // [s] of wall time
  Clock::time_point node_start_;
  ros::Time origin_, last_clock_;
  std::optional<double> bag_end_s_;
  Clock::time_point last_clock_wall_, end_seen_wall_;

  // Setpoints from the callbacks (input_mutex_), and the loop's queues
  // (sim_mutex_): speed/tension by simulated time, port samples in order.
  struct Incoming {
    bool tension = false;  // else a core speed
    double value = 0.0;    // [N] or [rad/s]
    ros::Time stamp;
  };
  struct IncomingPort {
    Eigen::Vector3d p_world;
    ros::Time stamp;
    std::string topic;
  };
  struct PortSample {
    double t_s;  // simulated time [s]; NaN: ~port_move_time after it is applied
    Eigen::Vector3d p_world;
    std::string topic;
  };
  std::mutex input_mutex_;
  std::vector<Incoming> incoming_;
  std::vector<IncomingPort> incoming_port_;
  std::multimap<double, Incoming> pending_;
  std::deque<PortSample> port_queue_;
  double port_move_time_ = 0.01;  // [s]

  // The sim/ topics' grid of simulated time [s] and rates [Hz].
  double spindle_rate_ = 100.0, profile_rate_ = 5.0;
  long fast_index_ = 0, profile_index_ = 0;
  double next_fast_s_ = 0.0, next_profile_s_ = 0.0;

  ros::Publisher state_pub_, metrics_pub_, marker_pub_, clock_pub_;
  ros::Publisher spindle_command_pub_, spindle_state_pub_, tension_command_pub_,
      tension_measured_pub_, port_command_pub_, port_position_pub_, profile_pub_;
  ros::Subscriber speed_sub_, tension_sub_, port_sub_, machine_spindle_sub_, machine_tension_sub_,
      machine_port_sub_;
  ros::ServiceServer reset_srv_, pause_srv_, snapshot_srv_, restore_srv_, run_until_srv_;
  tf2_ros::TransformBroadcaster tf_;
  diagnostic_updater::Updater diagnostics_;
};

}  // namespace

int main(int argc, char** argv) {
  // The snapshot reader process of ~restore (cws_ros::readSnapshotBagIsolated).
  if (argc == 3 && std::strcmp(argv[1], cws_ros::kReadSnapshotArg) == 0) {
    return cws_ros::snapshotReaderMain(argv[2], cws_ros::kSnapshotReaderFd);
  }
  ros::init(argc, argv, "winding_cell");
  ros::NodeHandle nh, pnh("~");
  std::unique_ptr<WindingCell> cell;
  try {
    cell = std::make_unique<WindingCell>(nh, pnh);
  } catch (const std::exception& e) {
    ROS_FATAL("winding_cell: %s", e.what());
    return 2;
  }
  ros::AsyncSpinner spinner(2);
  spinner.start();
  cell->run();
  spinner.stop();
  return 0;
}
