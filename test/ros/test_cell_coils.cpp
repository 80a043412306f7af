// Three coils in a row on one cell (cell_coils.test, the default scene):
// a goal of 3 turns winds coil 1; a goal of 2 turns with new_coil takes it
// off (coil_done: coil 1, its 3 turns) and winds coil 2 on an empty bobbin;
// ~change_coil takes coil 2 off (its 2 turns), and the new bobbin waits at
// rest; a goal of 4 turns winds coil 3, which ~change_coil takes off with
// its 4 turns. The node's clock runs on throughout: /clock never goes back.
#include <actionlib/client/simple_action_client.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <std_srvs/Trigger.h>

#include <mutex>
#include <string>
#include <vector>

#include "coil_winding_sim/CoilDone.h"
#include "coil_winding_sim/WindAction.h"
#include "coil_winding_sim/WindingMetrics.h"
#include "ros_test_support.hpp"

namespace {

using Client = actionlib::SimpleActionClient<coil_winding_sim::WindAction>;
using State = actionlib::SimpleClientGoalState;
using cws_ros_test::waitFor;

struct Listener {
  Listener() {
    ros::NodeHandle nh;
    done_sub = nh.subscribe("coil_done", 10, &Listener::onDone, this);
    clock_sub = nh.subscribe("/clock", 1000, &Listener::onClock, this);
  }
  void onDone(const coil_winding_sim::CoilDone::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    done.push_back(*m);
  }
  void onClock(const rosgraph_msgs::Clock::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    const double t = m->clock.toSec();
    if (t < last_clock) ++clock_back;
    last_clock = t;
  }
  std::size_t doneCount() {
    std::lock_guard<std::mutex> l(mutex);
    return done.size();
  }
  std::mutex mutex;
  std::vector<coil_winding_sim::CoilDone> done;
  double last_clock = -1.0;
  int clock_back = 0;
  ros::Subscriber done_sub, clock_sub;
};

coil_winding_sim::WindResult wind(Client& client, double turns, bool new_coil) {
  coil_winding_sim::WindGoal goal;
  goal.turns = turns;
  goal.new_coil = new_coil;
  client.sendGoal(goal);
  EXPECT_TRUE(client.waitForResult(ros::Duration(120.0))) << turns << " turns did not end";
  EXPECT_EQ(client.getState(), State::SUCCEEDED) << client.getState().getText();
  return client.getResult() ? *client.getResult() : coil_winding_sim::WindResult();
}

TEST(CellCoils, ThreeCoilsInARow) {
  Listener l;
  ros::NodeHandle nh;
  Client client("wind", true);
  ASSERT_TRUE(client.waitForServer(ros::Duration(60.0)));
  ros::ServiceClient change = nh.serviceClient<std_srvs::Trigger>("winding_cell/change_coil");
  ASSERT_TRUE(change.waitForExistence(ros::Duration(30.0)));

  // Coil 1: 3 turns.
  const coil_winding_sim::WindResult r1 = wind(client, 3.0, false);
  EXPECT_NEAR(r1.turns, 3.0, 1e-6);
  const double t1 = r1.sim_time;
  EXPECT_EQ(l.doneCount(), 0u);

  // Coil 2 on a new bobbin: coil 1 reported, and the goal's turns start from 0.
  const coil_winding_sim::WindResult r2 = wind(client, 2.0, true);
  ASSERT_TRUE(waitFor([&] { return l.doneCount() >= 1; }, 10.0)) << "no coil_done for coil 1";
  {
    std::lock_guard<std::mutex> g(l.mutex);
    const coil_winding_sim::CoilDone& d = l.done[0];
    EXPECT_EQ(d.coil, 1);
    EXPECT_NEAR(d.core_turns, 3.0, 1e-6);
    EXPECT_NEAR(d.duration, t1, 1e-9);
    EXPECT_FALSE(d.summary.empty());
  }
  EXPECT_NEAR(r2.turns, 2.0, 1e-6);
  // (The coil's own time: the new simulation starts at 0.)
  EXPECT_NEAR(r2.duration, r2.sim_time, 1e-9);

  // Coil 2 off by the service.
  std_srvs::Trigger t;
  ASSERT_TRUE(change.call(t));
  ASSERT_TRUE(t.response.success) << t.response.message;
  EXPECT_NE(t.response.message.find("coil 2 taken off"), std::string::npos) << t.response.message;
  ASSERT_TRUE(waitFor([&] { return l.doneCount() >= 2; }, 10.0)) << "no coil_done for coil 2";
  {
    std::lock_guard<std::mutex> g(l.mutex);
    EXPECT_EQ(l.done[1].coil, 2);
    EXPECT_NEAR(l.done[1].core_turns, 2.0, 1e-6);
  }

  // Coil 3: its bobbin waited at rest for the goal, so it holds the goal's
  // turns, as coil_done says when it is taken off in turn.
  const coil_winding_sim::WindResult r3 = wind(client, 4.0, false);
  EXPECT_NEAR(r3.turns, 4.0, 1e-6);
  ASSERT_TRUE(change.call(t));
  ASSERT_TRUE(t.response.success) << t.response.message;
  ASSERT_TRUE(waitFor([&] { return l.doneCount() >= 3; }, 10.0)) << "no coil_done for coil 3";
  std::lock_guard<std::mutex> g(l.mutex);
  EXPECT_EQ(l.done[2].coil, 3);
  EXPECT_NEAR(l.done[2].core_turns, 4.0, 1e-6);
  EXPECT_LT(l.done[0].header.stamp, l.done[1].header.stamp);
  EXPECT_LT(l.done[1].header.stamp, l.done[2].header.stamp);
  EXPECT_GT(l.last_clock, 0.0);
  EXPECT_EQ(l.clock_back, 0) << "/clock went back at a coil change";
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_cell_coils");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
