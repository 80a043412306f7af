// rostest of a coil's plan in the cell running until stopped (cell_plan.test,
// issue 57): the scene plans 6 turns in 2 layers on a bobbin that holds 9.
// - At the job's end the spindle is braked to rest (the core turns on by
//   omega^2 / (2 a) = 0.063 turns at 1200 rpm and 2e4 rad/s^2) and the cell
//   holds "job done" with why; the simulated time stands still.
// - A speed setpoint winds on, in a third layer, until the bobbin is full at
//   9 turns: the spindle stops again and the cell says so.
// - A wind goal then is refused with the bobbin's capacity.
#include <actionlib/client/simple_action_client.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <cmath>
#include <mutex>
#include <string>

#include "coil_winding_sim/CellStatus.h"
#include "coil_winding_sim/CoreSpeedSetpoint.h"
#include "coil_winding_sim/WindAction.h"
#include "coil_winding_sim/WindingMetrics.h"
#include "ros_test_support.hpp"

namespace {

using cws_ros_test::waitFor;

struct Listener {
  Listener() {
    ros::NodeHandle nh;
    status_sub = nh.subscribe("cell_status", 10, &Listener::onStatus, this);
    metrics_sub = nh.subscribe("winding_metrics", 10, &Listener::onMetrics, this);
  }
  void onStatus(const coil_winding_sim::CellStatus::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    status = *m;
  }
  void onMetrics(const coil_winding_sim::WindingMetrics::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    metrics = *m;
    ++metrics_count;
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
  int metrics_count = 0;
  ros::Subscriber status_sub, metrics_sub;
};

bool contains(const std::string& text, const std::string& words) {
  return text.find(words) != std::string::npos;
}

TEST(CellPlan, TheJobsEndStopsTheSpindleAndAFullBobbinStopsItForGood) {
  Listener l;
  // The job's end: the spindle braked to rest, the cell holding.
  ASSERT_TRUE(waitFor([&] { return l.lastStatus().job_done; }, 200.0))
      << "state " << l.lastStatus().state << ": " << l.lastStatus().message;
  const coil_winding_sim::CellStatus done = l.lastStatus();
  EXPECT_EQ(done.state, coil_winding_sim::CellStatus::JOB_DONE);
  EXPECT_TRUE(contains(done.message,
                       "the spindle stopped at the scene's plan of 6 turns in 2 "
                       "layers"))
      << done.message;
  EXPECT_TRUE(contains(done.message, "up to the bobbin's 9 turns")) << done.message;
  EXPECT_GE(done.core_turns, 6.0);
  EXPECT_LT(done.core_turns, 6.0 + 0.063 + 0.01);
  ASSERT_TRUE(waitFor([&] { return l.lastMetrics().job_done; }, 10.0));
  EXPECT_EQ(l.lastMetrics().core_angular_velocity, 0.0);
  const double held_at = l.lastMetrics().sim_time;
  ros::WallDuration(1.0).sleep();
  EXPECT_EQ(l.lastMetrics().sim_time, held_at);

  // A speed setpoint winds on, into the third layer, up to the full bobbin.
  ros::NodeHandle nh;
  ros::Publisher speed =
      nh.advertise<coil_winding_sim::CoreSpeedSetpoint>("core_speed_setpoint", 1, true);
  coil_winding_sim::CoreSpeedSetpoint w;
  w.angular_velocity = 1200.0 * 2.0 * M_PI / 60.0;
  speed.publish(w);
  ASSERT_TRUE(waitFor([&] { return l.lastMetrics().core_turns > 6.2; }, 60.0))
      << l.lastStatus().message;
  ASSERT_TRUE(waitFor(
      [&] {
        const coil_winding_sim::CellStatus s = l.lastStatus();
        return s.job_done && contains(s.message, "full");
      },
      200.0))
      << l.lastStatus().message;
  const coil_winding_sim::CellStatus full = l.lastStatus();
  EXPECT_TRUE(contains(full.message, "the bobbin is full at 9 turns")) << full.message;
  EXPECT_GE(full.core_turns, 9.0);
  EXPECT_LT(full.core_turns, 9.0 + 0.063 + 0.01);
  ASSERT_TRUE(waitFor([&] { return l.lastMetrics().core_angular_velocity == 0.0; }, 10.0));

  // A wind goal on the full bobbin: refused, with its capacity.
  actionlib::SimpleActionClient<coil_winding_sim::WindAction> client("wind", true);
  ASSERT_TRUE(client.waitForServer(ros::Duration(30.0)));
  coil_winding_sim::WindGoal goal;
  goal.turns = 1.0;
  client.sendGoal(goal);
  ASSERT_TRUE(client.waitForResult(ros::Duration(30.0)));
  EXPECT_EQ(client.getState(), actionlib::SimpleClientGoalState::ABORTED);
  EXPECT_TRUE(contains(client.getResult()->message, "9 turns")) << client.getResult()->message;
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_cell_plan");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
