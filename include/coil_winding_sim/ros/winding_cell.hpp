// winding_cell: the simulated winding cell as a ROS node's class.
//
// A thin shell over the simulation core: the simulation advances in the
// caller's thread (run()) in short chunks (at most ~10 ms of wall time
// each), paced to a target real-time factor; setpoints and services are
// served by an AsyncSpinner between chunks, so none waits behind a long
// computation. All conversions to messages and TF live in the bridge
// (bridge.hpp); the timing logic in cell_timing.hpp.
//
// Replay mode (~follow_clock): the simulated time follows the ROS clock
// that `rosbag play --clock` publishes, from the machine bag's start
// (~machine_bag) up to (clock - origin - ~replay_lag), never beyond; the
// setpoints are queued by stamp and applied when the simulated time reaches
// them (steps end there), port samples are handed to the simulation ahead
// of time as a path, and the `sim/` topics are published on a grid of
// simulated time: the replay is the same whatever the pace. At the bag's
// end the node shuts down.
//
// The class is split by concern over winding_cell.cpp (construction, the
// loop, pacing, replay), winding_cell_publish.cpp (what it publishes,
// /diagnostics), winding_cell_inputs.cpp (setpoint
// topics and their queues), winding_cell_services.cpp and
// winding_cell_job.cpp (the job's end and the cell's state) and
// winding_cell_wind.cpp (the wind action).
#pragma once

#include <actionlib/server/simple_action_server.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <geometry_msgs/PointStamped.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <std_srvs/SetBool.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/transform_broadcaster.h>
#include <trajectory_msgs/JointTrajectory.h>

#include <Eigen/Core>
#include <atomic>
#include <deque>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "coil_winding_sim/CellStatus.h"
#include "coil_winding_sim/CoreSpeedSetpoint.h"
#include "coil_winding_sim/Restore.h"
#include "coil_winding_sim/RunUntil.h"
#include "coil_winding_sim/Snapshot.h"
#include "coil_winding_sim/TensionSetpoint.h"
#include "coil_winding_sim/WindAction.h"
#include "coil_winding_sim/WindingCellConfig.h"
#include "coil_winding_sim/core/run/setpoint_inbox.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"
#include "coil_winding_sim/core/scene/setpoint_limits.hpp"
#include "coil_winding_sim/ros/bridge.hpp"
#include "coil_winding_sim/ros/cell_timing.hpp"
#include "coil_winding_sim/ros/job_error_estimate.hpp"
#include "coil_winding_sim/ros/node_options.hpp"

namespace cws_ros {

// Why a wind goal cannot run under the scene's setpoint limits; empty if
// it can.
std::string windGoalRefusal(const coil_winding_sim::WindGoal& goal,
                            const cws::SetpointLimits& limits);

class WindingCell {
 public:
  // Options already validated (validateNodeOptions). `this_executable`
  // reads snapshots in a child process (~restore). Throws
  // std::invalid_argument or cws::SceneError naming what is wrong.
  WindingCell(ros::NodeHandle nh, ros::NodeHandle pnh, const NodeOptions& options,
              std::string this_executable);

  // The simulation loop; returns when ROS shuts down.
  void run();

 private:
  // ---- the loop (winding_cell.cpp)
  double wallNow() const;
  bool finished() const;
  // The cell takes no steps: the job is done (the scene's, finished(), or
  // a wind goal's) or the wire's storage is full.
  bool holding() const { return job_done_ || storage_full_ || finished(); }
  // ~exit_at_end under roslaunch: asks the launch to end (SIGINT).
  static bool endParentLaunch();
  // The storage has no room for the points the next step may draw in.
  bool storageFull();
  void holdFull();
  // ---- the job (winding_cell_job.cpp)
  bool jobEnded() const;
  double jobEndTime() const;
  double timeAtTurns(double start_angle_rad, double turns) const;
  void endJob();
  std::string cellState(std::string& message) const;
  void publishStatus();
  // ---- the loop, continued (winding_cell.cpp)
  void restartPace();
  void advanceChunk();
  bool recorderReady();
  void advanceReplay();
  void publishDue();
  ros::Time stamp() const;
  void publishClock();
  void publishState();
  void publishFrames();
  void publishCompactWire();
  void publishMarkers();
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);
  void warn(WallThrottle& throttle, const std::string& text) const;
  // The implicit stepper's explicit fallback (implicit_stepper.hpp): a new
  // stretch is logged and marks the wall time /diagnostics warns from.
  void noteFallback();
  // A stretch began within the last kFallbackWarnS of wall time.
  static constexpr double kFallbackWarnS = 10.0;
  bool fallbackRecent() const { return wallNow() - fallback_wall_s_ < kFallbackWarnS; }

