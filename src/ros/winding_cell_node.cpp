// winding_cell: the simulated winding cell as a ROS node.
//
// A thin shell over the simulation core: the simulation advances in this
// process's main thread in short chunks (at most ~10 ms of wall time each),
// paced to a target real-time factor; setpoints and services are served by
// an AsyncSpinner between chunks, so none waits behind a long computation.
// All conversions to messages and TF live in the bridge (bridge.hpp).
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

#ifndef CWS_DEFAULT_SCENE
#define CWS_DEFAULT_SCENE ""
#endif

namespace {

using Clock = std::chrono::steady_clock;
double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

double rpmToRadPerS(double rpm) { return rpm * 2.0 * M_PI / 60.0; }

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
    speed_setpoint_ = rpmToRadPerS(scene_.process.core_speed_rpm);
    tension_setpoint_ = scene_.process.tension;

    state_pub_ = nh_.advertise<coil_winding_sim::WireState>("wire_state", 5);
    metrics_pub_ = nh_.advertise<coil_winding_sim::WindingMetrics>("winding_metrics", 5);
    marker_pub_ = nh_.advertise<visualization_msgs::MarkerArray>("wire_markers", 2, true);
    if (publish_clock_) clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
    speed_sub_ = nh_.subscribe("core_speed_setpoint", 100, &WindingCell::onSpeed, this);
    tension_sub_ = nh_.subscribe("tension_setpoint", 100, &WindingCell::onTension, this);
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
        if (!paused_ && !failed_ && !finished()) advanceChunk();
        done = paused_ || failed_ || finished();
        clock_s_ = stamp().toSec();
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

  bool finished() const { return stop_at_end_ && sim_->time() >= sim_->endTime(); }

  // Steps until the pace target, the scene's end, a ~run_until time or
  // ~10 ms of wall time.
  void advanceChunk() {
    const auto start = Clock::now();
    double t_limit = stop_at_end_ ? sim_->endTime() : 1e300;
    if (run_until_) t_limit = std::min(t_limit, *run_until_);
    try {
      while (sim_->time() < t_limit && aheadOfPace() < 0.0 &&
             Clock::now() - start < std::chrono::milliseconds(10)) {
        sim_->step(t_limit);
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

  // ---- time stamps -------------------------------------------------------------
  // With ~publish_clock the node's clock is the simulated time plus an offset
  // that keeps it monotonic across reset and restore; otherwise ROS time.
  ros::Time stamp() const {
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

  // ---- setpoints ---------------------------------------------------------------
  // Checked here, applied by the simulation loop between chunks. Neither
  // takes the simulation's lock: a burst of setpoints cannot hold up the
  // simulation or the services.
  void onSpeed(const coil_winding_sim::CoreSpeedSetpoint::ConstPtr& msg) {
    const double w = msg->angular_velocity;
    const double limit = max_speed_;
    if (!std::isfinite(w) || std::abs(w) > limit) {
      warn(speed_gate_.value_warning, "refused core_speed_setpoint " + number(w) +
                                          " rad/s (finite, |w| <= " + number(limit) +
                                          " rad/s = process.max_core_speed_rpm); keeping " +
                                          number(speed_setpoint_) + " rad/s");
      return;
    }
    if (admitStamp("core_speed_setpoint", msg->header.stamp, speed_gate_)) {
      speed_setpoint_ = w;
      setpoints_changed_ = true;
    }
  }

  void onTension(const coil_winding_sim::TensionSetpoint::ConstPtr& msg) {
    const double f = msg->tension;
    const double limit = max_tension_;
    if (!std::isfinite(f) || f < 0.0 || f > limit) {
      warn(tension_gate_.value_warning,
           "refused tension_setpoint " + number(f) + " N (finite, 0 .. " + number(limit) +
               " N = process.max_tension); keeping " + number(tension_setpoint_) + " N");
      return;
    }
    if (admitStamp("tension_setpoint", msg->header.stamp, tension_gate_)) {
      tension_setpoint_ = f;
      setpoints_changed_ = true;
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
    speed_gate_.last_stamp = ros::Time();
    tension_gate_.last_stamp = ros::Time();
  }

  // Makes `scene` the scene in use (its limits apply to the setpoints).
  void setScene(const cws::Scene& scene) {
    scene_ = scene;
    max_speed_ = rpmToRadPerS(scene_.process.max_core_speed_rpm);
    max_tension_ = scene_.process.max_tension;
  }

  void applySetpoints() {
    if (!setpoints_changed_.exchange(false)) return;
    sim_->setCoreSpeed(speed_setpoint_);
    sim_->setSupplyTension(tension_setpoint_);
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
      speed_setpoint_ = rpmToRadPerS(scene_.process.core_speed_rpm);
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
      const double speed_limit = rpmToRadPerS(scene.process.max_core_speed_rpm);
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
    restartPace();
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
  SetpointGate speed_gate_, tension_gate_;
  ros::Time last_clock_seen_;

  ros::Publisher state_pub_, metrics_pub_, marker_pub_, clock_pub_;
  ros::Subscriber speed_sub_, tension_sub_;
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
