// rostest of the cell's real-time factor (cell_pace.test): one figure,
// simulated over wall time in the last second of wall time, on
// winding_metrics, cell_status and /diagnostics; it agrees with the
// simulated time the test sees pass on winding_metrics against its own
// clock. A cell far behind its target says `slow` on cell_status, with the
// factor and the cause (its steps and their work), again once a second.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <cmath>
#include <cstdio>
#include <mutex>
#include <string>
#include <vector>

#include "coil_winding_sim/CellStatus.h"
#include "coil_winding_sim/WindingMetrics.h"
#include "ros_test_support.hpp"

namespace {

using cws_ros_test::waitFor;
using S = coil_winding_sim::CellStatus;

struct Sample {
  double wall_s, sim_s, rtf;
};

struct Listener {
  Listener() {
    ros::NodeHandle nh;
    status_sub = nh.subscribe("cell_status", 10, &Listener::onStatus, this);
    metrics_sub = nh.subscribe("winding_metrics", 100, &Listener::onMetrics, this);
    diagnostics_sub = nh.subscribe("/diagnostics", 10, &Listener::onDiagnostics, this);
  }
  void onStatus(const S::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    statuses.push_back(*m);
  }
  void onMetrics(const coil_winding_sim::WindingMetrics::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    metrics.push_back({ros::WallTime::now().toSec(), m->sim_time, m->real_time_factor});
  }
  void onDiagnostics(const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    for (const auto& s : m->status) {
      if (s.name.find("simulation") == std::string::npos) continue;
      for (const auto& kv : s.values) {
        if (kv.key == "real-time factor") diagnostics_rtf = std::stod(kv.value);
      }
      diagnostics_message = s.message;
    }
  }
  std::mutex mutex;
  std::vector<S> statuses;
  std::vector<Sample> metrics;
  double diagnostics_rtf = -1.0;
  std::string diagnostics_message;
  ros::Subscriber status_sub, metrics_sub, diagnostics_sub;
};

TEST(CellPace, OneRealTimeFactorAndASlowCellSaysWhy) {
  Listener l;
  // Slow after a second behind the target.
  ASSERT_TRUE(waitFor(
      [&] {
        std::lock_guard<std::mutex> g(l.mutex);
        return !l.statuses.empty() && l.statuses.back().state == S::SLOW;
      },
      20.0))
      << "cell_status never said slow";
  // Three seconds more: the factor settles, the status comes again.
  ros::WallDuration(3.0).sleep();
  std::lock_guard<std::mutex> g(l.mutex);
  const S& s = l.statuses.back();
  std::printf("cell_status: %s: %s (factor %.4g)\n", s.state.c_str(), s.message.c_str(),
              s.real_time_factor);
  EXPECT_EQ(s.state, S::SLOW);
  EXPECT_NE(s.message.find("real-time factor"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("steps of"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("retried"), std::string::npos) << s.message;
  int slow_statuses = 0;
  for (const S& x : l.statuses) slow_statuses += x.state == S::SLOW;
  EXPECT_GE(slow_statuses, 3) << "a slow cell's status should come again once a second";
  EXPECT_GT(s.real_time_factor, 0.0);
  EXPECT_LT(s.real_time_factor, 10000.0);
  EXPECT_NE(l.diagnostics_message.find("slow"), std::string::npos) << l.diagnostics_message;

  // The factor's definition, checked against the test's own clock: the
  // simulated time that passed in the last second of wall time, from the
  // metrics' arrival times.
  ASSERT_GE(l.metrics.size(), 40u);
  const Sample& last = l.metrics.back();
  const Sample* before = nullptr;
  for (const Sample& x : l.metrics) {
    if (last.wall_s - x.wall_s >= 1.0) before = &x;
  }
  ASSERT_NE(before, nullptr);
  const double seen = (last.sim_s - before->sim_s) / (last.wall_s - before->wall_s);
  std::printf(
      "real-time factor: winding_metrics %.4g, cell_status %.4g, /diagnostics %.4g; seen over "
      "%.2f s of wall time %.4g\n",
      last.rtf, s.real_time_factor, l.diagnostics_rtf, last.wall_s - before->wall_s, seen);
  EXPECT_NEAR(last.rtf / seen, 1.0, 0.15);
  // (cell_status and /diagnostics were each taken at an earlier moment,
  // over their own second: the machine's jitter, not another definition.)
  EXPECT_NEAR(s.real_time_factor / seen, 1.0, 0.4);
  EXPECT_NEAR(l.diagnostics_rtf / seen, 1.0, 0.4);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_cell_pace");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
