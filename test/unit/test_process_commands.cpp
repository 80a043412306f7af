// A job's own setpoints and faults (issue 57's abuse cases): setpoints at
// simulated times (process.commands), applied at their times by every run
// of the scene and kept across a snapshot, and a traverse that stalls
// (process.traverse_stall_turn, process.traverse_stall_turns), against
// the closed form of its profile.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "coil_winding_sim/core/machine/traverse_profile.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace {
constexpr double kTurn = 2.0 * M_PI;  // [rad]
}  // namespace

// 1 mm per turn over a travel of 4 mm, stalled from turn 2 for 3 turns: it
// stands at 2 mm, at rest, until turn 5, then goes on as the unstalled
// traverse did from turn 2 (3 turns later along the core angle).
TEST(TraverseStall, HoldsThePortThenGoesOnWhereItStopped) {
  const cws::TraverseProfile plain{1e-3, 4e-3, 3};
  const cws::TraverseProfile p = plain.stalled(2.0, 3.0);
  EXPECT_NEAR(p.at(1.5 * kTurn).offset, 1.5e-3, 1e-15);
  for (double turns : {2.01, 2.5, 4.0, 4.99}) {
    EXPECT_NEAR(p.at(turns * kTurn).offset, 2e-3, 1e-15) << turns << " turns";
    EXPECT_EQ(p.at(turns * kTurn).per_rad, 0.0) << turns << " turns";
  }
  for (double turns : {5.5, 8.25, 11.0, 30.0}) {
    const cws::TraverseProfile::Position a = p.at(turns * kTurn);
    const cws::TraverseProfile::Position b = plain.at((turns - 3.0) * kTurn);
    EXPECT_NEAR(a.offset, b.offset, 1e-15) << turns << " turns";
    EXPECT_EQ(a.per_rad, b.per_rad) << turns << " turns";
    EXPECT_EQ(a.layer, b.layer) << turns << " turns";
  }
}

#ifdef CWS_SOURCE_DIR
namespace {
const std::string kDefault = std::string(CWS_SOURCE_DIR) + "/config/scenes/default.yaml";

void expectRefused(const std::vector<std::string>& overrides, const std::string& key,
                   const std::string& why) {
  try {
    cws::loadScene(kDefault, overrides);
    ADD_FAILURE() << "accepted, expected a SceneError for '" << key << "'";
  } catch (const cws::SceneError& e) {
    EXPECT_EQ(e.key(), key) << "what(): " << e.what();
    EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << "what(): " << e.what();
  }
}
}  // namespace

// A stalled traverse's turns lay no layer: the plan counts the turns the
// traverse moves in.
TEST(TraverseStall, ItsTurnsAreNotPlannedLayers) {
  const std::string two_layers = std::string(CWS_SOURCE_DIR) + "/config/scenes/two_layers.yaml";
  const cws::Scene plain = cws::loadScene(two_layers, {});
  const cws::Scene s = cws::loadScene(
      two_layers, {"process.turns=" + std::to_string(plain.process.turns + 10.0),
                   "process.traverse_stall_turn=30", "process.traverse_stall_turns=10"});
  EXPECT_DOUBLE_EQ(s.traverseTurns(), plain.process.turns);
  EXPECT_EQ(s.plannedLayers(), plain.plannedLayers());
  // A stall that begins after the job's end stalls nothing within it.
  const cws::Scene late = cws::loadScene(
      two_layers, {"process.traverse_stall_turn=1000", "process.traverse_stall_turns=10"});
  EXPECT_DOUBLE_EQ(late.traverseTurns(), plain.process.turns);
}

TEST(ProcessCommands, AreCheckedWhenTheSceneLoads) {
  expectRefused({"process.duration=1",
                 "process.commands=[{time: 0.5, tension: 20}, {time: 0.2, "
                 "tension: 30}]"},
                "process.commands[1].time", "must not decrease");
  expectRefused({"process.commands=[{time: 0.5}]"}, "process.commands[0]", "no setpoint");
  expectRefused({"process.commands=[{time: 0.5, speed: 3}]"}, "process.commands[0].speed",
                "unknown key");
  expectRefused({"process.commands=[{time: 0.5, core_speed_rpm: -600}]"},
                "process.commands[0].core_speed_rpm", "process.duration");
  expectRefused({"process.duration=1", "process.commands=[{time: 0.5, core_speed_rpm: 7000}]"},
                "process.commands[0].core_speed_rpm", "process.max_core_speed_rpm");
  expectRefused({"process.commands=[{time: 0.5, tension: 400}]"}, "process.commands[0].tension",
                "process.max_tension");
  expectRefused({"process.commands=[{time: -1, tension: 20}]"}, "process.commands[0].time", "");
}

// The paper's planar case at 600 rpm and 30 N: the tension drops to 1 N at
// 20 ms and the core reverses at 30 ms. A step ends on each command's time,
// the commands act from then on, and they are part of the scene (a rerun
// repeats them), not inputs of the run.
TEST(ProcessCommands, ActAtTheirTimesAndAcrossASnapshot) {
  const cws::Scene s = cws::loadScene(
      kDefault, {"process.duration=0.05",
                 "process.commands=[{time: 0.02, tension: 1}, {time: 0.03, core_speed_rpm: "
                 "-600}]"});
  cws::Simulation sim(s);
  const cws::Supply& supply = *sim.model().supply();
  const cws::RotatingCore& core = *sim.model().core();
  std::vector<double> ends;
  std::unique_ptr<cws::Simulation> continued;
  while (sim.time() < sim.endTime()) {
    const double t0 = sim.time();
    sim.step(sim.endTime());
    ends.push_back(sim.time());
    EXPECT_EQ(supply.tension(), sim.time() < 0.02 - 1e-12 ? 30.0 : 1.0) << "t = " << sim.time();
    const double omega = cws::rpmToRadPerSec(sim.time() < 0.03 - 1e-12 ? 600.0 : -600.0);
    EXPECT_EQ(core.command(), omega) << "t = " << sim.time();
    if (!continued && t0 < 0.025 && sim.time() >= 0.025) {
      continued = cws::Simulation::fromState(sim.saveState());
    }
  }
  for (double t : {0.02, 0.03}) {
    bool hit = false;
    for (double e : ends) hit = hit || std::abs(e - t) <= 1e-12;
    EXPECT_TRUE(hit) << "no step ended at t = " << t;
  }
  EXPECT_EQ(sim.inputs().size(), 0u);
  // Continued from 25 ms: the tension command is not given again, the
  // speed command still is.
  ASSERT_TRUE(continued);
  EXPECT_EQ(continued->model().supply()->tension(), 1.0);
  EXPECT_EQ(continued->model().core()->command(), cws::rpmToRadPerSec(600.0));
  continued->run();
  EXPECT_EQ(continued->model().core()->command(), cws::rpmToRadPerSec(-600.0));
  EXPECT_EQ(continued->model().supply()->tension(), 1.0);
}
#endif
