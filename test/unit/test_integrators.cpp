// The registry of integrators drives the scene's key, validation and the
// stepper factory; the error estimate refines the setting each one reads.
#include <gtest/gtest.h>

#include "coil_winding_sim/core/run/error_estimate.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"
#include "coil_winding_sim/core/scene/integrators.hpp"
#include "wire_test_support.hpp"

#ifdef CWS_SOURCE_DIR
namespace {
using cws_test::kQuarterStep;
const std::string kDefault = std::string(CWS_SOURCE_DIR) + "/config/scenes/default.yaml";
constexpr double kPi = 3.14159265358979323846;
}  // namespace

TEST(Integrators, EveryRegisteredNameBuildsItsStepper) {
  for (const cws::IntegratorInfo& info : cws::integrators()) {
    cws::Scene s = cws::loadScene(kDefault, {std::string("solver.integrator=") + info.name,
                                             "process.duration=1e-4", "solver.fixed_step=1e-7"});
    cws::Simulation sim(s);
    EXPECT_EQ(std::string(sim.stepper().name()), info.name);
    EXPECT_FALSE(info.keys.empty()) << info.name;
  }
}

TEST(Integrators, UnknownNameListsTheRegistry) {
  try {
    cws::loadScene(kDefault, {"solver.integrator=leapfrog"});
    FAIL() << "an unknown integrator was accepted";
  } catch (const cws::SceneError& e) {
    EXPECT_EQ(e.key(), "solver.integrator");
    for (const std::string& name : cws::integratorNames()) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << name;
    }
  }
}

TEST(Integrators, NewtonStepMethodsTakeA3DScene) {
  // The 3-D formulation: the paper's spiral takes a few Newton steps, with
  // the frame constraints held to Newton's tolerance.
  for (const cws::IntegratorInfo& info : cws::integrators()) {
    if (!info.newton_steps) continue;
    cws::Simulation sim(
        cws::loadScene(std::string(CWS_SOURCE_DIR) + "/config/scenes/paper_case_3d.yaml",
                       {std::string("solver.integrator=") + info.name, "process.duration=0.002"}));
    sim.run();
    EXPECT_EQ(sim.time(), sim.endTime()) << info.name;
    EXPECT_LT(sim.maxConstraintResidual(), 1e-6) << info.name;
  }
}

TEST(ErrorEstimate, RefinesTheSettingTheMethodReads) {
  std::string what;
  cws::Scene s =
      cws::loadScene(kDefault, {"solver.integrator=bdf2", "solver.steps_per_revolution=500"});
  EXPECT_DOUBLE_EQ(cws::refinedScene(s, what).solver.implicit_step, 0.25 * s.solver.implicit_step);
  EXPECT_DOUBLE_EQ(cws::refinedScene(s, what).solver.steps_per_revolution, 2000.0);
  EXPECT_EQ(what, kQuarterStep);
  // A first-order error e(h) = c h: the difference to h / 4 is 3/4 of it.
  EXPECT_DOUBLE_EQ(cws::refinementScale(s), 4.0 / 3.0);
  s = cws::loadScene(kDefault, {"solver.integrator=implicit_euler"});
  EXPECT_DOUBLE_EQ(cws::refinedScene(s, what).solver.implicit_step, 0.25 * s.solver.implicit_step);
  EXPECT_EQ(what, kQuarterStep);
  s = cws::loadScene(kDefault, {"solver.integrator=symplectic_euler"});
  EXPECT_DOUBLE_EQ(*cws::refinedScene(s, what).solver.fixed_step, 0.5 * cws::fixedStep(s));
  EXPECT_EQ(cws::refinementScale(s), 1.0);
  s = cws::loadScene(kDefault, {"solver.integrator=rkf45"});
  EXPECT_DOUBLE_EQ(cws::refinedScene(s, what).solver.rtol, 0.1 * s.solver.rtol);
  EXPECT_DOUBLE_EQ(cws::refinedScene(s, what).solver.atol, 0.1 * s.solver.atol);
  EXPECT_EQ(cws::refinementScale(s), 1.0);
}

// The shape error is the distance of the two curves, not of the points
// with the same index: a wire that was fed a little more or less lies on
// the same curve, its points shifted along it.
TEST(ErrorEstimate, CurveDistanceIsTheLargestOffsetBetweenTwoCurves) {
  const double l = 1e-3;
  std::vector<Eigen::Vector3d> a, along, offset, bump;
  for (int i = 0; i < 40; ++i) {
    a.emplace_back(i * l, 0.0, 0.0);
    along.emplace_back((i + 0.3) * l, 0.0, 0.0);
    offset.emplace_back(i * l, 2e-5, 0.0);
    bump.emplace_back(i * l, i == 20 ? 5e-5 : 0.0, 0.0);
  }
  // Shifted along itself: only the end that sticks out counts (0.3 l past
  // the last point of a), nothing in between.
  EXPECT_NEAR(cws::curveDistance(a, along), 0.3 * l, 1e-12);
  along.pop_back();
  along.erase(along.begin());
  EXPECT_NEAR(cws::curveDistance(a, along), 1.3 * l, 1e-12);  // a's first point from along's start
  EXPECT_NEAR(cws::curveDistance(a, offset), 2e-5, 1e-12);
  EXPECT_NEAR(cws::curveDistance(a, bump), 5e-5, 1e-12);
  EXPECT_EQ(cws::curveDistance(a, a), 0.0);
}

