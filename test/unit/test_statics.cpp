// Static deflections against Euler-Bernoulli / Saint-Venant closed forms
// (../shared/reference/wire-data.md): axial FL/EA, cantilever PL^3/(3EI),
// tip moment rolling the wire into an arc of radius EI/M, torsion TL/GJ.
// Loads are ramped and held with damping until the wire is at rest.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "wire_test_support.hpp"

using cws_test::cantilever;
using cws_test::rampedStatic;
using cws_test::settle;

namespace {
constexpr double kL = 0.1;  // wire length [m]
}  // namespace

TEST(Statics, AxialStretchMatchesFLoverEA) {
  // 10 N is below the axial yield force (EA * 8e-4 = 39 N): the two-line law
  // stays on its elastic line, plasticity switched on.
  cws::Scene s = rampedStatic(cantilever(kL, 10), {10.0, 0.0, 0.0}, {0, 0, 0}, 0.02, 0.06);
  const cws::Simulation sim = settle(s);
  const double expected = 10.0 * kL / s.wire.stretch.elastic_rigidity;
  const double actual = cws_test::tipPosition(sim).x() - kL;
  std::printf("axial: extension %.6e m, closed form %.6e m, rel. error %.2e\n", actual, expected,
              actual / expected - 1.0);
  EXPECT_NEAR(actual / expected, 1.0, 1e-4);
  EXPECT_NEAR(sim.model().axialForce(0), 10.0, 1e-3);
}

TEST(Statics, CantileverTipForceConvergesToPL3over3EI) {
  // Tip deflection of 1 % of the length: small-deflection theory holds to
  // about 1e-4; the root moment 9.2e-4 N m is below yield (4.9e-3 N m).
  const double force = 9.18e-3;  // [N]
  const double ei = cws::Scene().wire.bend.elastic_rigidity;
  const double expected = force * kL * kL * kL / (3.0 * ei);
  double previous_error = 1.0;
  for (int segments : {5, 10, 20}) {
    cws::Scene s = rampedStatic(cantilever(kL, segments), {0.0, force, 0.0}, {0, 0, 0}, 0.02, 0.08);
    const cws::Simulation sim = settle(s);
    const double error = std::abs(cws_test::tipPosition(sim).y() / expected - 1.0);
    std::printf("cantilever: %d points, tip deflection rel. error %.3e (%.2f s wall)\n",
                segments + 1, error, sim.wallTime());
    EXPECT_LT(error, previous_error) << "error must fall as points are added";
    previous_error = error;
  }
  EXPECT_LT(previous_error, 2e-3);
}

TEST(Statics, TipMomentRollsTheWireIntoAnArc) {
  // M = EI / L * 1 rad: an arc of radius R = EI / M = L ending at 1 rad. The
  // discrete points lie on that circle; the last frame follows the chord of
  // the last segment, whose direction is the arc's at s = L - l/2.
  const double ei = cws::Scene().wire.bend.elastic_rigidity;
  const double moment = ei / kL;
  double previous_error = 1.0;
  for (int segments : {10, 20}) {
    cws::Scene s = cantilever(kL, segments);
    s.physics.plasticity = false;  // 1 rad over 0.1 m is far past yield curvature
    s = rampedStatic(s, {0, 0, 0}, {0.0, 0.0, moment}, 0.02, 0.08);
    const cws::Simulation sim = settle(s);
    const double r = ei / moment;
    const Eigen::Vector3d expected(r * std::sin(kL / r), r * (1.0 - std::cos(kL / r)), 0.0);
    const double error = (cws_test::tipPosition(sim) - expected).norm() / kL;
    const double l = kL / segments;
    const double angle_error = cws_test::tipFrameAngle(sim) - (kL - 0.5 * l) / r;
    std::printf("arc: %d points, tip position error %.3e L, last-frame angle error %.3e rad\n",
                segments + 1, error, angle_error);
    EXPECT_LT(error, previous_error);
    EXPECT_NEAR(angle_error, 0.0, 2e-3);
    previous_error = error;
  }
  EXPECT_LT(previous_error, 2e-4);
}

TEST(Statics, TorsionMatchesTLoverGJ) {
  // 0.5 rad of twist over 0.1 m (5 rad/m, past the yield twist): elastic law.
  cws::Scene s = cantilever(kL, 10);
  s.physics.plasticity = false;
  const double gj = s.wire.torsion.elastic_rigidity;
  const double torque = 0.5 * gj / kL;
  s = rampedStatic(s, {0, 0, 0}, {torque, 0.0, 0.0}, 0.02, 0.06);
  const cws::Simulation sim = settle(s);
  // The last frame belongs to the last segment, whose middle is at L - l/2:
  // closed form T (L - l/2) / GJ.
  const double expected = torque * (kL - 0.5 * kL / 10) / gj;
  const double twist = cws_test::tipFrameAngle(sim);
  std::printf("torsion: last-frame twist %.6f rad, closed form %.6f rad, rel. error %.2e\n", twist,
              expected, twist / expected - 1.0);
  EXPECT_NEAR(twist / expected, 1.0, 1e-3);
  // The axis stays straight: pure torsion bends nothing.
  EXPECT_LT((cws_test::tipPosition(sim) - Eigen::Vector3d(kL, 0, 0)).norm(), 1e-9);
}
