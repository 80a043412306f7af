// Viscous damping (physics.damping) against the closed form of a body
// falling through a fluid with linear drag c per length: from rest, v(t) =
// -v_t (1 - exp(-t / tau)) and the fall z(t) = -v_t (t - tau (1 - exp(-t /
// tau))), with tau = rho / c and the terminal speed v_t = rho g / c. As in
// test_air_drag.cpp, the far part of a horizontal wire held at one end falls
// freely within the run (10 ms: the clamp's bending waves reach about 0.15
// m; at 20 ms their ripples moved the far part's speed by 0.25 %). The law is written once on the
// force sink; this checks it through the explicit model and both Newton formulations (their
// Jacobian blocks: PlanarJacobian.* and SpatialJacobian.* with damping on).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "wire_test_support.hpp"

namespace {

struct Case {
  const char* integrator;
  bool planar;
};

class DampedFall : public ::testing::TestWithParam<Case> {};

TEST_P(DampedFall, FarWireFallsAtTheClosedFormsSpeedAndDepth) {
  const Case k = GetParam();
  cws::Scene s = cws_test::fallingWire(k.integrator, k.planar);
  s.physics.damping = true;
  s.damping.translational = 2.8;  // tau = 2.5 ms
  s.damping.rotational = 1e-7;    // (on the frames: little on a falling wire)
  s.process.duration = 0.01;
  cws::Simulation sim(s);
  sim.run();

  const double g = 9.81;
  const double rho = s.wire.line_density;
  const double tau = rho / s.damping.translational;
  const double vt = rho * g / s.damping.translational;
  const double t = sim.time();
  const double v_closed = -vt * (1.0 - std::exp(-t / tau));
  const double z_closed = -vt * (t - tau * (1.0 - std::exp(-t / tau)));
  // The far part: 0.6 m from the clamp to the free end.
  const cws_test::FarPart far = cws_test::farPart(sim, 0.6);
  ASSERT_GT(far.count, 10);
  const double v = far.v, z = far.z;
  std::printf(
      "%s%s: t %.4f s, v_t %.5f m/s; v %.6f m/s (closed form %.6f, rel. %.2e), "
      "z %.6f m (closed form %.6f, rel. %.2e)\n",
      k.integrator, k.planar ? " planar" : "", t, vt, v, v_closed, v / v_closed - 1.0, z, z_closed,
      z / z_closed - 1.0);
  EXPECT_NEAR(t, 0.01, 1e-9);
  EXPECT_NEAR(v / v_closed, 1.0, 2e-3);
  EXPECT_NEAR(z / z_closed, 1.0, 2e-3);
  // Damping has dissipated most of the work of gravity by now (t = 4 tau).
  const cws::EnergyReport e = sim.energy();
  EXPECT_GT(e.viscous, 0.5 * e.work_done);
}

INSTANTIATE_TEST_SUITE_P(Formulations, DampedFall,
                         ::testing::Values(Case{"rkf45", false}, Case{"bdf2", true},
                                           Case{"bdf2", false}),
                         [](const ::testing::TestParamInfo<Case>& i) {
                           return std::string(i.param.integrator) +
                                  (i.param.planar ? "_planar" : "_3d");
                         });

}  // namespace
