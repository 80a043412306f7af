// rostest of the spindle's frames at production speed (cell_frames.test):
// at 1200 rpm a sampler of TF recovers the core's speed within 1 % from the
// stamps and angles of world -> core alone, and joint_states come as often.
// At 20 Hz (the state's rate) the core turns exactly once between samples
// and a sampler sees it stand still.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <vector>

#include "ros_test_support.hpp"

namespace {

using cws_ros_test::waitFor;

constexpr double kOmega = 1200.0 * 2.0 * M_PI / 60.0;  // [rad/s]

struct Sample {
  double t_s, angle_rad;
};

struct Listener {
  Listener() {
    ros::NodeHandle nh;
    tf_sub = nh.subscribe("/tf", 1000, &Listener::onTf, this);
    joints_sub = nh.subscribe("joint_states", 1000, &Listener::onJoints, this);
  }
  void onTf(const tf2_msgs::TFMessage::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    for (const auto& t : m->transforms) {
      if (t.header.frame_id != "world" || t.child_frame_id != "core") continue;
      // The core turns about world z: its angle from the quaternion, in
      // (-pi, pi] whichever sign the quaternion has.
      const auto& q = t.transform.rotation;
      tf.push_back({t.header.stamp.toSec(), std::atan2(2.0 * q.w * q.z, q.w * q.w - q.z * q.z)});
    }
  }
  void onJoints(const sensor_msgs::JointState::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    joints.push_back(m->header.stamp.toSec());
  }
  std::mutex mutex;
  std::vector<Sample> tf;
  std::vector<double> joints;
  ros::Subscriber tf_sub, joints_sub;
};

TEST(CellFrames, TfAt1200RpmGivesTheSpeedWithinOnePercent) {
  Listener l;
  // A second of samples, after the first arrive.
  ASSERT_TRUE(waitFor(
      [&] {
        std::lock_guard<std::mutex> g(l.mutex);
        return l.tf.size() > 10;
      },
      20.0));
  ros::WallDuration(1.5).sleep();
  std::vector<Sample> s;
  std::vector<double> joints;
  {
    std::lock_guard<std::mutex> g(l.mutex);
    s = l.tf;
    joints = l.joints;
  }
  ASSERT_GT(s.size(), 100u);
  std::sort(s.begin(), s.end(), [](const Sample& a, const Sample& b) { return a.t_s < b.t_s; });
  // Ten samples a revolution (20 revolutions a second) or more.
  const double span_s = s.back().t_s - s.front().t_s;
  ASSERT_GT(span_s, 0.5);
  EXPECT_GE((s.size() - 1) / span_s, 0.95 * 200.0) << s.size() << " samples in " << span_s << " s";
  EXPECT_GE(joints.size() + 20, s.size());
  // Unwrap the angles (less than half a turn between samples) and fit a
  // line to angle against stamp.
  double offset = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
  std::vector<double> unwrapped;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (i > 0) {
      const double d = s[i].angle_rad + offset - unwrapped.back();
      if (d < -M_PI) offset += 2.0 * M_PI;
      if (d > M_PI) offset -= 2.0 * M_PI;
    }
    unwrapped.push_back(s[i].angle_rad + offset);
    const double x = s[i].t_s - s.front().t_s, y = unwrapped.back();
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  const double n = static_cast<double>(s.size());
  const double omega = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  std::printf("core: %.5f rad/s from %zu TF samples over %.3f s (commanded %.5f rad/s)\n", omega,
              s.size(), span_s, kOmega);
  EXPECT_NEAR(omega, kOmega, 0.01 * kOmega) << "from " << s.size() << " TF samples";
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_cell_frames");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
