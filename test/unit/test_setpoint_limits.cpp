// Setpoint limits (setpoint_limits.hpp): a scene's own setpoints and the
// commands of a run are refused by one check, with one message that names
// the limit's key; a refused command leaves the run as it was.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "coil_winding_sim/core/run/simulation.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"
#include "coil_winding_sim/core/scene/setpoint_limits.hpp"

namespace {
const std::string kDefault = std::string(CWS_SOURCE_DIR) + "/config/scenes/default.yaml";

std::string refusalOf(cws::Simulation& sim, bool tension, double value) {
  try {
    if (tension) {
      sim.apply(cws::Setpoint::supplyTension(value));
    } else {
      sim.apply(cws::Setpoint::coreSpeed(value));
    }
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(SetpointLimits, ARunRefusesCommandsBeyondTheScenesLimits) {
  cws::Simulation sim(cws::loadScene(
      kDefault,
      {"process.max_core_speed_rpm=1000", "process.max_tension=100", "solver.integrator=bdf2"}));
  const cws::SetpointLimits limits = cws::SetpointLimits::of(sim.scene().process);
  EXPECT_NEAR(limits.max_core_speed_rad_s, 1000.0 * 2.0 * M_PI / 60.0, 1e-12);
  const double command = sim.model().core()->command();
  const double w_over = cws::rpmToRadPerSec(1500.0);
  const std::string why = refusalOf(sim, false, w_over);
  EXPECT_NE(why.find("process.max_core_speed_rpm = 1000 rpm"), std::string::npos) << why;
  EXPECT_EQ(why, cws::coreSpeedText(w_over) + " " + cws::coreSpeedRefusal(limits, w_over));
  EXPECT_EQ(sim.model().core()->command(), command);  // unchanged
  EXPECT_NE(refusalOf(sim, false, -w_over), "");      // either direction
  EXPECT_NE(refusalOf(sim, false, std::numeric_limits<double>::quiet_NaN()).find("finite"),
            std::string::npos);
  EXPECT_EQ(refusalOf(sim, false, cws::rpmToRadPerSec(-999.0)), "");
  EXPECT_NE(refusalOf(sim, true, 120.0).find("process.max_tension = 100 N"), std::string::npos);
  EXPECT_NE(refusalOf(sim, true, -1.0).find("negative"), std::string::npos);
  EXPECT_EQ(refusalOf(sim, true, 99.0), "");
}

TEST(SetpointLimits, ASceneIsRefusedWithTheSameMessage) {
  const cws::Scene ok = cws::loadScene(kDefault, {"process.max_core_speed_rpm=1000"});
  const std::string expected =
      cws::coreSpeedRefusal(cws::SetpointLimits::of(ok.process), cws::rpmToRadPerSec(1500.0));
  try {
    cws::loadScene(kDefault, {"process.max_core_speed_rpm=1000", "process.core_speed_rpm=1500"});
    FAIL() << "a scene beyond its own speed limit was accepted";
  } catch (const cws::SceneError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("process.core_speed_rpm"), std::string::npos) << what;
    EXPECT_NE(what.find(expected), std::string::npos) << what;
  }
}
