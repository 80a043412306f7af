// Snapshots: a run continued from a saved state follows the original run
// exactly (same numbers), yield and stick states and supply points included;
// bad snapshots are refused without side effects.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "coil_winding_sim/core/run/simulation.hpp"

namespace {
// Steps a simulation to time t (accepted steps, no clipping beyond t).
void runTo(cws::Simulation& sim, double t) {
  while (sim.time() < t) sim.step(t);
}
}  // namespace

#ifdef CWS_SOURCE_DIR
namespace {
void continuedRunMatches(const std::string& law_key, const std::vector<std::string>& more = {}) {
  const std::string path = std::string(CWS_SOURCE_DIR) + "/config/scenes/default.yaml";
  // The explicit method: its state is the whole state, so a continued run is
  // the same to the bit (Newton steps: NewtonStepRunContinuesWithoutRetries).
  std::vector<std::string> keys = {"process.turns=0.1", "solver.integrator=symplectic_euler",
                                   law_key};
  keys.insert(keys.end(), more.begin(), more.end());
  cws::Simulation a(cws::loadScene(path, keys));
  runTo(a, 0.004);
  a.apply(cws::Setpoint::coreSpeed(50.0));
  a.apply(cws::Setpoint::supplyTension(45.0));
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
  for (int i = 0; i < a.model().constants().n; ++i) stuck += cws::wirePoint(a.model(), i).stick;
  EXPECT_GT(stuck, 0) << "stick states should be in use";
}
}  // namespace

TEST(Snapshot, ContinuedRunMatchesTheOriginal) {
  // The paper's case with friction (both laws: the anchors and flags of
  // elastic slip are history too), plasticity and a growing wire; a speed
  // and a tension setpoint change before the snapshot.
  for (const char* law : {"stick_speed", "elastic_slip"}) {
    SCOPED_TRACE(law);
    continuedRunMatches(std::string("contact.friction_law=") + law);
  }
  // A dancer and a nozzle with friction: the arm, the span, the draw-in
  // samples and the load cell's trace are history too.
  SCOPED_TRACE("dancer");
  continuedRunMatches("contact.friction_law=stick_speed",
                      {"supply.tensioner.kind=dancer", "supply.nozzle_friction=0.2",
                       "supply.nozzle_wrap_angle=1.5"});
}

TEST(Snapshot, NewtonStepRunContinuesWithoutRetries) {
  // bdf2 on the paper's case: a continued run restarts with one backward
  // Euler step (no past in a snapshot), so it is not the same numbers; but
  // it takes the same full steps, and the hysteresis lines its Newton
  // solves start from are the original's (without them the first step
  // after a snapshot was retried four times, down to 4e-7 s).
  const std::string path = std::string(CWS_SOURCE_DIR) + "/config/scenes/default.yaml";
  cws::Simulation a(cws::loadScene(path, {"solver.integrator=bdf2", "process.duration=0.03"}));
  for (double t_snap : {0.002, 0.004, 0.01, 0.02}) {
    runTo(a, t_snap);
    auto b = cws::Simulation::fromState(a.saveState());
    cws::Simulation& o = a;
    const long rejected = o.stepper().counts().rejected;
    const double h = a.scene().solver.implicit_step;
    for (int k = 1; k <= 10; ++k) {
      runTo(o, t_snap + k * h);
      runTo(*b, t_snap + k * h);
    }
    EXPECT_EQ(o.stepper().counts().rejected, rejected) << "t = " << t_snap;
    EXPECT_EQ(b->stepper().counts().rejected, rejected) << "t = " << t_snap;
    ASSERT_EQ(o.model().constants().n, b->model().constants().n);
    double worst = 0.0;
    for (int i = 0; i < o.model().constants().n; ++i) {
      worst = std::max(
          worst,
          (o.model().committed().p_world.col(i) - b->model().committed().p_world.col(i)).norm());
    }
    std::printf("continued at t = %g s: %g m off the original after 10 steps\n", t_snap, worst);
    EXPECT_LT(worst, 1e-3 * a.scene().wire.diameter) << "t = " << t_snap;
  }
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

TEST(Snapshot, HistoryIntegersAreChecked) {
  const std::vector<double> v = {1.0, -1.0, 0.5, 2.0, std::nan("")};
  cws::HistoryReader in(v);
  EXPECT_EQ(in.nextInteger(-1, 1, "line"), 1);
  EXPECT_EQ(in.nextInteger(-1, 1, "line"), -1);
  for (int k = 0; k < 3; ++k) {
    try {
      in.nextInteger(-1, 1, "stretching hysteresis line");
      FAIL() << "value " << k + 2 << " was accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("stretching hysteresis line"), std::string::npos)
          << e.what();
    }
  }
  EXPECT_TRUE(in.atEnd());
}
