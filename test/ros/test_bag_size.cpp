// Bags a user can keep, end to end: `roslaunch coil_winding_sim
// winding_cell.launch record:=true` on a ROS master port of its own.
// - A minute of winding at 1200 rpm, at the pace of the wall clock, ends
//   (exit_at_end) with a bag of at most 20 MB that holds the wire's compact
//   state and the sim/ series, and no markers.
// - A minute idle, recorded for 60 s of wall time: almost nothing (at most
//   1 MB), paused and with the core at rest (start:=at_rest: the simulated
//   time goes on, the state stands).
// The sizes are printed for the record.
//
// A plain gtest (catkin_add_gtest): it runs under the devel space, so that
// roslaunch finds the package; it starts no ROS node itself.
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "ros_test_support.hpp"

namespace fs = std::filesystem;

namespace {

// The one closed bag in `dir` (none: empty path).
fs::path closedBag(const fs::path& dir) {
  fs::path bag;
  int count = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() == ".active") return {};
    if (e.path().extension() == ".bag") {
      bag = e.path();
      ++count;
    }
  }
  return count == 1 ? bag : fs::path();
}

// Bytes of each topic's messages in a bag.
std::map<std::string, std::size_t> topicBytes(const fs::path& path) {
  rosbag::Bag bag(path.string(), rosbag::bagmode::Read);
  std::map<std::string, std::size_t> bytes;
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    std::string topic = m.getTopic();
    if (!topic.empty() && topic[0] == '/') topic.erase(0, 1);
    bytes[topic] += m.size();
  }
  return bytes;
}

void printSizes(const char* what, const fs::path& bag) {
  std::printf("%s: %.3f MB on disk (lz4)\n", what, fs::file_size(bag) / 1e6);
  for (const auto& [topic, b] : topicBytes(bag)) {
    std::printf("  %-22s %9.3f MB uncompressed\n", topic.c_str(), b / 1e6);
  }
}

TEST(BagSize, AMinuteOfWindingAt1200RpmFitsIn20MB) {
  const fs::path dir = fs::temp_directory_path() / ("cws_bag_wind_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const int port = cws_ros_test::freePort();
  ASSERT_GT(port, 0);
  const std::string log = (dir / "roslaunch.log").string();
  const std::vector<std::string> args{
      "coil_winding_sim",
      "winding_cell.launch",
      "rviz:=false",
      "record:=true",
      "bag_dir:=" + dir.string(),
      "exit_at_end:=true",
      "real_time_factor:=1",
      "overrides:=[process.duration=60, process.core_speed_rpm=1200, core.start_at_speed=true]"};
  const pid_t pid = cws_ros_test::startRoslaunch(args, port, dir, log);
  ASSERT_GT(pid, 0);
  int status = 0;
  const bool exited = cws_ros_test::waitForLaunch(pid, 240.0, status);
  const std::string output = cws_ros_test::readFile(log);
  ASSERT_TRUE(exited) << output;
  const fs::path bag = closedBag(dir);
  ASSERT_FALSE(bag.empty()) << output;
  printSizes("a minute of winding at 1200 rpm", bag);
  EXPECT_LE(fs::file_size(bag), 20u * 1000 * 1000);
  const auto bytes = topicBytes(bag);
  EXPECT_EQ(bytes.count("wire_markers"), 0u);
  EXPECT_EQ(bytes.count("wire_state_compact"), 1u);
  EXPECT_EQ(bytes.count("sim/spindle/state"), 1u);
  EXPECT_EQ(bytes.count("tf"), 1u);
  fs::remove_all(dir);
}

void idleMinute(const std::string& start) {
  const fs::path dir =
      fs::temp_directory_path() / ("cws_bag_idle_" + start + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const int port = cws_ros_test::freePort();
  ASSERT_GT(port, 0);
  const std::string log = (dir / "roslaunch.log").string();
  const std::vector<std::string> args{"coil_winding_sim",
                                      "winding_cell.launch",
                                      "rviz:=false",
                                      "record:=true",
                                      "bag_dir:=" + dir.string(),
                                      "start:=" + start,
                                      "record_args:=--duration=60"};
  const pid_t pid = cws_ros_test::startRoslaunch(args, port, dir, log);
  ASSERT_GT(pid, 0);
  // The recorder ends after its minute and closes the bag; then the launch.
  fs::path bag;
  const auto t0 = std::chrono::steady_clock::now();
  while (bag.empty() && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(150)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    if (std::chrono::steady_clock::now() - t0 > std::chrono::seconds(61)) bag = closedBag(dir);
  }
  ::kill(-pid, SIGINT);
  int status = 0;
  cws_ros_test::waitForLaunch(pid, 30.0, status);
  const std::string output = cws_ros_test::readFile(log);
  ASSERT_FALSE(bag.empty()) << output;
  printSizes(("a minute idle (" + start + ")").c_str(), bag);
  EXPECT_LE(fs::file_size(bag), 1000u * 1000);
  fs::remove_all(dir);
}

TEST(BagSize, AMinutePausedIsAlmostNothing) { idleMinute("paused"); }

TEST(BagSize, AMinuteAtRestIsAlmostNothing) { idleMinute("at_rest"); }

}  // namespace