  // ---- the wind action (winding_cell_wind.cpp)
  void startWindServer();
  void onWindGoal();
  void onWindPreempt();
  void takeWindRequests();
  void startWind(const coil_winding_sim::WindGoal& goal);
  void abortWind(const std::string& why);
  void applyWindProfile();
  double windTurns(double t) const;
  bool windEnded() const;
  double windEndTime() const;
  // `how`: "done" (succeeded), else the goal was cancelled or replaced.
  void endWind(const std::string& how);
  void publishWindFeedback();

  // ---- live parameters (winding_cell_reconfigure.cpp)
  void startReconfigure();
  void onReconfigure(coil_winding_sim::WindingCellConfig& config);
  void showSceneInReconfigure();

  // ---- setpoints (winding_cell_inputs.cpp)
  struct TopicWarnings {
    WallThrottle value, ahead, order;
  };
  // The setpoint table's topics, and with ~machine_inputs its machine
  // topics, subscribed: a message of type M on `topic` is read as a
  // setpoint of `row`.
  void subscribeSetpoints();
  template <class M>
  ros::Subscriber subscribeRow(const cws::SetpointRow& row, const std::string& topic,
                               uint32_t queue);
  void onTrajectory(const trajectory_msgs::JointTrajectory::ConstPtr& msg);
  // The simulated time a stamp on the node's clock stands for [s] (lock
  // held; zero: now).
  double simTimeOf(const ros::Time& stamp) const;
  double inUse(cws::Setpoint::Kind kind) const;
  void valueInput(const std::string& topic, const cws::Setpoint& setpoint, const ros::Time& stamp);
  void pathInput(const std::string& topic, const cws::Setpoint& setpoint, const ros::Time& stamp);
  // A setpoint that arrives while the cell holds (a finished job, a full
  // storage) is refused with a warning saying why and what to do.
  bool refusedWhileHolding(const std::string& topic, const std::string& what);
  ros::Time nodeClock() const;
  bool admitStamp(const std::string& topic, const ros::Time& stamp);
  TopicWarnings& warningsOf(const std::string& topic);
  void reportHeldWarnings();
  void drainInputs();
  void applyDue();
  void feedPort();
  void setScene(const cws::Scene& scene);
  cws::SetpointLimits limits() const;

