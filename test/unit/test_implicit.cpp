// The implicit planar steppers against closed forms: the same static
// deflections as test_statics.cpp (axial FL/EA, cantilever PL^3/(3EI), a tip
// moment rolling the wire into an arc of radius EI/M), reached with steps
// of 1e-4 s, hundreds of times the explicit stability limit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "wire_test_support.hpp"

using cws_test::cantilever;
using cws_test::rampedStatic;
using cws_test::settle;

namespace {
constexpr double kL = 0.1;  // wire length [m]

cws::Scene implicitScene(cws::Scene s, const char* integrator) {
  s.physics.planar = true;
  s.physics.torsion = false;
  s.solver.integrator = integrator;
  s.solver.implicit_step = 1e-4;
  return s;
}

class Implicit : public ::testing::TestWithParam<const char*> {};
}  // namespace

TEST_P(Implicit, AxialStretchMatchesFLoverEA) {
  cws::Scene s = implicitScene(
      rampedStatic(cantilever(kL, 10), {10.0, 0.0, 0.0}, {0, 0, 0}, 0.02, 0.06), GetParam());
  const cws::Simulation sim = settle(s);
  const double expected = 10.0 * kL / s.wire.stretch.elastic_rigidity;
  const double actual = cws_test::tipPosition(sim).x() - kL;
  std::printf("%s axial: extension %.6e m, closed form %.6e m, rel. error %.2e, %ld steps\n",
              GetParam(), actual, expected, actual / expected - 1.0,
              sim.stepper().counts().accepted);
  EXPECT_NEAR(actual / expected, 1.0, 1e-4);
  EXPECT_NEAR(sim.model().axialForce(0), 10.0, 1e-3);
}

TEST_P(Implicit, CantileverTipForceMatchesPL3over3EI) {
  const double force = 9.18e-3;  // [N]: 1 % of L, below yield (as in test_statics)
  const double ei = cws::Scene().wire.bend.elastic_rigidity;
  const double expected = force * kL * kL * kL / (3.0 * ei);
  cws::Scene s = implicitScene(
      rampedStatic(cantilever(kL, 20), {0.0, force, 0.0}, {0, 0, 0}, 0.02, 0.08), GetParam());
  const cws::Simulation sim = settle(s);
  const double error = std::abs(cws_test::tipPosition(sim).y() / expected - 1.0);
  std::printf("%s cantilever: tip deflection rel. error %.3e\n", GetParam(), error);
  // The explicit steppers reach 2e-3 at 21 points (discretization error).
  EXPECT_LT(error, 2e-3);
}

TEST_P(Implicit, TipMomentRollsTheWireIntoAnArc) {
  const double ei = cws::Scene().wire.bend.elastic_rigidity;
  const double moment = ei / kL;
  cws::Scene s = cantilever(kL, 20);
  s.physics.plasticity = false;
  s = implicitScene(rampedStatic(s, {0, 0, 0}, {0.0, 0.0, moment}, 0.02, 0.08), GetParam());
  const cws::Simulation sim = settle(s);
  const double r = ei / moment;
  const Eigen::Vector3d expected(r * std::sin(kL / r), r * (1.0 - std::cos(kL / r)), 0.0);
  const double error = (cws_test::tipPosition(sim) - expected).norm() / kL;
  const double angle_error = cws_test::tipFrameAngle(sim) - (kL - 0.5 * kL / 20) / r;
  std::printf("%s arc: tip position error %.3e L, last-frame angle error %.3e rad\n", GetParam(),
              error, angle_error);
  EXPECT_LT(error, 2e-4);
  EXPECT_NEAR(angle_error, 0.0, 2e-3);
}

INSTANTIATE_TEST_SUITE_P(Steppers, Implicit, ::testing::Values("implicit_euler", "bdf2"));
