// rostest (port_input.test): port_position_setpoint and the machine
// command adapter (machine/spindle/command, machine/port/command) refuse
// bad messages with a warning naming the problem and keep the last good
// setpoint; good ones apply. A trajectory_msgs/JointTrajectory drives the
// spindle and the port at its points' times.
#include <geometry_msgs/PointStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>
#include <sensor_msgs/JointState.h>
#include <trajectory_msgs/JointTrajectory.h>

#include <limits>
#include <mutex>
#include <string>
#include <vector>

#include "coil_winding_sim/WindingMetrics.h"
#include "ros_test_support.hpp"

namespace {
std::mutex mutex;
coil_winding_sim::WindingMetrics metrics;
geometry_msgs::PointStamped port;
int port_count = 0, metrics_count = 0;
std::vector<std::string> warnings;

void onMetrics(const coil_winding_sim::WindingMetrics::ConstPtr& m) {
  std::lock_guard<std::mutex> l(mutex);
  metrics = *m;
  ++metrics_count;
}
void onPort(const geometry_msgs::PointStamped::ConstPtr& m) {
  std::lock_guard<std::mutex> l(mutex);
  port = *m;
  ++port_count;
}
void onLog(const rosgraph_msgs::Log::ConstPtr& m) {
  std::lock_guard<std::mutex> l(mutex);
  if (m->level == rosgraph_msgs::Log::WARN) warnings.push_back(m->msg);
}

geometry_msgs::Point portNow() {
  std::lock_guard<std::mutex> l(mutex);
  return port.point;
}
double speedSetpoint() {
  std::lock_guard<std::mutex> l(mutex);
  return metrics.core_angular_velocity_setpoint;
}
bool warned(const std::string& words) {
  return cws_ros_test::waitFor(
      [&] {
        std::lock_guard<std::mutex> l(mutex);
        for (const std::string& w : warnings) {
          if (w.find(words) != std::string::npos) return true;
        }
        return false;
      },
      10.0);
}

using cws_ros_test::waitFor;
const double kX = 5.5e-3, kY = -0.03;  // the scene's port [m]
}  // namespace

TEST(PortInput, BadPortSetpointsAreRefused) {
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<geometry_msgs::PointStamped>("port_position_setpoint", 10);
  ASSERT_TRUE(waitFor([&] { return port_count > 0 && pub.getNumSubscribers() > 0; }, 30.0));
  EXPECT_DOUBLE_EQ(portNow().x, kX);
  geometry_msgs::PointStamped sp;
  sp.header.frame_id = "world";
  sp.point.x = std::numeric_limits<double>::quiet_NaN();
  pub.publish(sp);
  EXPECT_TRUE(warned("refused port_position_setpoint: the point is not finite"));
  ros::WallDuration(1.1).sleep();  // one warning a second per kind
  sp.header.frame_id = "core";
  sp.point.x = kX;
  sp.point.y = kY;
  pub.publish(sp);
  EXPECT_TRUE(warned("refused port_position_setpoint: frame 'core' is not 'world'"));
  ros::WallDuration(1.1).sleep();
  sp.header.frame_id = "world";
  sp.point.x = 0.0;
  sp.point.y = 1e-3;
  pub.publish(sp);
  EXPECT_TRUE(warned("inside the turning core"));
  EXPECT_DOUBLE_EQ(portNow().x, kX);
  EXPECT_DOUBLE_EQ(portNow().y, kY);
  // A good one: reached ~port_move_time (10 ms simulated) later.
  sp.point.x = kX;
  sp.point.y = kY;
  sp.point.z = 2e-4;
  pub.publish(sp);
  EXPECT_TRUE(waitFor([] { return std::abs(portNow().z - 2e-4) < 1e-12; }, 30.0))
      << "port at z = " << portNow().z;
}