  // ---- services (winding_cell_services.cpp)
  bool onReset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);
  // ~change_coil: the coil on the cell is taken off (its figures on
  // coil_done) and an empty bobbin starts from the scene's start; the node,
  // its clock and its recording run on.
  bool onChangeCoil(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);
  // The change itself (lock held); returns what it says.
  std::string changeCoil();
  int coil_number_ = 1;  // the coil on the cell: 1 for the node's first
  bool onPause(std_srvs::SetBool::Request& req, std_srvs::SetBool::Response& res);
  bool onRunUntil(coil_winding_sim::RunUntil::Request& req,
                  coil_winding_sim::RunUntil::Response& res);
  bool onSnapshot(coil_winding_sim::Snapshot::Request& req,
                  coil_winding_sim::Snapshot::Response& res);
  bool onRestore(coil_winding_sim::Restore::Request& req, coil_winding_sim::Restore::Response& res);
  void replace(std::unique_ptr<cws::Simulation> next);

  ros::NodeHandle nh_, pnh_;
  NodeOptions o_;
  std::string this_executable_;
  double node_start_s_ = 0.0;  // wall time [s]

  std::mutex sim_mutex_;  // guards everything below but the atomics
  cws::Scene scene_;
  std::unique_ptr<cws::Simulation> sim_;
  bool paused_ = false, failed_ = false, keeping_pace_ = true, send_delete_all_ = false;
  // The job's end (once per job: reset and restore start a new one), and
  // the exit it asks for with ~exit_at_end.
  // (Atomic: the setpoint callbacks read them without the lock.)
  std::atomic<bool> job_done_{false}, storage_full_{false};
  // A coil's plan (winding_cell_job.cpp, checkPlan): running until stopped,
  // a scene with process.layers planned ends its job with the spindle
  // braked to rest at process.turns, and the bobbin ends when it is full.
  // plan_ended_: once per job; braking_: the spindle is being stopped;
  // plan_stop_: the cell holds at such a stop, and a setpoint winds on
  // (resume_: one arrived); job_note_: what the stop says.
  bool plan_ended_ = false, braking_ = false;
  // (Atomic: the setpoint callbacks read them without the lock.)
  std::atomic<bool> plan_stop_{false}, resume_{false}, bobbin_full_{false};
  std::string job_note_;
  void checkPlan();
  bool exit_requested_ = false;
  // The job's pace, as Gazebo's: simulated time over the wall time spent
  // winding (not paused, held or at rest).
  double job_start_sim_s_ = 0.0;  // simulated time at the job's start [s]
  double job_run_wall_s_ = 0.0;   // wall time winding since then [s]
  double job_wall_s_ = 0.0;       // the ended job's run_wall [s]
  double loop_wall_s_ = 0.0;      // the loop's last pass [s of wall time]
  // The job-done words for the simulation and the time they were found for.
  struct DoneText {
    const cws::Simulation* sim = nullptr;
    double time_s = -1.0;
    std::string text;
  };
  mutable DoneText done_text_;
  double jobRealTimeFactor() const {
    return job_wall_s_ > 0.0 ? (sim_->time() - job_start_sim_s_) / job_wall_s_ : 0.0;
  }
  // ~start at_rest: the core held at 0 until the first speed setpoint.
  std::atomic<bool> at_rest_{false};
  WallThrottle pace_warning_{10.0};                // "not keeping pace" on the console
  WallThrottle fallback_warning_{kFallbackWarnS};  // explicit fallback stretches on the console
  long fallback_seen_ = 0;                         // stretches noted so far
  double fallback_wall_s_ = -1e300;                // wall time of the last new one [s]
  std::string last_status_;                        // the state last sent on cell_status
  std::string refused_, last_refused_;  // the last refused live change (cell_status), and sent
  int last_estimate_count_ = 0;         // error estimates sent on cell_status
  double force_max_N_ = 1.0;            // the wire's colour range, 0 to this [N]
  std::optional<double> run_until_;     // pause when the simulated time reaches it [s]
  double compute_s_ = 0.0;              // wall time in the present job's steps [s]
  std::unique_ptr<JobErrorEstimator> estimator_;  // with ~error_estimate
  std::string failure_;
  double clock_offset_ = 0.0;
  // On the wall clock (no /use_sim_time): the ROS time of simulated time 0
  // [s]. Samples are stamped with their simulated time on the ROS clock;
  // the origin moves forward (never back) when the pace restarts and while
  // the cell takes no steps.
  double stamp_origin_s_ = 0.0;
  PaceKeeper pace_;
  PaceWindow pace_window_;
  // The cell's real-time factor [-], the one figure of winding_metrics,
  // cell_status, /diagnostics, rviz and the wind feedback: simulated over
  // wall time in the last second of wall time (PaceWindow); 0 while the
  // cell takes no steps (paused, held, stopped).
  double realTimeFactor() const;
  // The integrator's work at the start of the present second of wall time,
  // and why the cell runs slow (slowCause over the last full second).
  cws::WorkCount work_mark_;
  long fallback_mark_ = 0;
  std::string slow_cause_;
  void markWork(double wall_s);
  double status_wall_s_ = -1e300;  // wall time cell_status was last sent [s]
  // The last speed and tension applied (or, holding a snapshot, to apply).
  std::atomic<double> speed_setpoint_{0.0}, tension_setpoint_{0.0};
  // Limits of the scene in use: |speed| [rad/s], tension [N].
  std::atomic<double> max_speed_{0.0}, max_tension_{0.0};
  // The node's clock with ~publish_clock [s] (read by the setpoint callbacks).
  std::atomic<double> clock_s_{0.0};

  std::mutex warnings_mutex_;  // guards the map (its entries are thread-safe)
  std::map<std::string, TopicWarnings> warnings_;

  // The wind goal in progress (lock held): its start, its end in turns or
  // simulated time, its profile (times from the start [s], speeds [rad/s],
  // tensions [N]) and the wall time of its steps [s].
  struct WindJob {
    bool active = false;
    double start_s = 0.0, start_angle_rad = 0.0;
    double turns = 0.0, duration_s = 0.0;
    std::vector<double> time_s, speed, tension;
    double next_profile_s = 0.0;  // when the profile is next applied [s]
    double run_wall_s = 0.0;      // wall time winding [s]
    // windEndTime's last answer [s] and the core command it was for [rad/s].
    mutable double end_s = 0.0, end_command = std::numeric_limits<double>::quiet_NaN();
  };
  WindJob wind_;
  // The job's end time found for the core's command (jobEndTime), found
  // again when the command changes or the run is replaced [s].
  mutable double job_end_s_ = 0.0, job_end_command_ = std::numeric_limits<double>::quiet_NaN();
  std::unique_ptr<actionlib::SimpleActionServer<coil_winding_sim::WindAction>> wind_server_;
  // A goal or a cancel from the server's callbacks, for the loop.
  std::mutex wind_mutex_;
  boost::shared_ptr<const coil_winding_sim::WindGoal> wind_goal_;
  bool wind_cancel_ = false;

  // Replay (~follow_clock): the bag's start on the ROS clock and its end.
  ReplayClock replay_;
  bool replay_done_ = false, replay_started_ = false;

  // Setpoints from the callbacks and the loop's queues (ROS-free): their
  // stamps' admission, by simulated time, port samples in order.
  cws::SetpointInbox inbox_;

  PublishGrid grid_;
  double next_rest_sample_s_ = 0.0;  // the core at rest: the next grid sample [s]

  ros::Publisher state_pub_, metrics_pub_, marker_pub_, clock_pub_, status_pub_, joints_pub_,
      compact_pub_;
  // wire_state_compact: the carried points sent so far (the reader holds
  // them), the subscribers then, and when the whole wire is next sent
  // [s of wall time].
  int carried_sent_ = 0;
  uint32_t compact_subscribers_ = 0;
  double compact_keyframe_s_ = 0.0;
  static constexpr double kCompactKeyframeS = 10.0;
  // wire_markers: the retired wire whose strips were sent (toMarkers), the
  // subscribers then, and when every strip is next sent [s of wall time].
  int retired_markers_sent_ = 0;
  uint32_t marker_subscribers_ = 0;
  double marker_keyframe_s_ = 0.0;
  ros::Publisher spindle_command_pub_, spindle_state_pub_, tension_command_pub_,
      tension_measured_pub_, port_command_pub_, port_position_pub_, profile_pub_;
  std::vector<ros::Subscriber> setpoint_subs_;  // one per topic of the setpoint table
  ros::Subscriber trajectory_sub_;
  ros::ServiceServer reset_srv_, pause_srv_, snapshot_srv_, restore_srv_, run_until_srv_,
      change_coil_srv_;
  ros::Publisher coil_done_pub_;
  tf2_ros::TransformBroadcaster tf_;
  diagnostic_updater::Updater diagnostics_;

  // dynamic_reconfigure: the server, its own lock, the values in use, and
  // the publish rates the loop reads without the simulation's lock [Hz].
  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<coil_winding_sim::WindingCellConfig>> reconfigure_;
  coil_winding_sim::WindingCellConfig applied_;
  std::atomic<double> state_rate_hz_{20.0}, marker_rate_hz_{10.0};
  static constexpr double kQuietRateHz = 1.0;  // state and markers while the state stands
};

}  // namespace cws_ros
