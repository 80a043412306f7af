// Scene errors and relative scene paths, end to end: `roslaunch
// coil_winding_sim winding_cell.launch` on a ROS master port of its own.
// - A misspelt key, and a scripted job too long for the storage, end the
//   launch with one line from the node that names the key, not inside
//   roslaunch's "Invalid <param> tag" exception for robot_description.
// - A relative scene path is the directory roslaunch was started from: the
//   cell runs the scene there, and a missing one is refused with the
//   absolute path tried.
//
// A plain gtest (catkin_add_gtest): it runs under the devel space, so that
// roslaunch finds the package; it starts no ROS node itself.
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosgraph_msgs/Clock.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "ros_test_support.hpp"

#ifndef CWS_SOURCE_DIR
#error "CWS_SOURCE_DIR must be defined"
#endif

namespace fs = std::filesystem;

namespace {

struct Launch {
  bool ended = false;
  int status = 0;
  std::string output;
};

// roslaunch (or `program`) of the cell (or of the package's `file`) with
// `args` from `cwd`, allowed 90 s to end by itself.
Launch launch(const std::vector<std::string>& args, const fs::path& cwd = {},
              const std::string& program = "roslaunch",
              const std::string& file = "winding_cell.launch") {
  const fs::path dir = fs::temp_directory_path() / ("cws_scene_errors_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const int port = cws_ros_test::freePort();
  std::vector<std::string> all{"coil_winding_sim", file, "rviz:=false"};
  all.insert(all.end(), args.begin(), args.end());
  const std::string log = (dir / "roslaunch.log").string();
  Launch l;
  const pid_t pid = cws_ros_test::startRoslaunch(all, port, dir, log, cwd, program);
  if (port > 0 && pid > 0) l.ended = cws_ros_test::waitForLaunch(pid, 90.0, l.status);
  l.output = cws_ros_test::readFile(log);
  fs::remove_all(dir);
  return l;
}

void expectOneClearLine(const Launch& l, const std::string& words) {
  EXPECT_TRUE(l.ended) << l.output;
  EXPECT_NE(l.output.find("[FATAL]"), std::string::npos) << l.output;
  EXPECT_NE(l.output.find(words), std::string::npos) << l.output;
  EXPECT_EQ(l.output.find("Invalid <param> tag"), std::string::npos) << l.output;
  EXPECT_EQ(l.output.find("RLException"), std::string::npos) << l.output;
}

TEST(SceneErrors, AMisspeltKeyIsNamedByTheNode) {
  expectOneClearLine(launch({"overrides:=[proces.turns=3]"}), "scene key 'proces': unknown key");
}

// (A job longer than the live storage winds: buried wire retires. One of a
// million turns, more wire than a run may wind, is refused.)
TEST(SceneErrors, AScriptedJobTooLongToWindIsNamedByTheNode) {
  expectOneClearLine(launch({"overrides:=[process.duration=1e5]", "stop_at_end:=true"}),
                     "scene key 'process.duration'");
}

TEST(SceneErrors, ARelativeSceneIsTheLaunchDirectorys) {
  const fs::path source(CWS_SOURCE_DIR);
  const Launch ok =
      launch({"scene:=test/scenes/spinning_wire.yaml", "overrides:=[process.duration=0.05]",
              "exit_at_end:=true", "real_time_factor:=0"},
             source);
  ASSERT_TRUE(ok.ended) << ok.output;
  ASSERT_TRUE(WIFEXITED(ok.status));
  EXPECT_EQ(WEXITSTATUS(ok.status), 0) << ok.output;
  EXPECT_NE(ok.output.find((source / "test/scenes/spinning_wire.yaml").string()), std::string::npos)
      << ok.output;
  EXPECT_NE(ok.output.find("job done: "), std::string::npos) << ok.output;

  const Launch missing = launch({"scene:=config/no_such_scene.yaml"}, source);
  expectOneClearLine(
      missing, "cannot open scene file '" + (source / "config/no_such_scene.yaml").string() + "'");
}

// roslaunch ends with status 0 when the cell refuses its scene; launch_cell
// (scripts/launch_cell) ends with the cell's status, 2, and with 0 after a
// job that ends.
TEST(SceneErrors, TheCheckedLaunchFailsWhenTheCellFails) {
  const Launch plain = launch({"overrides:=[proces.turns=3]"});
  ASSERT_TRUE(plain.ended) << plain.output;
  std::printf("roslaunch with a misspelt key: exit status %d\n", WEXITSTATUS(plain.status));
  const Launch bad = launch({"overrides:=[proces.turns=3]"}, {}, CWS_LAUNCH_CELL);
  expectOneClearLine(bad, "scene key 'proces': unknown key");
  ASSERT_TRUE(WIFEXITED(bad.status));
  EXPECT_EQ(WEXITSTATUS(bad.status), 2) << bad.output;
  const Launch ok =
      launch({"scene:=" + std::string(CWS_SOURCE_DIR) + "/test/scenes/spinning_wire.yaml",
              "overrides:=[process.duration=0.05]", "exit_at_end:=true", "real_time_factor:=0"},
             {}, CWS_LAUNCH_CELL);
  ASSERT_TRUE(ok.ended) << ok.output;
  ASSERT_TRUE(WIFEXITED(ok.status));
  EXPECT_EQ(WEXITSTATUS(ok.status), 0) << ok.output;
  EXPECT_NE(ok.output.find("job done: "), std::string::npos) << ok.output;
}

// replay.launch takes a bag path relative to the directory roslaunch runs
// in, as winding_cell.launch takes a scene (rosbag play itself runs in
// ROS_HOME, where it said "Error opening file"); a missing one fails the
// checked launch, naming the absolute path tried.
TEST(SceneErrors, AReplaysRelativeBagIsTheLaunchDirectorys) {
  const fs::path cwd = fs::temp_directory_path() / ("cws_replay_cwd_" + std::to_string(getpid()));
  fs::remove_all(cwd);
  fs::create_directories(cwd / "bags");
  {
    ros::Time::init();
    rosbag::Bag bag((cwd / "bags" / "short.bag").string(), rosbag::bagmode::Write);
    for (int k = 1; k <= 5; ++k) {
      rosgraph_msgs::Clock c;
      c.clock = ros::Time(100.0 + 0.05 * k);
      bag.write("/clock", c.clock, c);
    }
  }
  const Launch ok = launch({"bag:=bags/short.bag"}, cwd, CWS_LAUNCH_CELL, "replay.launch");
  ASSERT_TRUE(ok.ended) << ok.output;
  ASSERT_TRUE(WIFEXITED(ok.status));
  EXPECT_EQ(WEXITSTATUS(ok.status), 0) << ok.output;
  EXPECT_EQ(ok.output.find("Error opening file"), std::string::npos) << ok.output;
  EXPECT_NE(ok.output.find("Done."), std::string::npos) << ok.output;

  const Launch missing = launch({"bag:=bags/none.bag"}, cwd, CWS_LAUNCH_CELL, "replay.launch");
  ASSERT_TRUE(missing.ended) << missing.output;
  ASSERT_TRUE(WIFEXITED(missing.status));
  EXPECT_NE(WEXITSTATUS(missing.status), 0) << missing.output;
  EXPECT_NE(missing.output.find((cwd / "bags/none.bag").string()), std::string::npos)
      << missing.output;
  fs::remove_all(cwd);
}

}  // namespace
