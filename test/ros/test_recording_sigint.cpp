// Ctrl-C during a recorded run: `roslaunch coil_winding_sim winding_cell.launch
// record:=true` (no --duration) is started on a ROS master port of its own,
// runs a few seconds and is stopped with SIGINT, to roslaunch's process group
// as a terminal's Ctrl-C does, or to the node alone (a required node: its end
// ends the launch). The bag must be closed and indexed (.bag, not
// .bag.active), readable to its end, hold the cell's topics with monotonic
// stamps and cover the run up to the signal; the launch must stop on SIGINT
// alone (no escalation to SIGTERM) and leave no process behind.
//
// A plain gtest (catkin_add_gtest): it runs under the devel space, so that
// roslaunch finds the package; it starts no ROS node itself.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <ros/time.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <rosgraph_msgs/Clock.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <topic_tools/shape_shifter.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "coil_winding_sim/WindingMetrics.h"
#include "ros_test_support.hpp"

#ifndef CWS_SOURCE_DIR
#error "CWS_SOURCE_DIR must be defined"
#endif

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

using cws_ros_test::freePort;
using cws_ros_test::readFile;

// Parent pid and command line of a process (empty if it is gone).
bool processInfo(pid_t pid, pid_t& ppid, std::string& cmdline) {
  const std::string stat = readFile("/proc/" + std::to_string(pid) + "/stat");
  const std::size_t close = stat.rfind(')');
  if (close == std::string::npos) return false;
  char state = 0;
  if (std::sscanf(stat.c_str() + close + 1, " %c %d", &state, &ppid) != 2) return false;
  if (state == 'Z') return false;  // exited, not yet reaped
  cmdline = readFile("/proc/" + std::to_string(pid) + "/cmdline");
  for (char& c : cmdline) {
    if (c == '\0') c = ' ';
  }
  return true;
}

// The live children of `parent`, with their command lines.
std::map<pid_t, std::string> childrenOf(pid_t parent) {
  std::map<pid_t, std::string> out;
  for (const auto& e : fs::directory_iterator("/proc")) {
    const std::string name = e.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    const pid_t pid = std::stoi(name);
    pid_t ppid = 0;
    std::string cmd;
    if (processInfo(pid, ppid, cmd) && ppid == parent) out[pid] = cmd;
  }
  return out;
}

bool alive(pid_t pid) {
  pid_t ppid = 0;
  std::string cmd;
  return processInfo(pid, ppid, cmd);
}

enum class Stop { kCtrlC, kNodeOnly };

struct RunResult {
  double recorded_s = 0.0;  // wall time from the bag's creation to the signal
  double stop_s = 0.0;      // wall time from the signal to roslaunch's exit
  double signal_wall = 0.0;
  std::string output;  // roslaunch's stdout and stderr
  fs::path bag;
};

