// rostest of the winding_cell node on a light scene (test/scenes/
// spinning_wire.yaml) with the node publishing /clock (use_sim_time).
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <ros/topic.h>
#include <sensor_msgs/JointState.h>
#include <std_srvs/SetBool.h>
#include <std_srvs/Trigger.h>
#include <tf2_msgs/TFMessage.h>
#include <urdf/model.h>
#include <visualization_msgs/MarkerArray.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <vector>

#include "coil_winding_sim/CoreSpeedSetpoint.h"
#include "coil_winding_sim/Restore.h"
#include "coil_winding_sim/RunUntil.h"
#include "coil_winding_sim/Snapshot.h"
#include "coil_winding_sim/WindingMetrics.h"
#include "coil_winding_sim/WireState.h"
#include "ros_test_support.hpp"

namespace {

// Collects the latest messages of the node's topics.
class Listener {
 public:
  Listener() {
    ros::NodeHandle nh;
    metrics_ = nh.subscribe("winding_metrics", 10, &Listener::onMetrics, this);
    markers_ = nh.subscribe("wire_markers", 10, &Listener::onMarkers, this);
    tf_ = nh.subscribe("/tf", 100, &Listener::onTf, this);
  }
  void onMetrics(const coil_winding_sim::WindingMetrics::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    metrics = *m;
    ++metrics_count;
  }
  void onMarkers(const visualization_msgs::MarkerArray::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    for (const auto& k : m->markers) {
      if (k.ns == "wire" && k.type == visualization_msgs::Marker::LINE_STRIP)
        wire_points = k.points.size();
      if (k.action == visualization_msgs::Marker::DELETEALL) ++delete_all;
    }
  }
  void onTf(const tf2_msgs::TFMessage::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    for (const auto& t : m->transforms) {
      if (t.child_frame_id != "core") continue;
      const auto& q = t.transform.rotation;
      // Yaw about the core axis (world z in this scene).
      const double yaw =
          std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
      core_samples.push_back({t.header.stamp.toSec(), yaw});
    }
  }

  std::mutex mutex;
  coil_winding_sim::WindingMetrics metrics;
  int metrics_count = 0;
  std::size_t wire_points = 0;
  int delete_all = 0;
  std::vector<std::pair<double, double>> core_samples;  // (stamp, yaw)

 private:
  ros::Subscriber metrics_, markers_, tf_;
};

using cws_ros_test::waitFor;

coil_winding_sim::WindingMetrics latest(Listener& l) {
  std::lock_guard<std::mutex> lock(l.mutex);
  return l.metrics;
}

// Waits for a metrics message published after this call.
coil_winding_sim::WindingMetrics fresh(Listener& l) {
  int seen;
  {
    std::lock_guard<std::mutex> lock(l.mutex);
    seen = l.metrics_count;
  }
  waitFor(
      [&] {
        std::lock_guard<std::mutex> lock(l.mutex);
        return l.metrics_count >= seen + 2;
      },
      10.0);
  return latest(l);
}

bool pause(bool on) {
  std_srvs::SetBool s;
  s.request.data = on;
  return ros::service::call("/winding_cell/pause", s) && s.response.success;
}

Listener* listener = nullptr;
}  // namespace

TEST(WindingCell, MarkersAndTfArrive) {
  ASSERT_TRUE(waitFor(
      [] {
        std::lock_guard<std::mutex> l(listener->mutex);
        return listener->wire_points > 1 && !listener->core_samples.empty() &&
               listener->metrics_count > 0;
      },
      30.0))
      << "no markers, TF or metrics from winding_cell";
  std::lock_guard<std::mutex> l(listener->mutex);
  EXPECT_EQ(listener->wire_points, static_cast<std::size_t>(listener->metrics.points));
}

