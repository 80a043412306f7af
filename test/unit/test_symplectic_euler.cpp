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