// Runs the launch in `dir`, stops it as `stop` says, checks how it ended.
void runAndStop(const fs::path& dir, Stop stop, bool use_sim_time, RunResult& r) {
  const int port = freePort();
  ASSERT_GT(port, 0);
  const std::string log = (dir / "roslaunch.log").string();
  std::vector<std::string> args = {
      "coil_winding_sim", "winding_cell.launch", "rviz:=false", "record:=true",
      "bag_dir:=" + dir.string(), "bag_prefix:=cell",
      std::string("scene:=") + CWS_SOURCE_DIR + "/test/scenes/spinning_wire.yaml",
      "real_time_factor:=0.01", std::string("use_sim_time:=") + (use_sim_time ? "true" : "false"),
      // (Small chunks: the light, compressed recording reaches the file
      // within seconds, not at the default 768 kB.)
      "record_args:=--chunksize=16"};
  const pid_t pid = cws_ros_test::startRoslaunch(args, port, dir, log);
  ASSERT_GE(pid, 0);

  // Recording: the bag's .active file exists and grows.
  const auto t0 = Clock::now();
  fs::path active;
  Clock::time_point started;
  bool recording = false;
  while (since(t0) < 60.0 && !recording) {
    for (const auto& e : fs::directory_iterator(dir)) {
      const std::string name = e.path().filename().string();
      if (name.size() > 11 && name.compare(name.size() - 11, 11, ".bag.active") == 0) {
        if (active.empty()) {
          active = e.path();
          started = Clock::now();
        }
        recording = fs::file_size(active) > 20000;
      }
    }
    int status = 0;
    if (::waitpid(pid, &status, WNOHANG) == pid) {
      r.output = readFile(log);
      FAIL() << "roslaunch ended before recording:\n" << r.output;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  if (!recording) {
    ::kill(-pid, SIGKILL);
    ::waitpid(pid, nullptr, 0);
    r.output = readFile(log);
    FAIL() << "no growing .bag.active in " << dir << " after 60 s:\n" << r.output;
  }
  // A few seconds of recording, then the signal.
  std::this_thread::sleep_for(std::chrono::seconds(4));
  const std::map<pid_t, std::string> launched = childrenOf(pid);
  pid_t target = -pid;  // Ctrl-C: the whole process group
  if (stop == Stop::kNodeOnly) {
    target = 0;
    for (const auto& [child, cmd] : launched) {
      if (cmd.find("winding_cell_node") != std::string::npos) target = child;
    }
    if (target == 0) {
      ::kill(-pid, SIGKILL);
      ::waitpid(pid, nullptr, 0);
      FAIL() << "winding_cell_node is not a child of roslaunch";
    }
  }
  r.recorded_s = since(started);
  r.signal_wall = ros::WallTime::now().toSec();
  const auto signalled = Clock::now();
  ASSERT_EQ(::kill(target, SIGINT), 0);

  // roslaunch escalates to SIGTERM after 15 s and SIGKILL 2 s later; 40 s
  // covers both, so a hang shows as a failure here, not as a ctest timeout.
  int status = 0;
  bool exited = false;
  while (since(signalled) < 40.0) {
    if (::waitpid(pid, &status, WNOHANG) == pid) {
      exited = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  r.stop_s = since(signalled);
  if (!exited) {
    ::kill(-pid, SIGKILL);
    ::waitpid(pid, &status, 0);
  }
  r.output = readFile(log);
  // What roslaunch started must have ended with it (each runs in a process
  // group of its own, set up by setsid, so the group kill above does not
  // reach them: end them here).
  std::vector<std::string> left;
  for (const auto& [child, cmd] : launched) {
    if (alive(child)) {
      left.push_back(cmd);
      ::kill(child, SIGKILL);
    }
  }
  EXPECT_TRUE(exited) << "roslaunch did not end within 40 s of SIGINT:\n" << r.output;
  EXPECT_TRUE(left.empty()) << "left running: " << (left.empty() ? "" : left.front());
  EXPECT_EQ(r.output.find("escalating to"), std::string::npos)
      << "a process did not stop on SIGINT:\n"
      << r.output;

  // One closed bag and no .active left.
  std::vector<fs::path> bags;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    EXPECT_EQ(name.find(".active"), std::string::npos) << "unfinished bag " << name;
    if (e.path().extension() == ".bag") bags.push_back(e.path());
  }
  ASSERT_EQ(bags.size(), 1u) << "expected one .bag in " << dir << "\n" << r.output;
  r.bag = bags.front();
}

// The bag is indexed and readable to its end, holds the cell's topics with
// monotonic stamps and covers the run up to the signal.
void checkBag(const RunResult& r, bool use_sim_time) {
  rosbag::Bag bag;
  // Read mode needs the index: an unindexed bag throws here.
  ASSERT_NO_THROW(bag.open(r.bag.string(), rosbag::bagmode::Read)) << r.bag;
  rosbag::View view(bag);
  std::map<std::string, int> count;
  int unreadable = 0, metrics = 0;
  bool monotonic = true;
  double last_metrics_stamp = -1.0, last_clock = -1.0, last_metrics_time = 0.0;
  std::size_t seen = 0;
  for (const rosbag::MessageInstance& m : view) {
    ++seen;
    std::string topic = m.getTopic();
    if (!topic.empty() && topic[0] == '/') topic.erase(0, 1);
    ++count[topic];
    // Every message's bytes, read and deserialized into a generic message.
    if (!m.instantiate<topic_tools::ShapeShifter>()) ++unreadable;
    if (auto w = m.instantiate<coil_winding_sim::WindingMetrics>()) {
      ++metrics;
      monotonic = monotonic && w->header.stamp.toSec() >= last_metrics_stamp;
      last_metrics_stamp = w->header.stamp.toSec();
      last_metrics_time = m.getTime().toSec();
    }
    if (auto c = m.instantiate<rosgraph_msgs::Clock>()) {
      monotonic = monotonic && c->clock.toSec() >= last_clock;
      last_clock = c->clock.toSec();
    }
  }
  EXPECT_EQ(seen, view.size()) << "the bag ends before its index does";
  EXPECT_EQ(unreadable, 0);
  EXPECT_TRUE(monotonic) << "stamps of winding_metrics or /clock go back";
  std::vector<std::string> topics = {"wire_state_compact", "winding_metrics", "tf", "diagnostics"};
  if (use_sim_time) topics.push_back("clock");
  for (const std::string& t : topics) EXPECT_GT(count[t], 0) << "no " << t << " in " << r.bag;
  // Metrics come at 20 Hz (wall time): at least half of those of the
  // recorded span must be in the bag.
  std::printf("%s: %zu messages, %d winding_metrics over %.1f s of recording; stopped in %.2f s\n",
              r.bag.filename().c_str(), seen, metrics, r.recorded_s, r.stop_s);
  EXPECT_GE(metrics, static_cast<int>(0.5 * 20.0 * r.recorded_s)) << "the bag lost messages";
  // With wall-clock ROS time the bag's times are wall times: the last
  // metrics arrived within a second of the signal.
  if (!use_sim_time) {
    EXPECT_GT(last_metrics_time, r.signal_wall - 1.0)
        << "the bag ends " << r.signal_wall - last_metrics_time << " s before the signal";
  }
  bag.close();
}

// A fresh directory for one run; removed when its test passed.
struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& name) {
    path = fs::temp_directory_path() / ("cws_sigint_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    if (!testing::Test::HasFailure()) {
      fs::remove_all(path);
    } else {
      std::printf("kept %s for inspection\n", path.c_str());
    }
  }
};
}  // namespace

// Ctrl-C in the terminal of `roslaunch ... record:=true`.
TEST(RecordingSigint, CtrlCToRoslaunchLeavesACompleteBag) {
  TempDir dir("ctrl_c");
  RunResult r;
  runAndStop(dir.path, Stop::kCtrlC, false, r);
  if (HasFatalFailure()) return;
  checkBag(r, false);
}

// SIGINT to the node alone, with the node's /clock: the launch ends (the
// node is required) and the bag is complete.
TEST(RecordingSigint, SigintToTheNodeLeavesACompleteBag) {
  TempDir dir("node");
  RunResult r;
  runAndStop(dir.path, Stop::kNodeOnly, true, r);
  if (HasFatalFailure()) return;
  checkBag(r, true);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::Time::init();
  return RUN_ALL_TESTS();
}
