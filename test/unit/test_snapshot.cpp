// Snapshots: a run continued from a saved state follows the original run
// exactly (same numbers), yield and stick states and supply points included;
// bad snapshots are refused without side effects.
#include <gtest/gtest.h>

#include <string>

#include "coil_winding_sim/core/simulation.hpp"

namespace {
// Steps a simulation to time t (accepted steps, no clipping beyond t).
void runTo(cws::Simulation& sim, double t) {
  while (sim.time() < t) sim.step(t);
}
}  // namespace

#ifdef CWS_SOURCE_DIR
TEST(Snapshot, ContinuedRunMatchesTheOriginal) {
  // The paper's case with friction, plasticity and a growing wire; a speed
  // and a tension setpoint change before the snapshot.
  const std::string path = std::string(CWS_SOURCE_DIR) + "/config/scenes/default.yaml";
  cws::Simulation a(cws::loadScene(path, {"process.turns=0.1"}));
  runTo(a, 0.004);
  a.setCoreSpeed(50.0);
  a.setSupplyTension(45.0);
  runTo(a, 0.006);
  const cws::SimulationState st = a.saveState();
  auto b = cws::Simulation::fromState(st);
  ASSERT_EQ(b->time(), a.time());
  const double t_end = 0.009;
  runTo(a, t_end);
  runTo(*b, t_end);
  ASSERT_EQ(a.model().constants().n, b->model().constants().n);
  EXPECT_GT(a.model().constants().n, st.model.points) << "the wire should have grown";
  EXPECT_EQ(a.time(), b->time());
  EXPECT_EQ(a.stepper().counts().accepted, b->stepper().counts().accepted);
  const int size = a.model().size();
  EXPECT_EQ(a.state().head(size), b->state().head(size));
  EXPECT_EQ(a.model().history(), b->model().history());
  int stuck = 0;
  for (int i = 0; i < a.model().constants().n; ++i) stuck += a.model().point(i).stick;
  EXPECT_GT(stuck, 0) << "stick states should be in use";
}
#endif

TEST(Snapshot, BadSnapshotsAreRefused) {
  cws::Scene s;
  s.wire.length = 0.01;
  s.wire.segment_length = 0.002;
  s.process.duration = 1e-4;
  cws::Simulation a(s);
  runTo(a, 5e-5);
  const cws::SimulationState good = a.saveState();

  cws::SimulationState bad = good;
  bad.model.y.resize(bad.model.y.size() - 1);
  EXPECT_THROW(cws::Simulation::fromState(bad), std::runtime_error);
  bad = good;
  bad.model.y[5] = std::nan("");
  EXPECT_THROW(cws::Simulation::fromState(bad), std::runtime_error);
  bad = good;
  bad.model.history.push_back(1.0);
  EXPECT_THROW(cws::Simulation::fromState(bad), std::runtime_error);
  bad = good;
  bad.scene_yaml = "wire: {diameter: -1}";
  EXPECT_THROW(cws::Simulation::fromState(bad), cws::SceneError);
  bad = good;
  bad.model.points = 3;
  EXPECT_THROW(cws::Simulation::fromState(bad), std::runtime_error);
  // The original is untouched and still runs.
  EXPECT_NO_THROW(runTo(a, 1e-4));
}
