// The winding cell's services: reset, pause, run_until, snapshot and
// restore (winding_cell.hpp). A failing service leaves the run as it was.
#include <cmath>
#include <filesystem>
#include <limits>

#include "coil_winding_sim/core/base/text_format.hpp"
#include "coil_winding_sim/core/external_forces/supply.hpp"
#include "coil_winding_sim/core/scene/setpoint_limits.hpp"
#include "coil_winding_sim/ros/bridge.hpp"
#include "coil_winding_sim/ros/snapshot_bag.hpp"
#include "coil_winding_sim/ros/snapshot_reader.hpp"
#include "coil_winding_sim/ros/winding_cell.hpp"

namespace cws_ros {

namespace {
// Wall-time limit of reading a snapshot in the reader process [s].
constexpr double kRestoreTimeout = 20.0;
}  // namespace

bool WindingCell::onReset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
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

bool WindingCell::onChangeCoil(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  std::lock_guard<std::mutex> lock(sim_mutex_);
  if (o_.follow_clock) {
    res.success = false;
    res.message = "the cell replays a machine bag (~follow_clock): no coil change";
    return true;
  }
  try {
    res.message = changeCoil();
    res.success = true;
  } catch (const std::exception& e) {
    res.success = false;
    res.message = std::string("coil change failed: ") + e.what();
  }
  return true;
}

std::string WindingCell::changeCoil() {
  // The new bobbin first (a scene that cannot start leaves the coil on),
  // its core at rest until a speed setpoint, trajectory or wind goal, as a
  // machine waits after a bobbin change.
  cws::Scene empty = scene_;
  empty.core.start_at_speed = false;
  auto fresh = std::make_unique<cws::Simulation>(empty);
  const coil_winding_sim::CoilDone done = toCoilDone(*sim_, stamp(), o_.frames, coil_number_);
  coil_done_pub_.publish(done);
  const std::string b = std::isfinite(done.bulging_height)
                            ? cws::formatNumber(1e3 * done.bulging_height, "%.4f") + " mm"
                            : std::string("none");
  const std::string said = "coil " + std::to_string(coil_number_) + " taken off after " +
                           cws::formatNumber(done.core_turns, "%.4g") + " turns (" +
                           (done.layers > 0 ? std::to_string(done.layers) + " layers, " : "") +
                           "bulging " + b + "; coil_done); coil " +
                           std::to_string(coil_number_ + 1) +
                           ": an empty bobbin, the core at rest until a speed setpoint or goal";
  ++coil_number_;
  replace(std::move(fresh));
  at_rest_ = true;
  speed_setpoint_ = 0.0;
  sim_->apply(cws::Setpoint::coreSpeed(0.0));
  tension_setpoint_ = scene_.process.tension;
  ROS_INFO("winding_cell: %s", said.c_str());
  return said;
}

bool WindingCell::onPause(std_srvs::SetBool::Request& req, std_srvs::SetBool::Response& res) {
  std::lock_guard<std::mutex> lock(sim_mutex_);
  paused_ = req.data;
  restartPace();
  res.success = true;
  res.message = paused_ ? "paused" : "running";
  return true;
}

bool WindingCell::onRunUntil(coil_winding_sim::RunUntil::Request& req,
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

bool WindingCell::onSnapshot(coil_winding_sim::Snapshot::Request& req,
                             coil_winding_sim::Snapshot::Response& res) {
  cws::SimulationState state;
  ros::Time t;
  {
    std::lock_guard<std::mutex> lock(sim_mutex_);
    state = sim_->saveState();
    // The setpoints not yet applied belong to the state too.
    state.model.core[3] = sim_->model().core() ? speed_setpoint_.load() : state.model.core[3];
    if (sim_->model().supply()) {
      cws::holdSetpoint(state, cws::Setpoint::supplyTension(tension_setpoint_));
    }
    t = stamp();
  }
  try {
    // A relative path is the node's working directory's (roslaunch: ROS_HOME,
    // usually ~/.ros): the answer names the file absolutely.
    const std::string path = req.path.empty()
                                 ? req.path
                                 : std::filesystem::absolute(req.path).lexically_normal().string();
    writeSnapshotBag(path, toSnapshotMsg(state, t));
    res.success = true;
    res.message = "snapshot at t = " + std::to_string(state.time_s) + " s written to " + path;
  } catch (const std::exception& e) {
    res.success = false;
    res.message = e.what();
  }
  return true;
}

bool WindingCell::onRestore(coil_winding_sim::Restore::Request& req,
                            coil_winding_sim::Restore::Response& res) {
  // Read and rebuild outside the lock; swap only a complete simulation.
  // The file is read in a child process: a corrupt bag can crash rosbag's
  // reader or exhaust the memory, which must not take this node with it.
  try {
    const cws::SimulationState state = fromSnapshotMsg(
        readSnapshotBagIsolated(req.path, this_executable_.c_str(), kRestoreTimeout));
    auto restored = cws::Simulation::fromState(state);
    // Its core speed passes the checks of the setpoint topics (the held
    // setpoints passed their rows' checks in fromState).
    const cws::Scene& scene = restored->scene();
    const cws::SetpointLimits limits = cws::SetpointLimits::of(scene.process);
    std::string why;
    if (restored->model().core()) {
      why = cws::coreSpeedRefusal(limits, state.model.core[3]);
      if (!why.empty()) why = cws::coreSpeedText(state.model.core[3]) + " " + why;
    }
    if (!why.empty()) throw std::runtime_error("'" + req.path + "': its setpoint, " + why);
    {
      std::lock_guard<std::mutex> lock(sim_mutex_);
      setScene(scene);
      replace(std::move(restored));
      speed_setpoint_ = state.model.core[3];
      tension_setpoint_ = sim_->model().supply() ? sim_->model().supply()->tensionSetpoint()
                                                 : scene_.process.tension;
    }
    // The live parameters show the snapshot's friction and damping (outside
    // the simulation's lock: the server's callback takes it).
    showSceneInReconfigure();
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
void WindingCell::replace(std::unique_ptr<cws::Simulation> next) {
  abortWind("the run was replaced (reset or restore)");
  clock_offset_ += sim_->time() - next->time();
  sim_ = std::move(next);
  job_end_command_ = std::numeric_limits<double>::quiet_NaN();  // (jobEndTime)
  sim_->keepInputs(estimator_ != nullptr);
  clock_s_ = stamp().toSec();
  inbox_.clear();
  run_until_.reset();
  failed_ = false;
  failure_.clear();
  send_delete_all_ = true;
  grid_.restart(sim_->time());
  restartPace();
  compute_s_ = 0.0;
  job_done_ = false;
  storage_full_ = false;
  plan_ended_ = braking_ = false;
  plan_stop_ = resume_ = bobbin_full_ = false;
  job_note_.clear();
  carried_sent_ = 0;  // (the reader starts the new run's wire from point 0)
  exit_requested_ = false;
  job_start_sim_s_ = sim_->time();
  job_run_wall_s_ = 0.0;
  job_wall_s_ = 0.0;
  done_text_ = DoneText();
  if (estimator_) estimator_->startJob(*sim_);
}

}  // namespace cws_ros
