// ~exit_at_end, end to end: `roslaunch coil_winding_sim winding_cell.launch
// exit_at_end:=true record:=true` on a ROS master port of its own must end
// by itself with status 0 once the job is done, leaving one closed and
// indexed bag (.bag, no .active) that holds the job's end (cell_status
// job_done, winding_metrics with job_done) and the sim/ topics that
// compare_bags.py reads: the bag goes through `compare_bags.py --reference
// BAG --sim BAG`, and compared with itself every error is zero.
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
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "coil_winding_sim/CellStatus.h"
#include "coil_winding_sim/WindingMetrics.h"
#include "ros_test_support.hpp"

#if !defined(CWS_SOURCE_DIR) || !defined(CWS_PYTHON)
#error "CWS_SOURCE_DIR and CWS_PYTHON must be defined"
#endif

namespace fs = std::filesystem;

namespace {

TEST(ExitAtEnd, LaunchEndsWithStatusZeroAndItsBagIsClosed) {
  const fs::path dir = fs::temp_directory_path() / ("cws_exit_at_end_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const int port = cws_ros_test::freePort();
  ASSERT_GT(port, 0);
  const std::string log = (dir / "roslaunch.log").string();
  // The cell's scene (Newton steps: it keeps the wall clock's pace), a 2 s
  // job: the recorder subscribes within it.
  const std::vector<std::string> args{
      "coil_winding_sim",   "winding_cell.launch", "overrides:=[process.duration=2.0]",
      "exit_at_end:=true",  "record:=true",        "bag_dir:=" + dir.string(),
      "use_sim_time:=true", "real_time_factor:=1", "rviz:=false"};
  const pid_t pid = cws_ros_test::startRoslaunch(args, port, dir, log);
  ASSERT_GT(pid, 0);
  int status = 0;
  const bool exited = cws_ros_test::waitForLaunch(pid, 120.0, status);
  const std::string output = cws_ros_test::readFile(log);
  ASSERT_TRUE(exited) << "the launch did not end by itself:\n" << output;
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << output;
  EXPECT_NE(output.find("job done: "), std::string::npos) << output;

  // One closed bag, indexed (read mode needs the index).
  std::vector<fs::path> bags;
  for (const auto& e : fs::directory_iterator(dir)) {
    EXPECT_EQ(e.path().string().find(".active"), std::string::npos) << e.path();
    if (e.path().extension() == ".bag") bags.push_back(e.path());
  }
  ASSERT_EQ(bags.size(), 1u) << output;
  rosbag::Bag bag;
  ASSERT_NO_THROW(bag.open(bags.front().string(), rosbag::bagmode::Read));
  std::set<std::string> topics;
  bool status_done = false, metrics_done = false;
  rosbag::View view(bag);
  for (const rosbag::MessageInstance& m : view) {
    // (rosbag record keeps the names it was given: relative ones without "/".)
    std::string topic = m.getTopic();
    if (!topic.empty() && topic[0] == '/') topic.erase(0, 1);
    topics.insert(topic);
    if (auto s = m.instantiate<coil_winding_sim::CellStatus>()) status_done |= s->job_done;
    if (auto w = m.instantiate<coil_winding_sim::WindingMetrics>()) metrics_done |= w->job_done;
  }
  bag.close();
  std::string recorded;
  for (const std::string& t : topics) recorded += " " + t;
  EXPECT_TRUE(status_done) << "no cell_status with job_done in the bag:" << recorded;
  EXPECT_TRUE(metrics_done) << "no winding_metrics with job_done in the bag";
  for (const char* t : {"sim/spindle/command", "sim/spindle/state", "sim/tension/measured",
                        "sim/profile", "cell_status", "winding_metrics"}) {
    EXPECT_EQ(topics.count(t), 1u) << t << " not recorded; the bag holds" << recorded;
  }

  // The cell's bag through compare_bags.py, against itself.
  const fs::path out = dir / "compare";
  const std::string cmd = std::string(CWS_PYTHON) + " " + CWS_SOURCE_DIR +
                          "/src/tools/compare_bags.py --reference " + bags.front().string() +
                          " --sim " + bags.front().string() + " --out " + out.string() +
                          " --no-plots > " + (dir / "compare.log").string() + " 2>&1";
  const int rc = std::system(cmd.c_str());
  const std::string compare_log = cws_ros_test::readFile(dir / "compare.log");
  ASSERT_TRUE(WIFEXITED(rc) && WEXITSTATUS(rc) == 0) << compare_log;
  const std::string summary = cws_ros_test::readFile(out / "summary.json");
  EXPECT_NE(summary.find("\"rms_N\": 0.0"), std::string::npos) << summary;
  fs::remove_all(dir);
}

}  // namespace
