// The node's /diagnostics when the implicit steps fall back to explicit
// ones (issue 39, "progress is guaranteed"): the cell runs bdf2 with Newton
// allowed one iteration and solver.min_step at 1e-6 s, so Newton fails
// down to the smallest step from the start and the stepper takes stretches
// of explicit steps. The simulation's status turns
// WARN within one second of wall time of the cell's first step (the node
// reports its diagnostics once a second), names the cause, counts the
// stretches, and the cell keeps running at its pace.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <mutex>
#include <string>

#include "coil_winding_sim/WindingMetrics.h"
#include "ros_test_support.hpp"

namespace {

using cws_ros_test::waitFor;

struct Listener {
  Listener() {
    ros::NodeHandle nh;
    metrics_sub = nh.subscribe("winding_metrics", 10, &Listener::onMetrics, this);
    diag_sub = nh.subscribe("/diagnostics", 10, &Listener::onDiagnostics, this);
  }
  void onMetrics(const coil_winding_sim::WindingMetrics::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    sim_time = m->sim_time;
    if (first_step_wall < 0.0 && m->sim_time > 0.0) first_step_wall = ros::WallTime::now().toSec();
  }
  void onDiagnostics(const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    for (const auto& s : m->status) {
      if (s.name.find("simulation") == std::string::npos) continue;
      if (s.level == diagnostic_msgs::DiagnosticStatus::WARN && warn_wall < 0.0) {
        warn_wall = ros::WallTime::now().toSec();
        warn = s;
      }
    }
  }
  std::mutex mutex;
  double sim_time = 0.0, first_step_wall = -1.0, warn_wall = -1.0;
  diagnostic_msgs::DiagnosticStatus warn;
  ros::Subscriber metrics_sub, diag_sub;
};

TEST(FallbackDiagnostics, WarnsWithinASecondWithTheCause) {
  Listener l;
  ASSERT_TRUE(waitFor(
      [&] {
        std::lock_guard<std::mutex> lock(l.mutex);
        return l.first_step_wall >= 0.0;
      },
      30.0))
      << "the cell did not start";
  ASSERT_TRUE(waitFor(
      [&] {
        std::lock_guard<std::mutex> lock(l.mutex);
        return l.warn_wall >= 0.0;
      },
      10.0))
      << "no WARN on /diagnostics";
  std::lock_guard<std::mutex> lock(l.mutex);
  // One second of the node's reporting period, and the metrics' own period
  // (10 Hz) and delivery: 1.2 s.
  EXPECT_LT(l.warn_wall - l.first_step_wall, 1.2);
  EXPECT_NE(l.warn.message.find("explicit steps where Newton could not go on"), std::string::npos)
      << l.warn.message;
  EXPECT_NE(l.warn.message.find("Newton did not converge"), std::string::npos) << l.warn.message;
  bool counted = false;
  for (const auto& kv : l.warn.values) {
    if (kv.key == "explicit fallback stretches") counted = std::stol(kv.value) > 0;
  }
  EXPECT_TRUE(counted);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_fallback_diagnostics");
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
