// rostest of the cell's start and end (cell_start_end.test, a job that
// ends: ~stop_at_end): started with
// ~start at_rest, the core does not turn until a speed setpoint arrives, then
// turns at it; after a second setpoint doubles the speed midway, the job
// ends at process.turns (0.5) of the core's actual rotation, not at the time
// the scene's own speed would need, and cell_status, winding_metrics and
// /diagnostics say the job is done. A setpoint after the end is refused
// with a warning.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>

#include <cmath>
#include <mutex>
#include <string>
#include <vector>

#include "coil_winding_sim/CellStatus.h"
#include "coil_winding_sim/CoreSpeedSetpoint.h"
#include "coil_winding_sim/WindingMetrics.h"
#include "ros_test_support.hpp"

namespace {

using cws_ros_test::waitFor;

// The latest status, metrics and diagnostics summary of the node.
struct Listener {
  Listener() {
    ros::NodeHandle nh;
    status_sub = nh.subscribe("cell_status", 10, &Listener::onStatus, this);
    metrics_sub = nh.subscribe("winding_metrics", 10, &Listener::onMetrics, this);
    diag_sub = nh.subscribe("/diagnostics", 10, &Listener::onDiagnostics, this);
    log_sub = nh.subscribe("/rosout", 1000, &Listener::onLog, this);
  }
  void onLog(const rosgraph_msgs::Log::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    if (m->level == rosgraph_msgs::Log::WARN) warnings.push_back(m->msg);
  }
  bool warned(const std::string& words) {
    std::lock_guard<std::mutex> l(mutex);
    for (const std::string& w : warnings) {
      if (w.find(words) != std::string::npos) return true;
    }
    return false;
  }
  void onStatus(const coil_winding_sim::CellStatus::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    status = *m;
    ++statuses;
  }
  void onMetrics(const coil_winding_sim::WindingMetrics::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    metrics = *m;
    ++metrics_count;
  }
  void onDiagnostics(const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    for (const auto& s : m->status) {
      if (s.name.find("simulation") != std::string::npos) diagnostics = s.message;
    }
  }
  coil_winding_sim::CellStatus lastStatus() {
    std::lock_guard<std::mutex> l(mutex);
    return status;
  }
  coil_winding_sim::WindingMetrics lastMetrics() {
    std::lock_guard<std::mutex> l(mutex);
    return metrics;
  }
  std::mutex mutex;
  coil_winding_sim::CellStatus status;
  coil_winding_sim::WindingMetrics metrics;
  std::string diagnostics;
  int statuses = 0, metrics_count = 0;
  std::vector<std::string> warnings;
  ros::Subscriber status_sub, metrics_sub, diag_sub, log_sub;
};

TEST(CellStartEnd, AtRestUntilASetpointThenEndsAtTheTurnsTurned) {
  Listener l;
  using S = coil_winding_sim::CellStatus;
  ASSERT_TRUE(waitFor([&] { return l.lastStatus().state == S::AT_REST; }, 30.0))
      << "cell_status: '" << l.lastStatus().state << "'";
  // At rest while the simulated time goes on: the core does not turn.
  ASSERT_TRUE(waitFor([&] { return l.lastMetrics().sim_time > 0.05; }, 30.0));
  const coil_winding_sim::WindingMetrics rest = l.lastMetrics();
  EXPECT_EQ(rest.core_turns, 0.0);
  EXPECT_EQ(rest.core_angular_velocity, 0.0);
  EXPECT_FALSE(rest.job_done);

  // A controller takes over: 1 turn/s, then 2 turns/s once 0.1 turns are done.
  ros::NodeHandle nh;
  ros::Publisher pub =
      nh.advertise<coil_winding_sim::CoreSpeedSetpoint>("core_speed_setpoint", 1, true);
  ASSERT_TRUE(waitFor([&] { return pub.getNumSubscribers() > 0; }, 10.0));
  coil_winding_sim::CoreSpeedSetpoint sp;
  sp.angular_velocity = 2.0 * M_PI;  // [rad/s]
  pub.publish(sp);
  ASSERT_TRUE(waitFor(
      [&] { return std::abs(l.lastMetrics().core_angular_velocity - 2.0 * M_PI) < 1e-9; }, 30.0))
      << "the core did not reach the setpoint: " << l.lastMetrics().core_angular_velocity;
  EXPECT_EQ(l.lastStatus().state, S::RUNNING);
  ASSERT_TRUE(waitFor([&] { return l.lastMetrics().core_turns > 0.1; }, 30.0));
  ASSERT_LT(l.lastMetrics().core_turns, 0.45) << "too late for the second setpoint";
  sp.angular_velocity = 4.0 * M_PI;
  pub.publish(sp);

  // The job's end: 0.5 turns of actual rotation.
  ASSERT_TRUE(waitFor([&] { return l.lastStatus().state == S::JOB_DONE; }, 60.0))
      << "cell_status: '" << l.lastStatus().state << "', turns " << l.lastMetrics().core_turns;
  const coil_winding_sim::CellStatus done = l.lastStatus();
  EXPECT_TRUE(done.job_done);
  EXPECT_NEAR(done.core_turns, 0.5, 1e-6);
  EXPECT_NE(done.message.find("job done: 0.5 turns"), std::string::npos) << done.message;
  ASSERT_TRUE(waitFor([&] { return l.lastMetrics().job_done; }, 10.0));
  const coil_winding_sim::WindingMetrics end = l.lastMetrics();
  EXPECT_NEAR(end.core_turns, 0.5, 1e-6);
  // Not the scene's own end: 0.5 turns at its 600 rpm would end at 0.05 s,
  // before the core had even left its rest.
  EXPECT_GT(end.sim_time, rest.sim_time + 0.2);
  // Held at the end: the simulated time stands still.
  ros::WallDuration(0.5).sleep();
  EXPECT_EQ(l.lastMetrics().sim_time, end.sim_time);
  EXPECT_TRUE(waitFor(
      [&] {
        std::lock_guard<std::mutex> lock(l.mutex);
        return l.diagnostics.find("job done") != std::string::npos;
      },
      10.0))
      << "diagnostics: " << l.diagnostics;

  // A setpoint while the cell holds the finished job: refused, with why
  // and what to do; nothing moves.
  sp.angular_velocity = 3.0;
  pub.publish(sp);
  EXPECT_TRUE(waitFor(
      [&] { return l.warned("refused core_speed_setpoint 3 rad/s: the job is done"); }, 10.0));
  EXPECT_TRUE(l.warned("call ~reset or ~restore to wind again"));
  ros::WallDuration(0.3).sleep();
  EXPECT_EQ(l.lastMetrics().sim_time, end.sim_time);
  EXPECT_NEAR(l.lastMetrics().core_angular_velocity_setpoint, 4.0 * M_PI, 1e-12);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_cell_start_end");
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
