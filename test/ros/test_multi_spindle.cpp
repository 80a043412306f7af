// rostest of two cells on one graph (multi_spindle.test): the frames
// spindle1/core, spindle2/core (and their supply ports) hang under the
// shared world and no cell broadcasts the unprefixed ones; a speed setpoint
// to /spindle1 turns spindle1's core and leaves spindle2's as it was.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <tf2_msgs/TFMessage.h>

#include <cmath>
#include <map>
#include <mutex>
#include <set>
#include <string>

#include "coil_winding_sim/CoreSpeedSetpoint.h"
#include "coil_winding_sim/WindingMetrics.h"
#include "ros_test_support.hpp"

namespace {

using cws_ros_test::waitFor;

struct Listener {
  Listener() {
    ros::NodeHandle nh;
    tf_sub = nh.subscribe("/tf", 1000, &Listener::onTf, this);
    for (const char* s : {"spindle1", "spindle2"}) {
      const std::string name = s;
      metrics_subs.push_back(nh.subscribe<coil_winding_sim::WindingMetrics>(
          "/" + name + "/winding_metrics", 10,
          [this, name](const coil_winding_sim::WindingMetrics::ConstPtr& m) {
            std::lock_guard<std::mutex> l(mutex);
            metrics[name] = *m;
          }));
    }
  }
  void onTf(const tf2_msgs::TFMessage::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    for (const auto& t : m->transforms) edges.insert(t.header.frame_id + " -> " + t.child_frame_id);
  }
  bool has(const std::string& edge) {
    std::lock_guard<std::mutex> l(mutex);
    return edges.count(edge) > 0;
  }
  // The latest metrics of `spindle` after `after` of simulated time.
  bool metricsAfter(const std::string& spindle, double after, coil_winding_sim::WindingMetrics& m) {
    std::lock_guard<std::mutex> l(mutex);
    auto it = metrics.find(spindle);
    if (it == metrics.end() || it->second.sim_time <= after) return false;
    m = it->second;
    return true;
  }
  std::mutex mutex;
  std::set<std::string> edges;
  std::map<std::string, coil_winding_sim::WindingMetrics> metrics;
  ros::Subscriber tf_sub;
  std::vector<ros::Subscriber> metrics_subs;
};

TEST(MultiSpindle, EachCellHasItsFramesAndItsSetpoints) {
  Listener l;
  ASSERT_TRUE(waitFor(
      [&] {
        return l.has("world -> spindle1/core") && l.has("world -> spindle2/core") &&
               l.has("world -> spindle1/supply_port") && l.has("world -> spindle2/supply_port");
      },
      30.0))
      << "the prefixed frames were not all broadcast";
  EXPECT_FALSE(l.has("world -> core"));
  EXPECT_FALSE(l.has("world -> supply_port"));

  // Both at the scene's 600 rpm; then spindle1 to 20 rad/s.
  coil_winding_sim::WindingMetrics m1, m2;
  ASSERT_TRUE(waitFor([&] { return l.metricsAfter("spindle1", 0.0, m1); }, 20.0));
  ASSERT_TRUE(waitFor([&] { return l.metricsAfter("spindle2", 0.0, m2); }, 20.0));
  const double scene_speed = 600.0 * 2.0 * M_PI / 60.0;  // [rad/s]
  EXPECT_NEAR(m1.core_angular_velocity_setpoint, scene_speed, 1e-9);
  EXPECT_NEAR(m2.core_angular_velocity_setpoint, scene_speed, 1e-9);
  ros::NodeHandle nh;
  ros::Publisher pub =
      nh.advertise<coil_winding_sim::CoreSpeedSetpoint>("/spindle1/core_speed_setpoint", 1, true);
  ASSERT_TRUE(waitFor([&] { return pub.getNumSubscribers() > 0; }, 10.0));
  coil_winding_sim::CoreSpeedSetpoint sp;
  sp.angular_velocity = 20.0;
  pub.publish(sp);
  ASSERT_TRUE(waitFor(
      [&] {
        return l.metricsAfter("spindle1", m1.sim_time, m1) &&
               m1.core_angular_velocity_setpoint == 20.0;
      },
      20.0))
      << "spindle1 did not take its setpoint";
  const double t2 = m2.sim_time;
  ASSERT_TRUE(waitFor([&] { return l.metricsAfter("spindle2", t2 + 0.05, m2); }, 20.0));
  EXPECT_NEAR(m2.core_angular_velocity_setpoint, scene_speed, 1e-9)
      << "spindle2 took spindle1's setpoint";
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_multi_spindle");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