TEST(WindingCell, CoreTurnsAtTheCommandedSpeed) {
  ros::NodeHandle nh;
  ros::Publisher pub =
      nh.advertise<coil_winding_sim::CoreSpeedSetpoint>("core_speed_setpoint", 1, true);
  coil_winding_sim::CoreSpeedSetpoint sp;
  sp.angular_velocity = 40.0;  // [rad/s]
  pub.publish(sp);
  ASSERT_TRUE(
      waitFor([] { return std::abs(latest(*listener).core_angular_velocity - 40.0) < 1e-9; }, 20.0))
      << "the setpoint was not applied";
  {
    std::lock_guard<std::mutex> l(listener->mutex);
    listener->core_samples.clear();
  }
  ASSERT_TRUE(waitFor(
      [] {
        std::lock_guard<std::mutex> l(listener->mutex);
        return listener->core_samples.size() >= 20;
      },
      20.0));
  // Angular velocity from the TF stamps (simulated time): mean over
  // consecutive samples, unwrapping the yaw.
  std::lock_guard<std::mutex> l(listener->mutex);
  double turned = 0.0, elapsed = 0.0;
  for (std::size_t i = 1; i < listener->core_samples.size(); ++i) {
    const double dt = listener->core_samples[i].first - listener->core_samples[i - 1].first;
    double dyaw = listener->core_samples[i].second - listener->core_samples[i - 1].second;
    dyaw = std::remainder(dyaw, 2.0 * M_PI);
    if (dt <= 0.0) continue;
    turned += dyaw;
    elapsed += dt;
  }
  ASSERT_GT(elapsed, 0.0);
  std::printf("core: %.6f rad/s from TF stamps over %.4f s (commanded 40 rad/s)\n",
              turned / elapsed, elapsed);
  EXPECT_NEAR(turned / elapsed, 40.0, 0.4);
}

TEST(WindingCell, NonFiniteAndAbsurdSetpointsAreRefused) {
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<coil_winding_sim::CoreSpeedSetpoint>("core_speed_setpoint", 10);
  waitFor([&] { return pub.getNumSubscribers() > 0; }, 5.0);
  const double before = fresh(*listener).core_angular_velocity_setpoint;
  for (double bad : {std::nan(""), std::numeric_limits<double>::infinity(), 1e9}) {
    coil_winding_sim::CoreSpeedSetpoint sp;
    sp.angular_velocity = bad;
    pub.publish(sp);
  }
  ros::WallDuration(0.5).sleep();
  EXPECT_EQ(fresh(*listener).core_angular_velocity_setpoint, before);
}

// Runs until simulated time t and returns the wire there.
coil_winding_sim::WireState runUntil(double t) {
  coil_winding_sim::RunUntil r;
  r.request.time = t;
  EXPECT_TRUE(ros::service::call("/winding_cell/run_until", r));
  EXPECT_TRUE(r.response.success) << r.response.message;
  EXPECT_TRUE(waitFor([&] { return latest(*listener).sim_time == t; }, 30.0))
      << "did not reach " << t;
  auto w =
      ros::topic::waitForMessage<coil_winding_sim::WireState>("wire_state", ros::Duration(10.0));
  EXPECT_TRUE(w);
  return w ? *w : coil_winding_sim::WireState();
}

TEST(WindingCell, RestoredRunFollowsTheOriginal) {
  ASSERT_TRUE(pause(true));
  const double t0 = fresh(*listener).sim_time;
  const std::string path = "/tmp/cws_rostest_follow_" + std::to_string(getpid()) + ".bag";
  coil_winding_sim::Snapshot snap;
  snap.request.path = path;
  ASSERT_TRUE(ros::service::call("/winding_cell/snapshot", snap));
  ASSERT_TRUE(snap.response.success) << snap.response.message;
  const coil_winding_sim::WireState original = runUntil(t0 + 0.002);
  coil_winding_sim::Restore rest;
  rest.request.path = path;
  ASSERT_TRUE(ros::service::call("/winding_cell/restore", rest));
  ASSERT_TRUE(rest.response.success) << rest.response.message;
  const coil_winding_sim::WireState again = runUntil(t0 + 0.002);
  ASSERT_EQ(original.positions.size(), again.positions.size());
  ASSERT_GT(original.positions.size(), 1u);
  for (std::size_t i = 0; i < original.positions.size(); ++i) {
    EXPECT_EQ(original.positions[i].x, again.positions[i].x) << "point " << i;
    EXPECT_EQ(original.positions[i].y, again.positions[i].y) << "point " << i;
    EXPECT_EQ(original.positions[i].z, again.positions[i].z) << "point " << i;
    EXPECT_EQ(original.axial_force[i], again.axial_force[i]) << "point " << i;
  }
  ASSERT_TRUE(pause(false));
  std::remove(path.c_str());
}

