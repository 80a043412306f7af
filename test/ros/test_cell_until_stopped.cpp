// rostest of the cell's default run (cell_until_stopped.test): without a job
// end the cell winds on past the scene's process.turns (1.75) with no
// job_done; when the wire's storage (~max_points 450) is full it holds,
// says so on cell_status, /diagnostics (WARN) and the console, refuses a
// speed setpoint with a warning that says why and what to do, and ~reset
// winds again.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>
#include <std_srvs/Trigger.h>

#include <algorithm>
#include <mutex>
#include <string>
#include <vector>

#include "coil_winding_sim/CellStatus.h"
#include "coil_winding_sim/CoreSpeedSetpoint.h"
#include "coil_winding_sim/WindingMetrics.h"
#include "ros_test_support.hpp"

namespace {

using cws_ros_test::waitFor;
using S = coil_winding_sim::CellStatus;

struct Listener {
  Listener() {
    ros::NodeHandle nh;
    status_sub = nh.subscribe("cell_status", 10, &Listener::onStatus, this);
    metrics_sub = nh.subscribe("winding_metrics", 100, &Listener::onMetrics, this);
    diag_sub = nh.subscribe("/diagnostics", 10, &Listener::onDiagnostics, this);
    log_sub = nh.subscribe("/rosout", 1000, &Listener::onLog, this);
  }
  void onStatus(const S::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    status = *m;
  }
  void onMetrics(const coil_winding_sim::WindingMetrics::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    metrics = *m;
    // The most turns seen while the cell said it was winding.
    if (status.state == S::RUNNING && !m->job_done)
      turns_running = std::max(turns_running, m->core_turns);
  }
  void onDiagnostics(const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    for (const auto& s : m->status) {
      if (s.name.find("simulation") == std::string::npos) continue;
      diagnostics = s.message;
      diagnostics_level = s.level;
    }
  }
  void onLog(const rosgraph_msgs::Log::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    if (m->level == rosgraph_msgs::Log::WARN) warnings.push_back(m->msg);
  }
  template <class T>
  T read(const T& field) {
    std::lock_guard<std::mutex> l(mutex);
    return field;
  }
  bool warned(const std::string& words) {
    std::lock_guard<std::mutex> l(mutex);
    for (const std::string& w : warnings) {
      if (w.find(words) != std::string::npos) return true;
    }
    return false;
  }
  std::mutex mutex;
  S status;
  coil_winding_sim::WindingMetrics metrics;
  double turns_running = 0.0;
  std::string diagnostics;
  int diagnostics_level = -1;
  std::vector<std::string> warnings;
  ros::Subscriber status_sub, metrics_sub, diag_sub, log_sub;
};

TEST(CellUntilStopped, WindsPastTheJobHoldsWhenFullAndRefusesSetpoints) {
  Listener l;
  // Past the scene's 1.75 turns, still winding, no job done.
  ASSERT_TRUE(waitFor([&] { return l.read(l.turns_running) > 3.0; }, 60.0))
      << "turns while running: " << l.read(l.turns_running)
      << ", state: " << l.read(l.status).state;

  // 450 points hold about 7 turns of the paper's core, less than the 8
  // turns of wound wire that stay live (WireModel::keepTurns): the cell
  // holds.
  ASSERT_TRUE(waitFor([&] { return l.read(l.status).state == S::FULL; }, 60.0))
      << "cell_status: '" << l.read(l.status).state << "'";
  const S full = l.read(l.status);
  EXPECT_FALSE(full.job_done);
  EXPECT_NE(full.message.find("~max_points"), std::string::npos) << full.message;
  EXPECT_TRUE(waitFor([&] { return l.warned("the wire's storage is full"); }, 10.0));
  EXPECT_TRUE(waitFor(
      [&] {
        return l.read(l.diagnostics_level) == diagnostic_msgs::DiagnosticStatus::WARN &&
               l.read(l.diagnostics).find("storage is full") != std::string::npos;
      },
      10.0))
      << "/diagnostics: " << l.read(l.diagnostics);

  // It holds: the simulated time stands, and a setpoint is refused.
  ASSERT_TRUE(waitFor([&] { return l.read(l.metrics).sim_time > 0.0; }, 10.0));
  const coil_winding_sim::WindingMetrics held = l.read(l.metrics);
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<coil_winding_sim::CoreSpeedSetpoint>("core_speed_setpoint", 1);
  ASSERT_TRUE(waitFor([&] { return pub.getNumSubscribers() > 0; }, 10.0));
  coil_winding_sim::CoreSpeedSetpoint sp;
  sp.angular_velocity = 20.0;
  pub.publish(sp);
  EXPECT_TRUE(waitFor(
      [&] { return l.warned("refused core_speed_setpoint 20 rad/s: the wire's storage is full"); },
      10.0));
  EXPECT_TRUE(l.warned("call ~reset or ~restore to wind again"));
  ros::WallDuration(0.5).sleep();
  const coil_winding_sim::WindingMetrics after = l.read(l.metrics);
  EXPECT_EQ(after.sim_time, held.sim_time);
  EXPECT_EQ(after.core_angular_velocity_setpoint, held.core_angular_velocity_setpoint);
  EXPECT_NE(after.core_angular_velocity_setpoint, 20.0);

  // A reset winds again.
  std_srvs::Trigger reset;
  ASSERT_TRUE(ros::service::call("winding_cell/reset", reset));
  EXPECT_TRUE(reset.response.success) << reset.response.message;
  EXPECT_TRUE(waitFor([&] { return l.read(l.status).state == S::RUNNING; }, 20.0))
      << "cell_status after reset: '" << l.read(l.status).state << "'";
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_cell_until_stopped");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
