// The Newton-step methods against closed forms: the same static deflections
// as test_statics.cpp (axial FL/EA, cantilever PL^3/(3EI), a tip moment
// rolling the wire into an arc of radius EI/M, torsion TL/GJ), reached with
// steps of 1e-4 s, hundreds of times the explicit stability limit, in the
// planar formulation and in the 3-D one.
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

namespace {
// The 3-D formulation: positions and quaternions with the frame
// constraints, torsion on.
cws::Scene spatialScene(cws::Scene s, const char* integrator) {
  s.physics.planar = false;
  s.physics.torsion = true;
  s.solver.integrator = integrator;
  s.solver.implicit_step = 1e-4;
  return s;
}

class Implicit3d : public ::testing::TestWithParam<const char*> {};
}  // namespace

TEST_P(Implicit3d, AxialStretchMatchesFLoverEA) {
  cws::Scene s = spatialScene(
      rampedStatic(cantilever(kL, 10), {10.0, 0.0, 0.0}, {0, 0, 0}, 0.02, 0.06), GetParam());
  const cws::Simulation sim = settle(s);
  const double expected = 10.0 * kL / s.wire.stretch.elastic_rigidity;
  const double actual = cws_test::tipPosition(sim).x() - kL;
  std::printf("%s 3-D axial: rel. error %.2e\n", GetParam(), actual / expected - 1.0);
  EXPECT_NEAR(actual / expected, 1.0, 1e-4);
}

TEST_P(Implicit3d, TipMomentOutOfTheXYPlaneRollsAnArc) {
  // A moment about -y bends the wire (along +x) up into the x-z plane.
  const double ei = cws::Scene().wire.bend.elastic_rigidity;
  const double moment = ei / kL;
  cws::Scene s = cantilever(kL, 20);
  s.physics.plasticity = false;
  s = spatialScene(rampedStatic(s, {0, 0, 0}, {0.0, -moment, 0.0}, 0.02, 0.08), GetParam());
  const cws::Simulation sim = settle(s);
  const double r = ei / moment;
  const Eigen::Vector3d expected(r * std::sin(kL / r), 0.0, r * (1.0 - std::cos(kL / r)));
  const double error = (cws_test::tipPosition(sim) - expected).norm() / kL;
  const double angle_error = cws_test::tipFrameAngle(sim) - (kL - 0.5 * kL / 20) / r;
  std::printf("%s 3-D arc: tip position error %.3e L, last-frame angle error %.3e rad\n",
              GetParam(), error, angle_error);
  EXPECT_LT(error, 2e-4);
  EXPECT_NEAR(angle_error, 0.0, 2e-3);
}

TEST_P(Implicit3d, TorsionMatchesTLoverGJ) {
  cws::Scene s = cantilever(kL, 10);
  s.physics.plasticity = false;
  const double gj = s.wire.torsion.elastic_rigidity;
  const double torque = 0.5 * gj / kL;
  s = spatialScene(rampedStatic(s, {0, 0, 0}, {torque, 0.0, 0.0}, 0.02, 0.06), GetParam());
  // (Newton converged well below the 1e-9 m asked of the tip's position.)
  s.solver.newton_tol = 1e-10;
  const cws::Simulation sim = settle(s);
  const double expected = torque * (kL - 0.5 * kL / 10) / gj;
  const double twist = cws_test::tipFrameAngle(sim);
  std::printf("%s 3-D torsion: rel. error %.2e\n", GetParam(), twist / expected - 1.0);
  EXPECT_NEAR(twist / expected, 1.0, 1e-3);
  EXPECT_LT((cws_test::tipPosition(sim) - Eigen::Vector3d(kL, 0, 0)).norm(), 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Steppers, Implicit3d, ::testing::Values("implicit_euler", "bdf2"));