TEST(WindingCell, SnapshotRestoreAndReset) {
  ASSERT_TRUE(pause(true));
  const auto at_snapshot = fresh(*listener);
  const std::string path = "/tmp/cws_rostest_snapshot_" + std::to_string(getpid()) + ".bag";
  coil_winding_sim::Snapshot snap;
  snap.request.path = path;
  ASSERT_TRUE(ros::service::call("/winding_cell/snapshot", snap));
  ASSERT_TRUE(snap.response.success) << snap.response.message;
  // A relative path is the node's working directory's; the answer names the
  // file it wrote absolutely.
  {
    coil_winding_sim::Snapshot rel;
    rel.request.path = "cws_rostest_relative_" + std::to_string(getpid()) + ".bag";
    ASSERT_TRUE(ros::service::call("/winding_cell/snapshot", rel));
    ASSERT_TRUE(rel.response.success) << rel.response.message;
    const std::size_t at = rel.response.message.find(" written to /");
    ASSERT_NE(at, std::string::npos) << rel.response.message;
    const std::string written = rel.response.message.substr(at + 12);
    EXPECT_NE(written.find("/" + rel.request.path), std::string::npos) << written;
    EXPECT_TRUE(std::filesystem::exists(written)) << written;
    std::filesystem::remove(written);
  }
  // Run on, then restore: the state is the snapshot's, step for step.
  ASSERT_TRUE(pause(false));
  ASSERT_TRUE(waitFor(
      [&] { return latest(*listener).steps_accepted > at_snapshot.steps_accepted + 100; }, 20.0));
  ASSERT_TRUE(pause(true));
  coil_winding_sim::Restore rest;
  rest.request.path = path;
  ASSERT_TRUE(ros::service::call("/winding_cell/restore", rest));
  ASSERT_TRUE(rest.response.success) << rest.response.message;
  const auto restored = fresh(*listener);
  EXPECT_EQ(restored.sim_time, at_snapshot.sim_time);
  EXPECT_EQ(restored.steps_accepted, at_snapshot.steps_accepted);
  EXPECT_EQ(restored.core_turns, at_snapshot.core_turns);
  EXPECT_EQ(restored.points, at_snapshot.points);

  // A missing file, a corrupt file, a bag without a snapshot: refused with a
  // message, state unchanged.
  const std::string corrupt = path + ".corrupt";
  {
    std::ofstream f(corrupt);
    f << "this is not a bag";
  }
  for (const std::string& bad : {std::string("/tmp/no_such_snapshot.bag"), corrupt}) {
    coil_winding_sim::Restore r;
    r.request.path = bad;
    ASSERT_TRUE(ros::service::call("/winding_cell/restore", r));
    EXPECT_FALSE(r.response.success) << bad;
    EXPECT_NE(r.response.message.find(bad), std::string::npos) << r.response.message;
  }
  const auto unchanged = fresh(*listener);
  EXPECT_EQ(unchanged.sim_time, at_snapshot.sim_time);
  EXPECT_EQ(unchanged.steps_accepted, at_snapshot.steps_accepted);
  // Snapshot to an unwritable path fails cleanly.
  coil_winding_sim::Snapshot bad_snap;
  bad_snap.request.path = "/proc/cannot/write/here.bag";
  ASSERT_TRUE(ros::service::call("/winding_cell/snapshot", bad_snap));
  EXPECT_FALSE(bad_snap.response.success);

  // Reset: back to the start, markers cleared once.
  std_srvs::Trigger reset;
  ASSERT_TRUE(ros::service::call("/winding_cell/reset", reset));
  EXPECT_TRUE(reset.response.success);
  const auto after_reset = fresh(*listener);
  EXPECT_EQ(after_reset.steps_accepted, 0);
  EXPECT_EQ(after_reset.sim_time, 0.0);
  EXPECT_TRUE(waitFor(
      [] {
        std::lock_guard<std::mutex> l(listener->mutex);
        return listener->delete_all > 0;
      },
      5.0));
  ASSERT_TRUE(pause(false));
  std::remove(path.c_str());
  std::remove(corrupt.c_str());
}

