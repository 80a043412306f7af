// rostest of the wind action (cell_wind.test): the cell at rest takes a goal
// of 2 turns along a profile (a speed ramp to 1200 rpm, a tension step), sends
// feedback, ends on its turns with the coil report and the summary, and
// holds: a setpoint is refused. A goal of a duration winds on from there. A
// goal with both turns and a duration is refused with the reason; a long
// goal is cancelled and answers with the state it reached.
#include <actionlib/client/simple_action_client.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>

#include <cmath>
#include <mutex>
#include <string>
#include <vector>

#include "coil_winding_sim/CellStatus.h"
#include "coil_winding_sim/CoreSpeedSetpoint.h"
#include "coil_winding_sim/WindAction.h"
#include "coil_winding_sim/WindingMetrics.h"
#include "ros_test_support.hpp"

namespace {

using cws_ros_test::waitFor;
using Client = actionlib::SimpleActionClient<coil_winding_sim::WindAction>;
using State = actionlib::SimpleClientGoalState;

struct Listener {
  Listener() {
    ros::NodeHandle nh;
    status_sub = nh.subscribe("cell_status", 10, &Listener::onStatus, this);
    metrics_sub = nh.subscribe("winding_metrics", 10, &Listener::onMetrics, this);
    log_sub = nh.subscribe("/rosout", 1000, &Listener::onLog, this);
  }
  void onStatus(const coil_winding_sim::CellStatus::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    status = *m;
  }
  void onMetrics(const coil_winding_sim::WindingMetrics::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    metrics = *m;
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
  std::vector<std::string> warnings;
  ros::Subscriber status_sub, metrics_sub, log_sub;
};

struct Feedback {
  std::mutex mutex;
  std::vector<coil_winding_sim::WindFeedback> all;
  void on(const coil_winding_sim::WindFeedbackConstPtr& f) {
    std::lock_guard<std::mutex> l(mutex);
    all.push_back(*f);
  }
  std::size_t size() {
    std::lock_guard<std::mutex> l(mutex);
    return all.size();
  }
};

constexpr double kOmega = 1200.0 * 2.0 * M_PI / 60.0;  // [rad/s]

TEST(CellWind, GoalsOfTurnsAndDurationCancelAndRefusal) {
  Listener l;
  Client client("wind", true);
  ASSERT_TRUE(client.waitForServer(ros::Duration(30.0)));
  ASSERT_TRUE(waitFor([&] { return l.lastMetrics().sim_time > 0.0; }, 30.0));
  EXPECT_EQ(l.lastMetrics().core_turns, 0.0);  // at rest

  // Two turns: speed ramp 0 -> 1200 rpm over 20 ms, then held; tension 30
  // then 40 N.
  coil_winding_sim::WindGoal goal;
  goal.turns = 2.0;
  goal.profile_time = {0.0, 0.02, 0.05};
  goal.profile_core_speed = {0.0, kOmega, kOmega};
  goal.profile_tension = {30.0, 30.0, 40.0};
  Feedback fb;
  client.sendGoal(goal, Client::SimpleDoneCallback(), Client::SimpleActiveCallback(),
                  [&](const coil_winding_sim::WindFeedbackConstPtr& f) { fb.on(f); });
  ASSERT_TRUE(client.waitForResult(ros::Duration(120.0)));
  ASSERT_EQ(client.getState(), State::SUCCEEDED) << client.getState().getText();
  const coil_winding_sim::WindResult first = *client.getResult();
  EXPECT_NEAR(first.turns, 2.0, 1e-6);
  EXPECT_GT(first.duration, 0.11);  // 2 turns at 1200 rpm take 0.1 s, plus the ramp
  EXPECT_GT(first.wall_time, 0.0);
  EXPECT_FALSE(first.bulging_per_layer.empty());
  EXPECT_GE(first.layers, 1);
  EXPECT_NE(first.summary.find("\"bulging_height_m\""), std::string::npos) << first.summary;
  EXPECT_NE(first.summary.find("\"coil\""), std::string::npos);
  EXPECT_NE(first.message.find("done: 2 turns"), std::string::npos) << first.message;
  EXPECT_GT(fb.size(), 0u);
  {
    std::lock_guard<std::mutex> g(fb.mutex);
    for (std::size_t i = 1; i < fb.all.size(); ++i) EXPECT_GE(fb.all[i].turns, fb.all[i - 1].turns);
    EXPECT_LE(fb.all.back().turns, 2.0 + 1e-9);
  }
  // The profile's end values are in use.
  ASSERT_TRUE(waitFor([&] { return l.lastMetrics().sim_time >= first.sim_time; }, 10.0));
  EXPECT_NEAR(l.lastMetrics().core_angular_velocity_setpoint, kOmega, 1e-9);
  EXPECT_NEAR(l.lastMetrics().supply_tension, 40.0, 1e-9);

  // The cell holds: a setpoint is refused.
  ASSERT_TRUE(waitFor([&] { return l.lastStatus().job_done; }, 10.0));
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<coil_winding_sim::CoreSpeedSetpoint>("core_speed_setpoint", 1);
  ASSERT_TRUE(waitFor([&] { return pub.getNumSubscribers() > 0; }, 10.0));
  coil_winding_sim::CoreSpeedSetpoint sp;
  sp.angular_velocity = 5.0;
  pub.publish(sp);
  EXPECT_TRUE(waitFor(
      [&] { return l.warned("refused core_speed_setpoint 5 rad/s: the wind goal is done"); },
      10.0));

  // A goal of 10 ms winds on from there at the speed in use.
  coil_winding_sim::WindGoal more;
  more.duration = 0.01;
  client.sendGoal(more);
  ASSERT_TRUE(client.waitForResult(ros::Duration(60.0)));
  ASSERT_EQ(client.getState(), State::SUCCEEDED) << client.getState().getText();
  const coil_winding_sim::WindResult second = *client.getResult();
  EXPECT_NEAR(second.duration, 0.01, 1e-9);
  EXPECT_NEAR(second.sim_time, first.sim_time + 0.01, 1e-9);
  EXPECT_NEAR(second.turns, kOmega * 0.01 / (2.0 * M_PI), 1e-3);

  // Both turns and a duration: refused with the reason.
  coil_winding_sim::WindGoal bad;
  bad.turns = 1.0;
  bad.duration = 1.0;
  client.sendGoal(bad);
  ASSERT_TRUE(client.waitForResult(ros::Duration(30.0)));
  EXPECT_EQ(client.getState(), State::ABORTED);
  EXPECT_NE(client.getResult()->message.find("exactly one of turns and duration"),
            std::string::npos)
      << client.getResult()->message;

  // A long goal, cancelled: the answer carries the state it reached.
  coil_winding_sim::WindGoal longer;
  longer.turns = 60.0;  // within the bobbin's 75 turns
  Feedback fb2;
  client.sendGoal(longer, Client::SimpleDoneCallback(), Client::SimpleActiveCallback(),
                  [&](const coil_winding_sim::WindFeedbackConstPtr& f) { fb2.on(f); });
  ASSERT_TRUE(waitFor([&] { return fb2.size() > 2; }, 60.0));
  client.cancelGoal();
  ASSERT_TRUE(client.waitForResult(ros::Duration(30.0)));
  EXPECT_EQ(client.getState(), State::PREEMPTED);
  const coil_winding_sim::WindResult cancelled = *client.getResult();
  EXPECT_GT(cancelled.turns, 0.0);
  EXPECT_LT(cancelled.turns, 60.0);
  EXPECT_NE(cancelled.message.find("cancelled"), std::string::npos) << cancelled.message;
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_cell_wind");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
