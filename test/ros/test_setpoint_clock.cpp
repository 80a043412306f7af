// rostest (setpoint_clock.test): setpoint stamps when /clock comes from
// another node (here this test; e.g. `rosbag play --clock`). Before the
// first /clock no stamp is checked against the clock; when the clock goes
// back (a looping bag starts over) the stamps of the last setpoints are
// forgotten, so that the new time line is heard.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>

#include <functional>
#include <mutex>

#include "coil_winding_sim/CoreSpeedSetpoint.h"
#include "coil_winding_sim/WindingMetrics.h"
#include "ros_test_support.hpp"

namespace {
std::mutex mutex;
coil_winding_sim::WindingMetrics metrics;
int count = 0;

void onMetrics(const coil_winding_sim::WindingMetrics::ConstPtr& m) {
  std::lock_guard<std::mutex> l(mutex);
  metrics = *m;
  ++count;
}

coil_winding_sim::WindingMetrics latest() {
  std::lock_guard<std::mutex> l(mutex);
  return metrics;
}

using cws_ros_test::waitFor;

// True if the speed setpoint stays `w` for a second (wall time).
bool stays(double w) {
  return !waitFor([&] { return latest().core_angular_velocity_setpoint != w; }, 1.0);
}

ros::Publisher *speed_pub, *clock_pub;

void publishSpeed(double w, double stamp_s) {
  coil_winding_sim::CoreSpeedSetpoint sp;
  sp.header.stamp = ros::Time(stamp_s);
  sp.angular_velocity = w;
  speed_pub->publish(sp);
}

// Sets the clock and waits until the node uses it (the stamp of its
// metrics is its ROS time).
bool setClock(double t) {
  rosgraph_msgs::Clock c;
  c.clock = ros::Time(t);
  clock_pub->publish(c);
  return waitFor([&] { return latest().header.stamp == c.clock; }, 10.0);
}
}  // namespace

TEST(SetpointClock, StampsAgainstAnExternalClock) {
  ASSERT_TRUE(waitFor([] { return count > 0; }, 30.0)) << "no metrics";
  // No /clock yet (ROS time zero): a stamped setpoint applies.
  ASSERT_TRUE(latest().header.stamp.isZero());
  publishSpeed(10.0, 50.0);
  EXPECT_TRUE(waitFor([] { return latest().core_angular_velocity_setpoint == 10.0; }, 10.0))
      << "refused before the first /clock";

  ASSERT_TRUE(setClock(100.0));
  publishSpeed(11.0, 100.5);  // within the tolerance (1 s)
  EXPECT_TRUE(waitFor([] { return latest().core_angular_velocity_setpoint == 11.0; }, 10.0));
  publishSpeed(12.0, 100.2);  // older than the last applied: dropped
  EXPECT_TRUE(stays(11.0)) << "an out-of-order setpoint was applied";
  publishSpeed(13.0, 150.0);  // 50 s ahead of the clock: refused
  EXPECT_TRUE(stays(11.0)) << "a setpoint from the future was applied";

  // The clock goes back: stamps of the new time line apply.
  ASSERT_TRUE(setClock(10.0));
  publishSpeed(14.0, 10.0);
  EXPECT_TRUE(waitFor([] { return latest().core_angular_velocity_setpoint == 14.0; }, 10.0))
      << "the stamps of the old time line blocked the new one";
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_setpoint_clock");
  ros::NodeHandle nh;
  ros::Subscriber sub = nh.subscribe("winding_metrics", 10, onMetrics);
  ros::Publisher sp = nh.advertise<coil_winding_sim::CoreSpeedSetpoint>("core_speed_setpoint", 10);
  ros::Publisher cp = nh.advertise<rosgraph_msgs::Clock>("/clock", 10);
  speed_pub = &sp;
  clock_pub = &cp;
  ros::AsyncSpinner spinner(1);
  spinner.start();
  waitFor([&] { return sp.getNumSubscribers() > 0 && cp.getNumSubscribers() > 0; }, 30.0);
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