// joint_states and the cell's URDF (robot_description, from wire_sim urdf)
// give the node's own TF world -> core: the spindle joint's origin turned by
// its position equals the TF's rotation at the same stamp, to 1e-9 rad. So
// robot_state_publisher gives the same frames.
TEST(WindingCell, JointStatesAndTheUrdfGiveTheNodesFrames) {
  std::string xml;
  ASSERT_TRUE(ros::param::get("/robot_description", xml)) << "no robot_description";
  urdf::Model model;
  ASSERT_TRUE(model.initString(xml)) << xml;
  const urdf::JointConstSharedPtr spindle = model.getJoint("spindle");
  ASSERT_TRUE(spindle);
  EXPECT_EQ(spindle->type, urdf::Joint::CONTINUOUS);
  EXPECT_EQ(spindle->parent_link_name, "world");
  EXPECT_EQ(spindle->child_link_name, "core");
  double x, y, z, w;
  spindle->parent_to_joint_origin_transform.rotation.getQuaternion(x, y, z, w);
  const Eigen::Quaterniond origin(w, x, y, z);
  const Eigen::Vector3d axis(spindle->axis.x, spindle->axis.y, spindle->axis.z);

  // Pairs of (joint position, TF rotation) at equal stamps.
  std::mutex m;
  std::map<double, double> joint_at;           // stamp -> spindle position
  std::map<double, Eigen::Quaterniond> tf_at;  // stamp -> world -> core
  ros::NodeHandle nh;
  ros::Subscriber js = nh.subscribe<sensor_msgs::JointState>(
      "joint_states", 100, [&](const sensor_msgs::JointState::ConstPtr& msg) {
        std::lock_guard<std::mutex> l(m);
        for (std::size_t i = 0; i < msg->name.size(); ++i) {
          if (msg->name[i] == "spindle") joint_at[msg->header.stamp.toSec()] = msg->position[i];
        }
      });
  ros::Subscriber tf =
      nh.subscribe<tf2_msgs::TFMessage>("/tf", 100, [&](const tf2_msgs::TFMessage::ConstPtr& msg) {
        std::lock_guard<std::mutex> l(m);
        for (const auto& t : msg->transforms) {
          if (t.child_frame_id != "core") continue;
          const auto& q = t.transform.rotation;
          tf_at[t.header.stamp.toSec()] = Eigen::Quaterniond(q.w, q.x, q.y, q.z);
        }
      });
  int pairs = 0;
  ASSERT_TRUE(waitFor(
      [&] {
        std::lock_guard<std::mutex> l(m);
        pairs = 0;
        for (const auto& [stamp, q] : tf_at) pairs += joint_at.count(stamp) > 0;
        return pairs >= 20;
      },
      30.0))
      << pairs << " pairs";
  std::lock_guard<std::mutex> l(m);
  double worst = 0.0;
  for (const auto& [stamp, q_tf] : tf_at) {
    const auto j = joint_at.find(stamp);
    if (j == joint_at.end()) continue;
    const Eigen::Quaterniond q_urdf =
        origin * Eigen::Quaterniond(Eigen::AngleAxisd(j->second, axis));
    worst = std::max(worst, q_urdf.angularDistance(q_tf));
  }
  std::printf("joint_states + URDF against TF: largest angle %.3g rad over %d stamps\n", worst,
              pairs);
  EXPECT_LT(worst, 1e-9);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_winding_cell");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  Listener l;
  listener = &l;
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
