// The winding cell's construction and its simulation loop with pacing and
// replay (winding_cell.hpp; what it publishes: winding_cell_publish.cpp).
#include "coil_winding_sim/ros/winding_cell.hpp"

#include <rosgraph_msgs/Clock.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iterator>
#include <thread>

#include "coil_winding_sim/ros/bridge.hpp"
#include "coil_winding_sim/ros/snapshot_bag.hpp"

namespace cws_ros {

namespace {
using Clock = std::chrono::steady_clock;
}  // namespace

double WindingCell::wallNow() const {
  return std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
}

WindingCell::WindingCell(ros::NodeHandle nh, ros::NodeHandle pnh, const NodeOptions& options,
                         std::string this_executable)
    : nh_(nh),
      pnh_(pnh),
      o_(options),
      this_executable_(std::move(this_executable)),
      replay_(options.replay_lag_s, std::nullopt),
      inbox_(options.setpoint_stamp_tolerance_s),
      grid_(options.spindle_rate_hz, options.state_rate_hz, options.profile_rate_hz),
      diagnostics_(nh, pnh) {
  node_start_s_ = wallNow();
  pace_.setTarget(o_.real_time_factor);
  if (o_.follow_clock && !o_.machine_bag.empty()) {
    ros::Time start, end;
    bagTimeRange(o_.machine_bag, start, end);
    replay_ = ReplayClock(o_.replay_lag_s, (end - start).toSec());
    replay_.setOrigin(start);
  }
  // A cell that runs until stopped keeps ~max_points of storage, whatever
  // the job's length would need (the scene's supply.max_points gives way).
  std::vector<std::string> overrides = o_.overrides;
  if (!o_.stop_at_end && !o_.follow_clock) {
    overrides.push_back("supply.max_points=" + std::to_string(o_.max_points));
  }
  setScene(cws::loadScene(o_.scene, overrides));
  grid_.setRate(PublishGrid::kFrames, frameRateHz(o_, scene_));
  // ~start at_rest: the core starts at rest, whatever the scene says.
  if (o_.start == "at_rest") scene_.core.start_at_speed = false;
  sim_ = std::make_unique<cws::Simulation>(scene_);
  grid_.restart(sim_->time());
  stamp_origin_s_ = ros::Time::now().toSec() - sim_->time();
  job_start_sim_s_ = sim_->time();
  if (o_.error_estimate) {
    if (o_.follow_clock || !o_.stop_at_end) {
      ROS_WARN(
          "winding_cell: ~error_estimate needs jobs that end: not with ~follow_clock or "
          "without ~stop_at_end; no estimates");
    } else {
      estimator_ = std::make_unique<JobErrorEstimator>(nh_);
      estimator_->startJob(*sim_);
    }
  }
  // The simulation logs its inputs only for the error estimate's rerun.
  sim_->keepInputs(estimator_ != nullptr);
  speed_setpoint_ = cws::rpmToRadPerSec(scene_.process.core_speed_rpm);
  tension_setpoint_ = scene_.process.tension;
  if (o_.start == "at_rest") {
    at_rest_ = true;
    speed_setpoint_ = 0.0;
    sim_->apply(cws::Setpoint::coreSpeed(0.0));
  }
  paused_ = o_.start == "paused";
  // A fixed colour range, so that a colour means one force all run long.
  force_max_N_ = o_.force_color_max_N > 0.0 ? o_.force_color_max_N
                                            : std::max(1.0, 2.0 * scene_.process.tension);

  state_pub_ = nh_.advertise<coil_winding_sim::WireState>("wire_state", 5);
  compact_pub_ = nh_.advertise<coil_winding_sim::WireStateCompact>("wire_state_compact", 20);
  metrics_pub_ = nh_.advertise<coil_winding_sim::WindingMetrics>("winding_metrics", 5);
  marker_pub_ = nh_.advertise<visualization_msgs::MarkerArray>("wire_markers", 2, true);
  status_pub_ = nh_.advertise<coil_winding_sim::CellStatus>("cell_status", 1, true);
  joints_pub_ = nh_.advertise<sensor_msgs::JointState>("joint_states", 10);
  if (o_.publish_clock) clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
  subscribeSetpoints();
  trajectory_sub_ = nh_.subscribe("joint_trajectory", 100, &WindingCell::onTrajectory, this);
  spindle_command_pub_ = nh_.advertise<sensor_msgs::JointState>("sim/spindle/command", 100);
  spindle_state_pub_ = nh_.advertise<sensor_msgs::JointState>("sim/spindle/state", 100);
  tension_command_pub_ =
      nh_.advertise<coil_winding_sim::TensionSetpoint>("sim/tension/command", 100);
  tension_measured_pub_ = nh_.advertise<coil_winding_sim::WireTension>("sim/tension/measured", 100);
  port_command_pub_ = nh_.advertise<geometry_msgs::PointStamped>("sim/port/command", 100);
  port_position_pub_ = nh_.advertise<geometry_msgs::PointStamped>("sim/port/position", 100);
  profile_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("sim/profile", 10);
  reset_srv_ = pnh_.advertiseService("reset", &WindingCell::onReset, this);
  pause_srv_ = pnh_.advertiseService("pause", &WindingCell::onPause, this);
  snapshot_srv_ = pnh_.advertiseService("snapshot", &WindingCell::onSnapshot, this);
  restore_srv_ = pnh_.advertiseService("restore", &WindingCell::onRestore, this);
  run_until_srv_ = pnh_.advertiseService("run_until", &WindingCell::onRunUntil, this);
  change_coil_srv_ = pnh_.advertiseService("change_coil", &WindingCell::onChangeCoil, this);
  coil_done_pub_ = nh_.advertise<coil_winding_sim::CoilDone>("coil_done", 1, true);

  state_rate_hz_ = o_.state_rate_hz;
  marker_rate_hz_ = o_.marker_rate_hz;
  startReconfigure();
  startWindServer();
  diagnostics_.setHardwareID("coil_winding_sim");
  diagnostics_.add("simulation", this, &WindingCell::diagnose);
  // The line that says the cell is ready, with where to reach it.
  ROS_INFO(
      "winding_cell: ready: action %s, services "
      "%s/{reset,pause,snapshot,restore,run_until,change_coil}; "
      "scene '%s', %d points, target real-time factor %g%s, %s; %s",
      nh_.resolveName("wind").c_str(), pnh_.getNamespace().c_str(), o_.scene.c_str(),
      sim_->model().constants().n, pace_.target(), o_.publish_clock ? ", publishing /clock" : "",
      o_.follow_clock  ? "replaying"
      : o_.stop_at_end ? "holding at the job's end (~stop_at_end)"
                       : "running until stopped",
      o_.start == "at_rest"  ? "the core at rest until a speed setpoint"
      : o_.start == "paused" ? "paused (~pause false starts it)"
                             : "winding");
  if (o_.follow_clock) {
    if (replay_.end()) {
      ROS_INFO("winding_cell: replaying '%s': %.6f s from %.9f s, lag %g s", o_.machine_bag.c_str(),
               *replay_.end(), replay_.origin().toSec(), o_.replay_lag_s);
    } else {
      ROS_INFO("winding_cell: following /clock from its first value, lag %g s", o_.replay_lag_s);
    }
  }
}

void WindingCell::run() {
  restartPace();
  double next_state = wallNow(), next_marker = next_state, next_clock = next_state,
         next_diagnostics = next_state, next_held = next_state;
  bool was_quiet = false;
  double next_wire = next_state;
  loop_wall_s_ = wallNow();
  while (ros::ok()) {
    bool done = false;
    {
      std::lock_guard<std::mutex> lock(sim_mutex_);
      // Wall time winding: not paused, held, stopped or at rest.
      const double pass_s = wallNow() - loop_wall_s_;
      loop_wall_s_ += pass_s;
      if (!paused_ && !failed_ && !holding() && !at_rest_ && !o_.follow_clock) {
        job_run_wall_s_ += pass_s;
        if (wind_.active) wind_.run_wall_s += pass_s;
      }
      takeWindRequests();
      drainInputs();
      // Setpoints without a time apply on receipt (with ~follow_clock each
      // waits for its stamp: advanceReplay).
      if (!o_.follow_clock) applyDue();
      if (o_.follow_clock) {
        if (!failed_ && !replay_done_) advanceReplay();
      } else if (!paused_ && !failed_ && !holding()) {
        advanceChunk();
        // Slower than the target: once, then every 10 s of wall time.
        int skipped = 0;
        if (!keeping_pace_ && !holding() && pace_warning_.due(wallNow(), skipped)) {
          ROS_WARN(
              "winding_cell: not keeping pace: real-time factor %.3g over the last second "
              "against the target %.3g (~real_time_factor); %s",
              pace_window_.factor(), pace_.target(), slow_cause_.c_str());
        }
      }
      noteFallback();
      if (!o_.follow_clock && o_.stop_at_end && !job_done_ && !failed_ && jobEnded()) endJob();
      checkPlan();
      if (wind_.active && !failed_ && windEnded()) endWind("done");
      done = paused_ || failed_ || holding();
      // While the cell takes no steps, its stamps follow the clock: the
      // state they show holds at every one of them.
      if (done)
        stamp_origin_s_ = std::max(stamp_origin_s_, ros::Time::now().toSec() - sim_->time());
      clock_s_ = stamp().toSec();
      // The job's end: its refined twin runs on the estimator's worker.
      if (estimator_ && finished()) estimator_->finishJob(*sim_, compute_s_, stamp());
    }
    publishStatus();
    // ~exit_at_end: the last state out, once the job's estimate (if any) is
    // published; a required node's exit ends the launch, and rosbag record
    // closes its bag.
    if (exit_requested_ && (!estimator_ || estimator_->settled())) {
      publishState();
      publishMarkers();
      ROS_INFO("winding_cell: exiting at the job's end (~exit_at_end)");
      // Started by roslaunch: the launch ends as after Ctrl-C, each node
      // and recorder closing in order, without the alarm roslaunch raises
      // when a required node ends by itself. Else: this node alone. (Half
      // a second first, for the last messages to reach a recorder.)
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
      if (endParentLaunch()) {
        const double until = wallNow() + 10.0;
        while (ros::ok() && wallNow() < until) {
          std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
      }
      ros::shutdown();
      break;
    }
    const double now = wallNow();
    if (o_.publish_clock && now >= next_clock) {
      publishClock();
      next_clock = now + 0.001;
    }
    // While the state stands (paused, held, stopped, the core at rest):
    // the state and the markers once a second, not at their full rates.
    const bool quiet = done || at_rest_;
    if (now >= next_state) {
      publishState();
      next_state = now + 1.0 / (quiet ? kQuietRateHz : state_rate_hz_.load());
    }
    if (now >= next_marker) {
      publishMarkers();
      next_marker = now + 1.0 / (quiet ? kQuietRateHz : marker_rate_hz_.load());
    }
    if (now >= next_wire) {
      publishCompactWire();
      next_wire = now + 1.0 / (quiet ? kQuietRateHz : o_.wire_rate_hz);
    }
    // Leaving a quiet stretch: at the full rates at once.
    if (!quiet && was_quiet) next_state = next_marker = next_wire = now;
    was_quiet = quiet;
    // Once a second of wall time: the updater's own period counts ROS
    // time, with ~publish_clock the simulated time (100 s of wall time
    // between reports at a real-time factor of 0.01).
    if (now >= next_diagnostics) {
      diagnostics_.force_update();
      next_diagnostics = now + 1.0;
    }
    if (now >= next_held) {
      reportHeldWarnings();
      next_held = now + 0.1;
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
    const double ahead_s = pace_.ahead(wallNow(), sim_->time());
    if (done || ahead_s > 0.0) {
      std::this_thread::sleep_for(std::chrono::duration<double>(
          done ? 0.005 : std::min(0.005, ahead_s / std::max(pace_.target(), 1e-9))));
    }
  }
}

// Sends SIGINT to the parent process if it is roslaunch; false if not.
bool WindingCell::endParentLaunch() {
  const pid_t parent = ::getppid();
  std::ifstream in("/proc/" + std::to_string(parent) + "/cmdline");
  std::string cmdline((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (cmdline.find("roslaunch") == std::string::npos) return false;
  return ::kill(parent, SIGINT) == 0;
}

// ---- pacing -----------------------------------------------------------------

void WindingCell::restartPace() {
  // The stamps' origin: on after a pause, a reset or a restore, never back.
  stamp_origin_s_ = std::max(stamp_origin_s_, ros::Time::now().toSec() - sim_->time());
  const double now = wallNow();
  pace_.restart(now, sim_->time());
  pace_window_.restart(now, sim_->time());
  work_mark_ = cws::PaceProfile::count(sim_->time(), now, sim_->stepper());
  const cws::NewtonCounts* newton = sim_->stepper().newtonCounts();
  fallback_mark_ = newton ? newton->fallback_stretches : 0;
  slow_cause_.clear();
}

double WindingCell::realTimeFactor() const {
  return paused_ || failed_ || holding() ? 0.0 : pace_window_.factor();
}

// Once a second of wall time: the work done in it, and from it the cause a
// slow cell gives.
void WindingCell::markWork(double wall_s) {
  if (wall_s - work_mark_.wall_s < 1.0) return;
  const cws::WorkCount now = cws::PaceProfile::count(sim_->time(), wall_s, sim_->stepper());
  const cws::NewtonCounts* newton = sim_->stepper().newtonCounts();
  const long fallbacks = newton ? newton->fallback_stretches : 0;
  slow_cause_ =
      slowCause(work_mark_, now, fallbacks - fallback_mark_, newton ? newton->fallback_cause : "");
  work_mark_ = now;
  fallback_mark_ = fallbacks;
}

// Room for the points a step may draw in at the fastest feed (a few at
// 6,000 rpm on a large coil), with a wide margin.
namespace {
constexpr int kStorageRoom = 64;
}  // namespace

bool WindingCell::storageFull() {
  // (Buried wire retires from the live arrays first.)
  return sim_->model().supply() && !sim_->makeRoom(kStorageRoom);
}

// The storage is full: the cell holds its state and says so once, on the
// console, cell_status and /diagnostics.
void WindingCell::holdFull() {
  storage_full_ = true;
  std::string message;
  cellState(message);
  ROS_WARN("winding_cell: %s", message.c_str());
}

bool WindingCell::finished() const {
  if (o_.follow_clock) return replay_done_;
  return o_.stop_at_end && jobEnded();
}

// Steps until the pace target, the scene's end, a ~run_until time or
// ~10 ms of wall time.
void WindingCell::advanceChunk() {
  const double start = wallNow();
  double t_limit = o_.stop_at_end ? jobEndTime() : 1e300;
  // Running until stopped: the steps end on a coil's plan and on a full
  // bobbin, where the spindle is braked (checkPlan).
  if (!o_.stop_at_end && !o_.follow_clock && !braking_ && sim_->model().core()) {
    if (scene_.process.layers > 0 && !plan_ended_ && !wind_.active)
      t_limit = std::min(t_limit, jobEndTime());
    const double holds = scene_.bobbinTurns();
    if (std::isfinite(holds) && !bobbin_full_) t_limit = std::min(t_limit, timeAtTurns(0.0, holds));
  }
  if (run_until_) t_limit = std::min(t_limit, *run_until_);
  if (wind_.active && wind_.duration_s > 0.0) t_limit = std::min(t_limit, windEndTime());
  try {
    publishDue();
    while (sim_->time() < t_limit && pace_.ahead(wallNow(), sim_->time()) < 0.0 &&
           wallNow() - start < 0.010) {
      if (storageFull()) {
        holdFull();
        break;
      }
      feedPort();
      double limit = std::min(t_limit, grid_.next());
      if (wind_.active) {
        applyWindProfile();
        // A goal of turns ends on its turns at the present command.
        if (wind_.turns > 0.0) limit = std::min(limit, windEndTime());
        if (windEnded()) break;
      }
      // Trajectory points end steps and apply at their times.
      applyDue();
      limit = std::min(limit, inbox_.due().nextTime());
      const double step_start = wallNow();
      sim_->step(limit);
      const double step_wall = wallNow() - step_start;
      compute_s_ += step_wall;

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
  const double now = wallNow();
  pace_window_.update(now, sim_->time(), pace_.target(), pace_.keeping(now, sim_->time()));
  keeping_pace_ = !pace_window_.slow();
  markWork(now);
  // Behind by more than a quarter second: a stall (a slow start, a burst of
  // work), not a deficit to chase at full speed; the pace goes on from here.
  if (pace_.ahead(now, sim_->time()) < -0.25 * pace_.target()) pace_.restart(now, sim_->time());
}

// ---- replay (~follow_clock) -------------------------------------------------

// Before the replay's first output: every sim/ topic has a subscriber
// (rosbag record), or ~wait_for_subscribers of wall time has passed since
// the node started. Waiting costs nothing but wall time: the steps do not
// depend on the pace.
bool WindingCell::recorderReady() {
  if (replay_started_) return true;
  const bool all =
      spindle_command_pub_.getNumSubscribers() > 0 && spindle_state_pub_.getNumSubscribers() > 0 &&
      tension_command_pub_.getNumSubscribers() > 0 &&
      tension_measured_pub_.getNumSubscribers() > 0 && port_command_pub_.getNumSubscribers() > 0 &&
      port_position_pub_.getNumSubscribers() > 0 && profile_pub_.getNumSubscribers() > 0;
  if (!all && wallNow() - node_start_s_ < o_.wait_for_subscribers_s) return false;
  if (!all) {
    ROS_WARN(
        "winding_cell: replay starts with sim/ topics nobody subscribed to after %g s "
        "(~wait_for_subscribers)",
        o_.wait_for_subscribers_s);
  }
  replay_started_ = true;
  return true;
}

// Steps towards the replay's target for at most ~10 ms of wall time,
// ending steps at setpoint stamps and at the publishing grid.
void WindingCell::advanceReplay() {
  const double target = replay_.target(ros::Time::now(), wallNow());
  if (target < 0.0) return;  // no clock yet, or not yet past the lag
  if (!recorderReady()) return;
  const double start = wallNow();
  const std::optional<double>& end = replay_.end();
  try {
    applyDue();
    publishDue();
    while (sim_->time() < target && wallNow() - start < 0.010) {
      feedPort();
      // Steps end at events only (setpoints, the publishing grid, the
      // bag's end), never at the clock: a step that would end beyond the
      // clock's target waits for it. So the steps are the same whatever
      // the pace.
      double limit = grid_.next();
      if (end) limit = std::min(limit, *end);
      limit = std::min(limit, inbox_.due().nextTime());
      // Port samples still waiting for room: not past the queued path.
      if (!inbox_.ports().empty()) limit = std::min(limit, sim_->portCommandEnd());
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
  if (end && sim_->time() >= *end - cws::PortTrajectory::timeTolerance(*end)) replay_done_ = true;
  // (A replay follows the clock: its factor is measured, it has no target.)
  pace_window_.update(wallNow(), sim_->time(), 0.0, true);
}

}  // namespace cws_ros
