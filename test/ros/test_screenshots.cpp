// The rviz pictures of README.md and docs/cell.md, taken as their commands
// run: the cell's default job in rviz/winding_cell.rviz and the 14-turn
// coil in rviz/coil.rviz, each through src/tools/rviz_screenshot.sh on a
// virtual screen (Xvfb).
// Each picture must show rviz drawing the scene, not an empty or black
// window: more than 2,000 colours (3,600 measured for the cell, 11,000 for
// the coil: the wire's force colours, the layers' spheres, the text)
// against 1,155 of rviz's window with nothing to draw. `make
// screenshots` writes the same pictures to docs/ for those documents, where a
// person looks at them.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "ros_test_support.hpp"

#ifndef CWS_SOURCE_DIR
#error "CWS_SOURCE_DIR must be defined"
#endif

namespace fs = std::filesystem;

namespace {

// The number of distinct colours of a PNG (ImageMagick), or -1.
long colours(const fs::path& png) {
  const std::string cmd = "identify -format %k " + png.string() + " 2>/dev/null";
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return -1;
  long k = -1;
  if (std::fscanf(p, "%ld", &k) != 1) k = -1;
  ::pclose(p);
  return k;
}

void shoot(const std::string& name, const std::string& args) {
  const fs::path dir = fs::temp_directory_path() / ("cws_shot_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const fs::path png = dir / (name + ".png");
  const std::string src(CWS_SOURCE_DIR);
  // Bounded well inside ctest's 300 s for both pictures: a hang shows its
  // log instead of a timeout.
  const std::string cmd = "CWS_SCREENSHOT_DEADLINE=90 timeout -k 10 130 " + src +
                          "/src/tools/rviz_screenshot.sh " + png.string() + " " + args + " > " +
                          (dir / (name + ".log")).string() + " 2>&1";
  const int rc = std::system(cmd.c_str());
  const std::string log = cws_ros_test::readFile(dir / (name + ".log"));
  ASSERT_EQ(rc, 0) << log;
  ASSERT_TRUE(fs::exists(png)) << log;
  const long k = colours(png);
  std::printf("%s: %ld colours, %.0f kB\n", name.c_str(), k, fs::file_size(png) / 1e3);
  EXPECT_GT(k, 2000) << "rviz drew little or nothing: " << png;
  fs::remove_all(dir);
}

TEST(Screenshots, TheCellsDefaultJob) { shoot("winding_cell", "real_time_factor:=0"); }

TEST(Screenshots, TheCoilOfTheReadme) {
  const std::string src(CWS_SOURCE_DIR);
  shoot("coil_layers", "scene:=" + src + "/config/scenes/two_layers.yaml " +
                           "'overrides:=[process.turns=14, process.winding_width=7e-3]' " +
                           "real_time_factor:=0 rviz_config:=" + src + "/rviz/coil.rviz");
}

}  // namespace
