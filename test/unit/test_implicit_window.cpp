// The Newton steps held to the explicit model on a short window (issue
// 39): the paper's planar case at 1200 rpm and 30 N, the reference model,
// stopped at 50 ms (the first landings and sticks), integrated by bdf2 at a
// small step and by symplectic_euler at its automatic step. A Newton
// formulation that solved a slightly different model (a law, a flag, an
// anchor or a dashpot that is not the explicit one) would show here as a
// gap that no step closes. Measured at 2 mm segments (2026-11-27): bdf2 at
// 2e-6 s lies 0.0017 d from the explicit run, symplectic_euler at a quarter
// of its step 0.0026 d; bdf2 without the dashpots (damping_ratio 0) 0.0099 d,
// with mu_s 0.25 instead of 0.23 0.044 d
// (docs/history/2026-11-27-newton-convergence-and-step-control.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "coil_winding_sim/core/run/error_estimate.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"
#include "coil_winding_sim/core/time_steppers/time_stepper.hpp"

namespace {

const std::string kDefault = std::string(CWS_SOURCE_DIR) + "/config/scenes/default.yaml";

// The window's run; a later process.duration in `method` wins.
cws::Simulation windowRun(const std::vector<std::string>& method) {
  std::vector<std::string> keys{"process.core_speed_rpm=1200", "process.duration=0.05",
                                "wire.segment_length=2e-3"};
  keys.insert(keys.end(), method.begin(), method.end());
  cws::Simulation sim(cws::loadScene(kDefault, keys));
  sim.run();
  return sim;
}

// Largest distance between corresponding points over the wire diameter
// (both runs end at the same time, so the core stands at the same angle).
double pointDistance(const cws::Simulation& a, const cws::Simulation& b) {
  const cws::WireModel& ma = a.model();
  const cws::WireModel& mb = b.model();
  const int n = std::min(ma.constants().n, mb.constants().n);
  double far = 0.0;
  for (int i = 0; i < n; ++i) {
    far = std::max(far, (ma.committed().p_world.col(i) - mb.committed().p_world.col(i)).norm());
  }
  return far / (2.0 * ma.constants().radius);
}

TEST(ImplicitWindow, Bdf2AtSmallStepsIsTheExplicitModel) {
  const cws::Simulation explicit_run = windowRun({"solver.integrator=symplectic_euler"});
  const cws::Simulation bdf2 = windowRun({"solver.integrator=bdf2", "solver.implicit_step=2e-6"});
  ASSERT_EQ(explicit_run.model().constants().n, bdf2.model().constants().n);
  const double gap = pointDistance(explicit_run, bdf2);
  std::printf("bdf2 at 2e-6 s against symplectic_euler after 50 ms: %.4f d\n", gap);
  // Half way between the two explicit runs' own spread (0.0026 d) and the
  // undamped model's 0.0099 d.
  EXPECT_LT(gap, 0.005);
}

// An honest error estimate (issue 39): bdf2 at the default step, its
// estimate (the run again at a quarter of the step, the difference x 4/3)
// against its distance from the explicit run, at the default 1 mm segments
// after 50 ms (the first span wound). Measured (2026-11-27): true 0.0095 d
// and 1.99 % in bulging, estimated 0.0104 d and 1.90 %; the estimate at
// half the step, as it was made before, said 0.0024 d and 0.42 % on the
// whole case, where the error was 0.0135 d and 2.45 %
// (docs/PERFORMANCE.md, "An honest error estimate").
TEST(ImplicitWindow, Bdf2sErrorEstimateIsWithinAFactorOfTwoOfItsError) {
  const std::vector<std::string> one_mm{"wire.segment_length=1e-3"};
  auto with = [&](std::vector<std::string> keys) {
    keys.insert(keys.begin(), one_mm.begin(), one_mm.end());
    return keys;
  };
  const cws::Simulation explicit_run = windowRun(with({"solver.integrator=symplectic_euler"}));
  // Without strike steps: the window's error is then the targets' size.
  // (With them, the default, its strike at 1200 rpm leaves 0.0037 d; on the
  // five whole accuracy cases their estimate lies within 0.61-2.8 of the
  // true error: docs/history/2026-11-29-accuracy-by-default.md.)
  const cws::Simulation bdf2 = windowRun(with({"solver.integrator=bdf2", "solver.strike_step=0"}));
  std::string what;
  cws::Simulation refined(cws::refinedScene(bdf2.scene(), what));
  refined.run();
  const cws::ErrorEstimate estimate = cws::compareWithRefined(bdf2, refined, what);
  const cws::RunDifference error = cws::differenceOf(bdf2, explicit_run);
  ASSERT_TRUE(estimate.bulging_valid && error.bulging_valid);
  std::printf("bdf2 after 50 ms: error %.4f d, %.4f in bulging; estimated %.4f d, %.4f\n",
              error.shape_rel_diameter, error.bulging_rel, estimate.shape_error_rel_diameter,
              estimate.bulging_error_rel);
  // The window's errors are those the targets care about (hundredths of d,
  // percent), not the explicit runs' own spread (0.0015 d).
  ASSERT_GT(error.shape_rel_diameter, 0.005);
  EXPECT_GT(estimate.shape_error_rel_diameter, 0.5 * error.shape_rel_diameter);
  EXPECT_LT(estimate.shape_error_rel_diameter, 2.0 * error.shape_rel_diameter);
  EXPECT_GT(estimate.bulging_error_rel, 0.5 * error.bulging_rel);
  EXPECT_LT(estimate.bulging_error_rel, 2.0 * error.bulging_rel);
}

// Progress is guaranteed (issue 39). Newton allowed a single iteration
// fails at most steps (a step from its predictor mostly needs two), and
// solver.min_step at 1e-6 s puts the smallest step within reach of the
// first retries, so the stepper takes stretches of explicit steps and
// resumes Newton steps after each. The run reaches its end, counts its
// stretches and says why they began, keeps its energy balance (an
// independent account: the work done against the energies), and ends where
// the explicit run ends (its steps are mostly explicit ones: within the
// explicit runs' own spread, 0.0026 d).
TEST(ImplicitWindow, NewtonThatCannotGoOnFallsBackToExplicitSteps) {
  const std::vector<std::string> window{"process.duration=0.02"};
  std::vector<std::string> failing = window;
  failing.insert(failing.end(), {"solver.integrator=bdf2", "solver.newton_max_iterations=1",
                                 "solver.min_step=1e-6", "solver.initial_step=1e-6"});
  const cws::Simulation sim = windowRun(failing);
  EXPECT_DOUBLE_EQ(sim.time(), sim.endTime());
  const cws::NewtonCounts* n = sim.stepper().newtonCounts();
  ASSERT_NE(n, nullptr);
  std::printf("%ld stretches of explicit steps, %ld explicit steps of %ld; last: %s\n",
              n->fallback_stretches, n->fallback_steps, sim.stepper().counts().accepted,
              n->fallback_cause);
  // Again and again, with Newton steps between them.
  EXPECT_GE(n->fallback_stretches, 3);
  EXPECT_GT(n->fallback_steps, 0);
  EXPECT_GT(sim.stepper().counts().accepted, n->fallback_steps);
  EXPECT_NE(std::string(n->fallback_cause).find("Newton did not converge"), std::string::npos)
      << n->fallback_cause;
  const cws::EnergyReport e = sim.energy();
  EXPECT_LT(std::abs(e.imbalance()), 0.01 * std::abs(e.work_done));
  std::vector<std::string> reference = window;
  reference.push_back("solver.integrator=symplectic_euler");
  const double gap = pointDistance(windowRun(reference), sim);
  std::printf("against symplectic_euler after 20 ms: %.4f d\n", gap);
  EXPECT_LT(gap, 0.005);
}

// A Newton step that converges is never replaced: the paper's case at its
// default step takes no explicit step.
TEST(ImplicitWindow, NewtonThatConvergesTakesNoExplicitStep) {
  const cws::Simulation sim = windowRun({"solver.integrator=bdf2"});
  const cws::NewtonCounts* n = sim.stepper().newtonCounts();
  ASSERT_NE(n, nullptr);
  EXPECT_EQ(n->fallback_stretches, 0);
  EXPECT_EQ(n->fallback_steps, 0);
  EXPECT_STREQ(n->fallback_cause, "");
}

}  // namespace