TEST(ErrorEstimate, ARunAgainstItselfHasNoErrorAndAgainstItsRefinementSome) {
  const cws::Scene s = cws::loadScene(
      kDefault, {"solver.integrator=bdf2", "process.core_speed_rpm=1200", "process.duration=0.03"});
  cws::Simulation a(s), b(s);
  a.run();
  b.run();
  const cws::ErrorEstimate same = cws::compareWithRefined(a, b, "none");
  EXPECT_EQ(same.shape_error_rel_diameter, 0.0);
  EXPECT_EQ(same.scale, 4.0 / 3.0);
  std::string what;
  cws::Simulation fine(cws::refinedScene(s, what));
  fine.run();
  const cws::ErrorEstimate e = cws::compareWithRefined(a, fine, what);
  std::printf("bdf2 1e-4 against 2.5e-5 at t = 0.03 s (x 4/3): shape %.3g d, bulging %.3g\n",
              e.shape_error_rel_diameter, e.bulging_error_rel);
  // The wound wire is wound: both runs agree to a few percent of d, and they
  // are not the same run.
  EXPECT_GT(e.shape_error_rel_diameter, 0.0);
  EXPECT_LT(e.shape_error_rel_diameter, 0.1);
  ASSERT_TRUE(e.bulging_valid);
  EXPECT_LT(e.bulging_error_rel, 0.1);
}
#endif

TEST(ImplicitSteps, FollowTheCoreRevolution) {
  // 500 steps per revolution at the core's speed, at most
  // solver.implicit_step: 4e-4 s at 300 rpm (a revolution over 500 is
  // 4e-4 s too) and at 100 rpm (the bound), 2e-4 s at 600 rpm, 1e-4 s at
  // 1200 rpm, 4e-5 s at 3,000 rpm; with steps_per_revolution 0 the bound
  // alone. The core is at speed from t = 0 (reached within 1 ns: the first
  // step ends there), and the steps grow from 1/64 of the longest.
  struct Case {
    double rpm, per_revolution, bound, expected;
  };
  for (const Case& c :
       {Case{300, 500, 4e-4, 4e-4}, Case{100, 500, 4e-4, 4e-4}, Case{600, 500, 4e-4, 2e-4},
        Case{1200, 500, 4e-4, 1e-4}, Case{3000, 500, 4e-4, 4e-5}, Case{1200, 0, 2e-4, 2e-4}}) {
    cws::Simulation sim(cws::loadScene(
        kDefault, {"solver.integrator=bdf2", "core.start_at_speed=true", "solver.strike_step=0",
                   "process.core_speed_rpm=" + std::to_string(c.rpm),
                   "solver.steps_per_revolution=" + std::to_string(c.per_revolution),
                   "solver.implicit_step=" + std::to_string(c.bound), "process.duration=0.01"}));
    const std::string what = std::to_string(c.rpm) + " rpm, " + std::to_string(c.per_revolution) +
                             " steps per revolution";
    sim.step(sim.endTime());
    EXPECT_LE(sim.time(), 1e-8) << what;
    sim.step(sim.endTime());
    EXPECT_NEAR(sim.stepper().lastStep(), c.expected / 64.0, 1e-12 * c.expected) << what;
    while (sim.time() < 0.005) sim.step(sim.endTime());
    EXPECT_DOUBLE_EQ(sim.stepper().lastStep(), c.expected) << what;
  }
  // A new speed setpoint: the step after it is 1/64 of the new speed's
  // (the core ramps towards it), and the steps grow to it.
  cws::Simulation sim(cws::loadScene(
      kDefault, {"solver.integrator=bdf2", "core.start_at_speed=true", "solver.strike_step=0",
                 "process.core_speed_rpm=300", "solver.steps_per_revolution=500",
                 "solver.implicit_step=4e-4", "process.duration=0.05"}));
  while (sim.time() < 0.005) sim.step(sim.endTime());
  EXPECT_DOUBLE_EQ(sim.stepper().lastStep(), 4e-4);
  sim.apply(cws::Setpoint::coreSpeed(3000.0 * 2.0 * kPi / 60.0));
  sim.step(sim.endTime());
  EXPECT_NEAR(sim.stepper().lastStep(), 4e-5 / 64.0, 1e-15);
  while (sim.time() < 0.03) sim.step(sim.endTime());
  EXPECT_DOUBLE_EQ(sim.stepper().lastStep(), 4e-5);
}