TEST(PortInput, BadMachineSpindleCommandsAreRefused) {
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<sensor_msgs::JointState>("machine/spindle/command", 10);
  ASSERT_TRUE(waitFor([&] { return metrics_count > 0 && pub.getNumSubscribers() > 0; }, 30.0));
  const double before = speedSetpoint();
  sensor_msgs::JointState js;
  js.name = {"other"};
  js.velocity = {5.0};
  pub.publish(js);
  EXPECT_TRUE(warned("refused machine/spindle/command: no joint named 'spindle'"));
  ros::WallDuration(1.1).sleep();
  js.name = {"spindle"};
  js.velocity.clear();
  pub.publish(js);
  EXPECT_TRUE(warned("refused machine/spindle/command: no velocity for joint 'spindle'"));
  ros::WallDuration(1.1).sleep();
  js.velocity = {std::numeric_limits<double>::quiet_NaN()};
  pub.publish(js);
  EXPECT_TRUE(
      warned("refused machine/spindle/command: the velocity of joint 'spindle' is not finite"));
  ros::WallDuration(0.5).sleep();
  EXPECT_EQ(speedSetpoint(), before);
  js.velocity = {7.0};
  pub.publish(js);
  EXPECT_TRUE(waitFor([] { return speedSetpoint() == 7.0; }, 10.0));
}

// Trajectories of the spindle and the port (joint_trajectory), stamped
// zero: from the simulated time they arrive at.
TEST(PortInput, JointTrajectoriesDriveTheSpindleAndThePort) {
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<trajectory_msgs::JointTrajectory>("joint_trajectory", 10);
  ASSERT_TRUE(waitFor([&] { return metrics_count > 0 && pub.getNumSubscribers() > 0; }, 30.0));
  auto point = [](double t, double position, double velocity, bool with_velocity) {
    trajectory_msgs::JointTrajectoryPoint p;
    p.time_from_start = ros::Duration(t);
    p.positions = {position};
    if (with_velocity) p.velocities = {velocity};
    return p;
  };
  // The spindle: 3 rad/s now, 6 rad/s 20 ms (simulated) later.
  trajectory_msgs::JointTrajectory spindle;
  spindle.joint_names = {"spindle"};
  spindle.points = {point(0.0, 0.0, 3.0, true), point(0.02, 0.0, 6.0, true)};
  double t0 = 0.0;
  {
    std::lock_guard<std::mutex> l(mutex);
    t0 = metrics.sim_time;
  }
  pub.publish(spindle);
  EXPECT_TRUE(waitFor([] { return speedSetpoint() == 3.0; }, 20.0)) << speedSetpoint();
  double t_six = -1.0;
  EXPECT_TRUE(waitFor(
      [&] {
        std::lock_guard<std::mutex> l(mutex);
        if (metrics.core_angular_velocity_setpoint == 6.0 && t_six < 0.0) t_six = metrics.sim_time;
        return t_six >= 0.0;
      },
      60.0));
  EXPECT_GE(t_six, t0 + 0.02);
  EXPECT_LT(t_six, t0 + 0.05);

  // The port: z to 2 mm 10 ms from now; x and y stay.
  trajectory_msgs::JointTrajectory port;
  port.joint_names = {"port_z"};
  port.points = {point(0.01, 0.002, 0.0, false)};
  pub.publish(port);
  EXPECT_TRUE(waitFor([] { return std::abs(portNow().z - 0.002) < 1e-12; }, 60.0)) << portNow().z;
  EXPECT_DOUBLE_EQ(portNow().x, kX);

  // A joint the cell does not have: refused by name.
  port.joint_names = {"elbow"};
  pub.publish(port);
  EXPECT_TRUE(warned("refused joint_trajectory: joint 'elbow' is not one of the cell's"));
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_port_input");
  ros::NodeHandle nh;
  ros::Subscriber s1 = nh.subscribe("winding_metrics", 10, onMetrics);
  ros::Subscriber s2 = nh.subscribe("sim/port/position", 100, onPort);
  ros::Subscriber s3 = nh.subscribe("/rosout", 1000, onLog);
  ros::AsyncSpinner spinner(1);
  spinner.start();
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
