// The cell's URDF (wire_sim urdf, src/tools/cell_urdf.cpp): the spindle
// joint's origin, written as xyz and rpy, rebuilds the core's frame at rest
// that the simulation uses, for a tilted core axis too (the rpy read back
// with URDF's convention R = Rz(yaw) Ry(pitch) Rx(roll), independently of the
// writer's conversion); the port joints exist only with a supply. `wire_sim
// urdf` does not check the job's length, and with --on-error world gives the
// world link alone for a bad scene (the cell's launch file: the node then
// names the error).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <iostream>
#include <regex>
#include <sstream>
#include <string>

#include "cell_urdf.hpp"
#include "coil_winding_sim/core/machine/rotating_core.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace {

// The package's default scene: a winding cell with a supply.
const std::string kDefaultScene = std::string(CWS_SOURCE_DIR) + "/config/scenes/default.yaml";

// The three numbers of attribute `name` of the spindle joint's <origin>.
Eigen::Vector3d originAttribute(const std::string& urdf, const std::string& name) {
  const std::regex joint(
      "<joint name=\"spindle\"[\\s\\S]*?<origin xyz=\"([^\"]*)\" rpy=\"([^\"]*)\"");
  std::smatch m;
  EXPECT_TRUE(std::regex_search(urdf, m, joint)) << urdf;
  std::istringstream in(m[name == "xyz" ? 1 : 2].str());
  Eigen::Vector3d v;
  in >> v.x() >> v.y() >> v.z();
  return v;
}

TEST(CellUrdf, SpindleOriginIsTheCoresFrameAtRest) {
  for (const char* axis : {"[0, 0, 1]", "[1, 2, 3]", "[0, -1, 0]", "[-1, 0.2, -0.5]"}) {
    const cws::Scene scene =
        cws::loadScene("", {std::string("core.axis=") + axis, "core.position=[0.01, -0.02, 0.5]"});
    const std::string urdf = cws_tools::cellUrdf(scene);
    const Eigen::Vector3d xyz = originAttribute(urdf, "xyz");
    const Eigen::Vector3d rpy = originAttribute(urdf, "rpy");
    const Eigen::Matrix3d r = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                                  .toRotationMatrix();
    const cws::RotatingCore core(scene.core, 0.0);
    EXPECT_LT((xyz - Eigen::Vector3d(0.01, -0.02, 0.5)).norm(), 1e-15) << axis;
    EXPECT_LT((r - core.quaternionWorldCore(0.0).toRotationMatrix()).norm(), 1e-12) << axis;
    // The joint turns about the core's z axis, which is the scene's axis.
    EXPECT_LT((r.col(2) - scene.core.axis_world.normalized()).norm(), 1e-12) << axis;
  }
}

TEST(CellUrdf, PortJointsOnlyWithASupply) {
  const std::string with = cws_tools::cellUrdf(cws::loadScene(kDefaultScene, {}));
  for (const char* j : {"port_x", "port_y", "port_z"}) {
    EXPECT_NE(with.find(std::string("<joint name=\"") + j + "\" type=\"prismatic\">"),
              std::string::npos)
        << j;
  }
  const std::string without =
      cws_tools::cellUrdf(cws::loadScene(kDefaultScene, {"physics.supply=false"}));
  EXPECT_EQ(without.find("<joint name=\"port_x\""), std::string::npos);
  EXPECT_NE(without.find("<joint name=\"spindle\" type=\"continuous\">"), std::string::npos);
  // A dancer's pulley only with a dancer.
  EXPECT_EQ(with.find("<joint name=\"dancer\""), std::string::npos);
  const std::string dancer =
      cws_tools::cellUrdf(cws::loadScene(kDefaultScene, {"supply.tensioner.kind=dancer"}), "cell");
  EXPECT_NE(dancer.find("<joint name=\"dancer\" type=\"prismatic\">"), std::string::npos);
  EXPECT_NE(dancer.find("<child link=\"cell/dancer_pulley\"/>"), std::string::npos);
}

// urdfMain's exit status, with what it printed on std::cout and std::cerr.
int urdf(const std::vector<std::string>& args, std::string& out, std::string& err) {
  std::ostringstream o, e;
  std::streambuf* const cout_buf = std::cout.rdbuf(o.rdbuf());
  std::streambuf* const cerr_buf = std::cerr.rdbuf(e.rdbuf());
  std::vector<std::string> all{"urdf"};
  all.insert(all.end(), args.begin(), args.end());
  const int rc = cws_tools::urdfMain(all, kDefaultScene);
  std::cout.rdbuf(cout_buf);
  std::cerr.rdbuf(cerr_buf);
  out = o.str();
  err = e.str();
  return rc;
}

TEST(CellUrdf, TheJobsLengthIsNotCheckedAndABadSceneCanGiveTheWorldLink) {
  std::string out, err;
  // 300 s at 600 rpm needs more points than a scripted run may have: the
  // frames do not care.
  EXPECT_EQ(urdf({"--set", "process.duration=300"}, out, err), 0) << err;
  EXPECT_NE(out.find("<joint name=\"spindle\" type=\"continuous\">"), std::string::npos);
  // A misspelt key: refused by name, or (--on-error world) the world link.
  EXPECT_EQ(urdf({"--set", "proces.turns=3"}, out, err), 2);
  EXPECT_NE(err.find("'proces'"), std::string::npos) << err;
  EXPECT_EQ(urdf({"--set", "proces.turns=3", "--on-error", "world"}, out, err), 0);
  EXPECT_NE(out.find("<link name=\"world\"/>"), std::string::npos) << out;
  EXPECT_EQ(out.find("spindle"), std::string::npos) << out;
  EXPECT_EQ(urdf({"--on-error", "maybe"}, out, err), 2);
  EXPECT_NE(err.find("--on-error"), std::string::npos) << err;
}

}  // namespace
