// Dynamics: the first cantilever vibration frequency against Euler-Bernoulli
// beam theory, and the constraint residuals over a long 3-D dynamic run.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "wire_test_support.hpp"

using cws_test::cantilever;

namespace {
constexpr double kL = 0.1;  // [m]
constexpr double kPi = 3.14159265358979323846;

// Runs a wire released straight in gravity (its static sag has nearly the
// first mode's shape) without damping, and measures the period of the tip's
// vertical oscillation from successive downward crossings of its mean.
double measuredFirstPeriod(int segments, int periods) {
  cws::Scene s = cantilever(kL, segments);
  s.physics.gravity = true;
  s.physics.plasticity = false;
  const double rho = s.wire.line_density, ei = s.wire.bend.elastic_rigidity;
  const double omega1 = 1.8751 * 1.8751 * std::sqrt(ei / (rho * std::pow(kL, 4)));
  const double period = 2.0 * kPi / omega1;
  s.process.duration = (periods + 0.6) * period;
  cws::Simulation sim(s);
  // Static sag w L^4 / (8 EI) is the centre of the oscillation.
  const double mean_z = -rho * 9.81 * std::pow(kL, 4) / (8.0 * ei);
  std::vector<double> crossings;
  double t_prev = 0.0, z_prev = 0.0;
  while (sim.time() < sim.endTime()) {
    sim.step(sim.endTime());
    const double z = cws_test::tipPosition(sim).z() - mean_z;
    if (z_prev > 0.0 && z <= 0.0) {
      crossings.push_back(t_prev + (sim.time() - t_prev) * z_prev / (z_prev - z));
    }
    t_prev = sim.time();
    z_prev = z;
  }
  EXPECT_GE(static_cast<int>(crossings.size()), periods);
  if (crossings.size() < 2) return 0.0;
  return (crossings.back() - crossings.front()) / (crossings.size() - 1);
}
}  // namespace

TEST(Dynamics, FirstCantileverFrequencyConverges) {
  const cws::Scene s;
  const double omega1 =
      1.8751 * 1.8751 *
      std::sqrt(s.wire.bend.elastic_rigidity / (s.wire.line_density * std::pow(kL, 4)));
  double previous_error = 1.0;
  for (int segments : {5, 10, 20}) {
    const double period = measuredFirstPeriod(segments, 3);
    const double omega = 2.0 * kPi / period;
    const double error = std::abs(omega / omega1 - 1.0);
    std::printf(
        "vibration: %d points, omega1 %.2f rad/s, closed form %.2f rad/s, rel. error %.3e\n",
        segments + 1, omega, omega1, error);
    EXPECT_LT(error, previous_error);
    previous_error = error;
  }
  EXPECT_LT(previous_error, 0.03);
}

TEST(Dynamics, ConstraintResidualsStayBoundedOverALongRun) {
  // A 3-D run: gravity, a tip force and a skew tip moment that bend and twist
  // the wire plastically and then let go, 0.15 s (about 6 first-mode periods).
  cws::Scene s = cantilever(kL, 10);
  s.physics.gravity = true;
  cws::LoadKeyframe a, b, c;
  b.time = 0.03;
  b.force_world = {0.0, 0.05, 0.02};
  b.moment_world = {0.01, 0.004, -0.006};
  c.time = 0.06;
  s.end.load = {a, b, c};
  s.process.duration = 0.15;
  cws::Simulation sim(s);
  double worst = 0.0;
  while (sim.time() < sim.endTime()) {
    sim.step(sim.endTime());
    worst = std::max(worst, sim.model().maxConstraintResidual());
  }
  std::printf("constraints: largest residual %.3e over %ld steps\n", worst,
              sim.stepper().counts().accepted);
  // Stated bound: |q|^2 - 1 and the sine of the frame-segment misalignment
  // stay below 1e-8 (their Baumgarte-stabilized drift is set by the local
  // integration error, atol / l = 1e-9 here).
  EXPECT_LT(worst, 1e-8);
  EXPECT_EQ(worst, sim.maxConstraintResidual());
  EXPECT_GT(sim.energy().plastic, 0.0) << "the run was meant to yield";
}
