// History state (yield points, plastic work) changes only on accepted steps,
// and what a scene switches off is neither built nor allocated.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "coil_winding_sim/core/time_steppers/rkf45.hpp"
#include "wire_test_support.hpp"

using cws_test::cantilever;

namespace {
// A wire whose root is yielding: a strong tip force ramps in 5 ms.
cws::Scene yieldingScene() {
  cws::Scene s = cantilever(0.02, 10);
  cws::LoadKeyframe a, b;
  b.time = 0.005;
  b.force_world = {0.0, 0.5, 0.0};
  s.end.load = {a, b};
  s.process.duration = 0.01;
  return s;
}
}  // namespace

TEST(Commit, RejectedAttemptLeavesHysteresisUntouched) {
  const cws::Scene s = yieldingScene();
  cws::WireModel model(s);
  cws::Rkf45 rk(s.solver, model.size());
  Eigen::VectorXd y = model.initialState();
  double t = 0.0;
  // Step until the root has yielded, so that trial states cross yield points.
  while (t < 0.004) rk.step(model, t, y, 0.01);
  const std::vector<double> before = model.history();
  ASSERT_FALSE(before.empty());
  ASSERT_GT(cws::wirePoint(model, 0).plastic_curvature_1pm, 0.0) << "the root should have yielded";

  // A far too large step fails the error test; it must change nothing.
  const double error = rk.attempt(model, t, y, 1e-4);
  ASSERT_GT(error, 1.0);
  EXPECT_EQ(model.history(), before);

  // An accepted step does move the yield points, exactly once: the committed
  // state equals the two-line law applied to the new strain from `before`.
  const long accepted = rk.counts().accepted;
  rk.step(model, t, y, 0.01);
  EXPECT_EQ(rk.counts().accepted, accepted + 1);
  const std::vector<double> after = model.history();
  EXPECT_NE(after, before);
  const cws::TwoLineLaw law(s.wire.stretch);
  const int segments = model.constants().n - 1;
  for (int j = 0; j < segments; ++j) {
    const double x = model.stretching().strain(model.committed(), j);
    EXPECT_EQ(after[j], law.movedUpper(x, before[j])) << "segment " << j;
  }
}

TEST(Commit, StepWithRejectionsCommitsOnlyTheAcceptedState) {
  // Start with a step far too large so that the first call rejects first.
  cws::Scene s = yieldingScene();
  s.solver.initial_step = 5e-5;
  cws::WireModel model(s);
  cws::Rkf45 rk(s.solver, model.size());
  Eigen::VectorXd y = model.initialState();
  double t = 0.0;
  while (t < 0.004) rk.step(model, t, y, 0.01);
  const std::vector<double> before = model.history();
  // Force a large next attempt again.
  cws::Rkf45 rk_big(s.solver, model.size());
  rk_big.step(model, t, y, 0.01);
  EXPECT_GT(rk_big.counts().rejected, 0);
  EXPECT_EQ(rk_big.counts().accepted, 1);
  const cws::TwoLineLaw law(s.wire.stretch);
  const std::vector<double> after = model.history();
  for (int j = 0; j < model.constants().n - 1; ++j) {
    EXPECT_EQ(after[j], law.movedUpper(model.stretching().strain(model.committed(), j), before[j]));
  }
}

TEST(Commit, StepFloorStopsTheRunWithAClearError) {
  // A floor above the stable step of this stiff wire cannot be met.
  cws::Scene s = yieldingScene();
  s.solver.min_step = 5e-5;
  s.solver.initial_step = 5e-5;
  cws::Simulation sim(s);
  try {
    sim.run();
    FAIL() << "expected an IntegrationError";
  } catch (const cws::IntegrationError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("step size fell below solver.min_step"), std::string::npos) << msg;
    EXPECT_NE(msg.find("rkf45"), std::string::npos) << msg;
  }
}

TEST(PhysicsSwitches, OnlyTheEffectsASceneNeedsAreBuilt) {
  auto names = [](const cws::Scene& s) {
    const cws::WireModel model(s);
    std::set<std::string> out;
    for (const cws::ForceEffect* e : model.effects()) out.insert(e->name());
    return out;
  };
  cws::Scene s = cantilever(0.01, 5);
  s.physics.torsion = false;
  EXPECT_EQ(names(s), (std::set<std::string>{"stretching", "bending", "end_load"}));
  s.physics.torsion = true;
  s.physics.gravity = true;
  s.physics.damping = true;
  EXPECT_EQ(names(s), (std::set<std::string>{"stretching", "bending", "twisting", "gravity",
                                             "damping", "end_load"}));
  // Without plasticity no yield state exists at all.
  s.physics.plasticity = false;
  EXPECT_TRUE(cws::WireModel(s).history().empty());
  s.physics.plasticity = true;
  EXPECT_FALSE(cws::WireModel(s).history().empty());
}
