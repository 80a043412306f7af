// The input log (core/input_log): a run repeated from its start with the
// logged inputs is the run that received them by hand, step for step; a
// refined start state halves the step of the run it continues; a log that
// overflowed refuses to replay.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "coil_winding_sim/core/run/error_estimate.hpp"
#include "coil_winding_sim/core/run/input_log.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"
#include "wire_test_support.hpp"

#ifdef CWS_SOURCE_DIR
namespace {
using cws_test::kQuarterStep;
const std::string kDefault = std::string(CWS_SOURCE_DIR) + "/config/scenes/default.yaml";

// The paper's case with Newton steps, 20 ms long.
cws::Scene shortCase() {
  return cws::loadScene(kDefault, {"solver.integrator=bdf2", "process.duration=0.02"});
}

// Steps sim to t_s [s] exactly.
void stepTo(cws::Simulation& sim, double t_s) {
  while (sim.time() < t_s - 1e-15) sim.step(t_s);
}
}  // namespace

TEST(InputLog, ReplayIsTheRunThatReceivedTheInputs) {
  const cws::Scene scene = shortCase();
  // The run driven by hand: a faster core at 5 ms, 45 N at 8 ms, other
  // friction at 9 ms (a wire batch's), a port command given at 10 ms for
  // 12 ms; the simulation logs each input it accepts.
  cws::Simulation by_hand(scene);
  const Eigen::Vector3d p_port(-22.5e-3, -5.0e-3, 0.0);
  stepTo(by_hand, 0.005);
  by_hand.apply(cws::Setpoint::coreSpeed(90.0));
  stepTo(by_hand, 0.008);
  by_hand.apply(cws::Setpoint::supplyTension(45.0));
  stepTo(by_hand, 0.009);
  by_hand.apply(cws::Setpoint::friction(0.30, 0.22));
  stepTo(by_hand, 0.010);
  by_hand.apply(cws::Setpoint::portPosition(p_port, 0.012));
  // A refused setpoint is not logged (a port position in the past).
  EXPECT_THROW(by_hand.apply(cws::Setpoint::portPosition(p_port, 0.001)), std::invalid_argument);
  stepTo(by_hand, scene.endTime());
  const cws::InputLog& log = by_hand.inputs();
  ASSERT_EQ(log.size(), 4u);
  EXPECT_NEAR(log.inputs()[0].t_s, 0.005, 1e-15);
  EXPECT_EQ(log.inputs()[2].setpoint.kind, cws::Setpoint::Kind::kFriction);
  EXPECT_EQ(log.inputs()[3].setpoint.kind, cws::Setpoint::Kind::kPortPosition);

  cws::Simulation replayed(scene);
  ASSERT_TRUE(log.replay(replayed, scene.endTime()));
  EXPECT_DOUBLE_EQ(replayed.time(), by_hand.time());
  EXPECT_EQ(replayed.model().constants().n, by_hand.model().constants().n);
  EXPECT_EQ((replayed.state() - by_hand.state()).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(replayed.stepper().counts().accepted, by_hand.stepper().counts().accepted);
  EXPECT_EQ(replayed.scene().contact.static_friction, 0.30);

  // The inputs matter: without them the run ends elsewhere (the port alone
  // moved by 0.5 mm).
  cws::Simulation without(scene);
  ASSERT_TRUE(cws::InputLog().replay(without, scene.endTime()));
  const int n = std::min(without.model().constants().n, by_hand.model().constants().n);
  const double moved = (without.model().committed().p_world.col(n - 1) -
                        by_hand.model().committed().p_world.col(n - 1))
                           .norm();
  EXPECT_GT(moved, 1e-4);
}

// A damping change (the node's dynamic_reconfigure sets one) is an input
// like the others: logged, and repeated by a replay.
TEST(InputLog, ADampingChangeIsLoggedAndReplayed) {
  const cws::Scene scene = cws::loadScene(
      kDefault, {"solver.integrator=bdf2", "process.duration=0.02", "physics.damping=true",
                 "damping.translational=1", "damping.rotational=1e-6"});
  cws::Simulation by_hand(scene);
  stepTo(by_hand, 0.006);
  by_hand.apply(cws::Setpoint::damping(20.0, 2e-5));
  stepTo(by_hand, scene.endTime());
  ASSERT_EQ(by_hand.inputs().size(), 1u);
  EXPECT_EQ(by_hand.inputs().inputs()[0].setpoint.kind, cws::Setpoint::Kind::kDamping);
  EXPECT_STREQ(by_hand.inputs().inputs()[0].setpoint.name(), "damping");
  EXPECT_EQ(by_hand.scene().damping.translational, 20.0);

  cws::Simulation replayed(scene);
  ASSERT_TRUE(by_hand.inputs().replay(replayed, scene.endTime()));
  EXPECT_EQ((replayed.state() - by_hand.state()).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(replayed.scene().damping.rotational, 2e-5);

  // Without it the run ends elsewhere: the change acts.
  cws::Simulation without(scene);
  stepTo(without, scene.endTime());
  EXPECT_GT((without.state() - by_hand.state()).cwiseAbs().maxCoeff(), 0.0);
  // A refused value is not logged.
  EXPECT_THROW(by_hand.apply(cws::Setpoint::damping(-1.0, 0.0)), cws::SceneError);
  EXPECT_EQ(by_hand.inputs().size(), 1u);
}

TEST(InputLog, ASimulationThatKeepsNoInputsLogsNone) {
  cws::Simulation sim(shortCase());
  sim.keepInputs(false);
  sim.apply(cws::Setpoint::supplyTension(45.0));
  EXPECT_EQ(sim.inputs().size(), 0u);
  EXPECT_EQ(sim.model().supply()->tension(), 45.0);  // applied all the same
  sim.keepInputs(true);
  sim.apply(cws::Setpoint::supplyTension(46.0));
  EXPECT_EQ(sim.inputs().size(), 1u);
}

TEST(InputLog, StopEndsTheReplayBeforeTheEnd) {
  const cws::Scene scene = shortCase();
  cws::Simulation sim(scene);
  int asked = 0;
  EXPECT_FALSE(cws::InputLog().replay(sim, scene.endTime(), [&] { return ++asked > 10; }));
  EXPECT_LT(sim.time(), scene.endTime());
}

TEST(InputLog, AnOverflowedLogRefusesToReplay) {
  cws::InputLog log;
  for (std::size_t k = 0; k <= cws::InputLog::kCapacity; ++k)
    log.record(1e-9 * k, cws::Setpoint::supplyTension(30.0));
  EXPECT_TRUE(log.overflowed());
  EXPECT_EQ(log.size(), cws::InputLog::kCapacity);
  cws::Simulation sim(shortCase());
  try {
    log.replay(sim, 0.02);
    FAIL() << "an overflowed log was replayed";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("overflowed"), std::string::npos) << e.what();
  }
  EXPECT_EQ(sim.time(), 0.0);
  log.clear();
  EXPECT_FALSE(log.overflowed());
  EXPECT_EQ(log.size(), 0u);
}

TEST(InputLog, RefinedStateContinuesAtAQuarterOfTheStep) {
  const cws::Scene scene = shortCase();
  cws::Simulation sim(scene);
  stepTo(sim, 0.004);
  std::string what;
  const cws::SimulationState start = sim.saveState();
  auto refined = cws::Simulation::fromState(cws::refinedState(start, what));
  EXPECT_EQ(what, kQuarterStep);
  EXPECT_DOUBLE_EQ(refined->scene().solver.implicit_step, 0.25 * scene.solver.implicit_step);
  EXPECT_DOUBLE_EQ(refined->time(), 0.004);
  EXPECT_EQ((refined->state() - sim.state()).cwiseAbs().maxCoeff(), 0.0);
  // It resumes with a quarter of the step the run would have taken next
  // (which may be below solver.implicit_step after a retried step).
  EXPECT_DOUBLE_EQ(refined->stepper().nextStep(), 0.25 * sim.stepper().nextStep());
  const double h = sim.stepper().nextStep();
  refined->step(1.0);
  EXPECT_NEAR(refined->time() - 0.004, 0.25 * h, 1e-15);
}
#endif

#ifdef CWS_SOURCE_DIR
TEST(InputLog, EstimateFromInputsIsTheRefinedRunWithTheSameInputs) {
  const cws::Scene scene = shortCase();
  // The job: a tension step at 6 ms, given by hand and logged.
  cws::Simulation job(scene);
  const cws::SimulationState start = job.saveState();
  stepTo(job, 0.006);
  job.apply(cws::Setpoint::supplyTension(60.0));
  stepTo(job, scene.endTime());
  const cws::InputLog& log = job.inputs();
  const std::optional<cws::ErrorEstimate> e = cws::estimateFromInputs(start, log, job);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->refinement, kQuarterStep);
  EXPECT_GT(e->refined_wall_s, 0.0);
  std::printf(
      "bdf2 against a quarter of its step, tension step at 6 ms: shape %.4f d, bulging %.4f\n",
      e->shape_error_rel_diameter, e->bulging_error_rel);

  // Independently: the refined scene run by hand with the same step.
  std::string what;
  cws::Simulation refined(cws::refinedScene(scene, what));
  stepTo(refined, 0.006);
  refined.apply(cws::Setpoint::supplyTension(60.0));
  stepTo(refined, scene.endTime());
  const cws::ErrorEstimate by_hand = cws::compareWithRefined(job, refined, what);
  EXPECT_EQ(e->shape_error_rel_diameter, by_hand.shape_error_rel_diameter);
  EXPECT_EQ(e->bulging_error_rel, by_hand.bulging_error_rel);
  EXPECT_GT(e->shape_error_rel_diameter, 0.0);
  EXPECT_LT(e->shape_error_rel_diameter, 0.05);

  // Without the tension step the refined run is another job: far off.
  const std::optional<cws::ErrorEstimate> wrong =
      cws::estimateFromInputs(start, cws::InputLog(), job);
  ASSERT_TRUE(wrong.has_value());
  EXPECT_GT(wrong->shape_error_rel_diameter, 10.0 * e->shape_error_rel_diameter);
}
#endif
