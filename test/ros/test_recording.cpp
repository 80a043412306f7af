// rostest of the winding_cell node on the paper's scene, recorded by the
// launch file's rosbag: the tension setpoint reaches the supply, and the bag
// holds the cell's topics with monotonic stamps.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <mutex>
#include <set>

#include "coil_winding_sim/TensionSetpoint.h"
#include "coil_winding_sim/WindingMetrics.h"
#include "ros_test_support.hpp"

namespace fs = std::filesystem;

namespace {
std::mutex mutex;
coil_winding_sim::WindingMetrics metrics;
int count = 0;
fs::file_time_type started;

void onMetrics(const coil_winding_sim::WindingMetrics::ConstPtr& m) {
  std::lock_guard<std::mutex> l(mutex);
  metrics = *m;
  ++count;
}

using cws_ros_test::waitFor;

double tensionNow() {
  std::lock_guard<std::mutex> l(mutex);
  return metrics.supply_tension;
}
}  // namespace

TEST(Recording, TensionSetpointReachesTheSupply) {
  ros::NodeHandle nh;
  ros::Publisher pub =
      nh.advertise<coil_winding_sim::TensionSetpoint>("tension_setpoint", 10, true);
  ASSERT_TRUE(waitFor([] { return count > 0; }, 30.0));
  EXPECT_EQ(tensionNow(), 30.0);
  coil_winding_sim::TensionSetpoint sp;
  sp.tension = 45.0;
  pub.publish(sp);
  EXPECT_TRUE(waitFor([] { return tensionNow() == 45.0; }, 20.0));
  // Negative and non-finite tensions are refused; the last good one stays.
  for (double bad : {-1.0, std::numeric_limits<double>::quiet_NaN(), 1e6}) {
    sp.tension = bad;
    pub.publish(sp);
    ros::WallDuration(0.3).sleep();
  }
  ros::WallDuration(0.5).sleep();
  EXPECT_EQ(tensionNow(), 45.0);
}

TEST(Recording, BagHoldsTheTopicsWithMonotonicStamps) {
  // The launch file records for 6 s (record_args --duration=6); wait for the
  // closed bag of this run.
  fs::path bag_path;
  ASSERT_TRUE(waitFor(
      [&] {
        for (const auto& e : fs::directory_iterator("/tmp")) {
          const std::string name = e.path().filename().string();
          if (name.rfind("cws_rostest_", 0) == 0 && e.path().extension() == ".bag" &&
              e.last_write_time() >= started) {
            bag_path = e.path();
            return true;
          }
        }
        return false;
      },
      60.0))
      << "no closed bag in /tmp";
  rosbag::Bag bag(bag_path.string(), rosbag::bagmode::Read);
  rosbag::View view(bag);
  std::set<std::string> topics;
  std::map<std::string, ros::Time> last_time;
  bool monotonic = true;
  int metrics_msgs = 0;
  double last_stamp = -1.0;
  for (const rosbag::MessageInstance& m : view) {
    // rosbag keeps relative topic names as given on its command line.
    std::string topic = m.getTopic();
    if (!topic.empty() && topic[0] == '/') topic.erase(0, 1);
    topics.insert(topic);
    auto it = last_time.find(m.getTopic());
    if (it != last_time.end() && m.getTime() < it->second) monotonic = false;
    last_time[m.getTopic()] = m.getTime();
    if (auto w = m.instantiate<coil_winding_sim::WindingMetrics>()) {
      ++metrics_msgs;
      if (w->header.stamp.toSec() < last_stamp) monotonic = false;
      last_stamp = w->header.stamp.toSec();
    }
  }
  for (const char* t :
       {"wire_state_compact", "winding_metrics", "tf", "diagnostics", "tension_setpoint"}) {
    EXPECT_TRUE(topics.count(t)) << "missing topic " << t << " in " << bag_path;
  }
  EXPECT_GT(metrics_msgs, 5);
  EXPECT_TRUE(monotonic);
  bag.close();
  fs::remove(bag_path);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_recording");
  started = fs::file_time_type::clock::now() - std::chrono::seconds(30);
  ros::NodeHandle nh;
  ros::Subscriber sub = nh.subscribe("winding_metrics", 10, onMetrics);
  ros::AsyncSpinner spinner(1);
  spinner.start();
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
