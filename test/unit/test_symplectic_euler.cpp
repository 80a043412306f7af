// The fixed-step semi-implicit (symplectic) Euler integrator: closed forms
// and energy as for RKF45, and a clear stop above its stability limit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "wire_test_support.hpp"

using cws_test::cantilever;

namespace {
cws::Scene withEuler(cws::Scene s, double h) {
  s.solver.integrator = "symplectic_euler";
  s.solver.fixed_step = h;
  return s;
}
}  // namespace

TEST(SymplecticEuler, CantileverTipForce) {
  const double force = 9.18e-3, length = 0.1;
  cws::Scene s =
      cws_test::rampedStatic(cantilever(length, 10), {0.0, force, 0.0}, {0, 0, 0}, 0.02, 0.08);
  cws::Simulation sim(withEuler(s, 1e-6));
  sim.run();
  cws::Simulation reference(s);  // RKF45, error-controlled
  reference.run();
  const double expected = force * std::pow(length, 3) / (3.0 * s.wire.bend.elastic_rigidity);
  const double error = cws_test::tipPosition(sim).y() / expected - 1.0;
  const double vs_rkf45 =
      (cws_test::tipPosition(sim).y() - cws_test::tipPosition(reference).y()) / expected;
  std::printf(
      "symplectic euler: cantilever n=11 rel. error %.3e against PL^3/3EI, %.1e against "
      "rkf45; %.2f s wall (rkf45 %.2f s)\n",
      error, vs_rkf45, sim.wallTime(), reference.wallTime());
  // The static answer is the model's, not the integrator's: the same
  // discretization error as with RKF45.
  EXPECT_LT(std::abs(error), 5e-3);
  EXPECT_LT(std::abs(vs_rkf45), 1e-4);
}

TEST(SymplecticEuler, EnergyStaysBalancedInAnElasticRun) {
  const cws::Scene s = cws_test::elasticOscillation();
  cws::Simulation sim(withEuler(s, 1e-6));
  sim.run();
  const cws::EnergyReport e = sim.energy();
  const double rel = std::abs(e.imbalance()) / e.work_done;
  std::printf("symplectic euler: elastic run rel. energy imbalance %.3e (h = 1 us)\n", rel);
  // First order: O(h) energy error, bounded (symplectic), stated bound 1e-3.
  EXPECT_LT(rel, 1e-3);
}

TEST(SymplecticEuler, AboveTheStabilityLimitItIsRefused) {
  // Segments of 2 mm: axial waves (c = sqrt(EA / rho) = 2639 m/s) cross one
  // in 7.58e-7 s, the explicit limit. Just above it the scene is refused
  // with a message naming the key and the limit; just below it runs.
  cws::Scene s = cantilever(0.05, 25);
  s.end.load = {cws::LoadKeyframe{0.0, {0.0, 0.1, 0.0}, {0, 0, 0}}};
  s.process.duration = 1e-4;
  s.physics.torsion = false;
  const double limit = 2e-3 / std::sqrt(s.wire.stretch.elastic_rigidity / s.wire.line_density);
  try {
    cws::Simulation sim(withEuler(s, 1.01 * limit));
    FAIL() << "expected a SceneError";
  } catch (const cws::SceneError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(e.key(), "solver.fixed_step");
    EXPECT_NE(msg.find("stability limit"), std::string::npos) << msg;
    std::printf("symplectic euler: refused above l/c = %.3e s: %s\n", limit, msg.c_str());
  }
  cws::Simulation below(withEuler(s, 0.5 * limit));
  below.run();
  EXPECT_TRUE(std::isfinite(cws_test::tipPosition(below).norm()));
}

TEST(SymplecticEuler, AutoStepFollowsAStifferWire) {
  // solver.fixed_step: auto (the default scene's) is a quarter of l / c for
  // whatever wire the scene has: a wire 100 times stiffer in tension
  // (c = sqrt(EA / rho) ten times higher) is not refused for a step its
  // user never set, and its step is l / (4 c) from the closed form.
  const std::string path = std::string(CWS_SOURCE_DIR) + "/config/scenes/default.yaml";
  const std::vector<std::string> stiff = {"solver.integrator=symplectic_euler",
                                          "wire.stretch.elastic_rigidity=4.89e6",
                                          "physics.torsion=false", "process.duration=2e-5"};
  cws::Scene s = cws::loadScene(path, stiff);
  EXPECT_FALSE(s.solver.fixed_step.has_value());
  const double c = std::sqrt(4.89e6 / 7.02e-3);  // [m/s]
  EXPECT_NEAR(cws::fixedStep(s), 0.25 * 1.0e-3 / c, 1e-12 * 1.0e-3 / c);
  cws::Simulation sim(s);
  sim.run();
  EXPECT_NEAR(sim.time(), 2e-5, 1e-15);
  EXPECT_TRUE(std::isfinite(sim.model().maxConstraintResidual()));
  // The same wire with the step the default scene used to name (1e-7 s,
  // above its l / c of 3.8e-8 s) is refused, naming the key.
  std::vector<std::string> fixed = stiff;
  fixed.push_back("solver.fixed_step=1e-7");
  try {
    cws::loadScene(path, fixed);
    FAIL() << "expected a SceneError";
  } catch (const cws::SceneError& e) {
    EXPECT_EQ(e.key(), "solver.fixed_step");
  }
}

TEST(SymplecticEuler, AutoIsAWordOfTheSceneFile) {
  // `auto` reads as unset and is printed back as `auto`; another word is
  // refused naming both choices.
  cws::Scene s = cws::loadScene("", {"solver.fixed_step=auto"});
  EXPECT_FALSE(s.solver.fixed_step.has_value());
  EXPECT_NE(cws::sceneToYamlText(s).find("fixed_step: auto"), std::string::npos);
  s = cws::loadScene("", {"solver.fixed_step=2e-7"});
  ASSERT_TRUE(s.solver.fixed_step.has_value());
  EXPECT_DOUBLE_EQ(*s.solver.fixed_step, 2e-7);
  EXPECT_DOUBLE_EQ(cws::fixedStep(s), 2e-7);
  try {
    cws::loadScene("", {"solver.fixed_step=fast"});
    FAIL() << "expected a SceneError";
  } catch (const cws::SceneError& e) {
    EXPECT_EQ(e.key(), "solver.fixed_step");
    EXPECT_NE(std::string(e.what()).find("a number or 'auto'"), std::string::npos) << e.what();
  }
}
