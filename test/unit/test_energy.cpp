// Energy balance: kinetic + elastic + dissipated = work done by the applied
// loads and gravity, in an elastic and in a plastic run. Each side is
// computed independently: kinetic and elastic from the state, plastic work
// from the hysteresis loops, viscous dissipation and external work integrated
// from their power along the trajectory.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "wire_test_support.hpp"

using cws_test::cantilever;

namespace {
// Relative imbalance |KE + U + D - W| / max(W, KE + U + D).
double relativeImbalance(const cws::EnergyReport& e) {
  const double scale = std::max(std::abs(e.work_done), e.kinetic + e.elastic + e.dissipated());
  return std::abs(e.imbalance()) / scale;
}
}  // namespace

TEST(Energy, BalanceHoldsInAnElasticRun) {
  const cws::Scene s = cws_test::elasticOscillation();
  cws::Simulation sim(s);
  sim.run();
  const cws::EnergyReport e = sim.energy();
  std::printf("elastic run: W %.6e J, KE %.6e J, U %.6e J, D %.3e J, rel. imbalance %.3e\n",
              e.work_done, e.kinetic, e.elastic, e.dissipated(), relativeImbalance(e));
  EXPECT_GT(e.work_done, 1e-6);
  EXPECT_EQ(e.plastic, 0.0);
  EXPECT_LT(relativeImbalance(e), 1e-5);
}

TEST(Energy, BalanceHoldsInAPlasticDampedRun) {
  // The package's default scene in spirit: a tip force bends the root past
  // yield, is released, and damping settles the spring-back.
  cws::Scene s = cantilever(0.05, 25);
  s.physics.gravity = true;
  s.physics.damping = true;
  s.damping.translational = 2.0;
  s.damping.rotational = 1e-6;
  cws::LoadKeyframe a, b, c, d;
  b.time = 0.01;
  b.force_world = {0.0, 0.15, 0.0};
  c.time = 0.02;
  c.force_world = b.force_world;
  d.time = 0.025;
  s.end.load = {a, b, c, d};
  s.process.duration = 0.04;
  cws::Simulation sim(s);
  sim.run();
  const cws::EnergyReport e = sim.energy();
  std::printf(
      "plastic run: W %.6e J, KE %.6e J, U %.6e J, plastic %.6e J, viscous %.6e J, "
      "rel. imbalance %.3e\n",
      e.work_done, e.kinetic, e.elastic, e.plastic, e.viscous, relativeImbalance(e));
  EXPECT_GT(e.plastic, 0.1 * e.work_done) << "the run was meant to yield";
  EXPECT_GT(e.viscous, 0.0);
  EXPECT_LT(relativeImbalance(e), 1e-5);
  // A permanent bend remains at the root after release.
  EXPECT_GT(cws::wirePoint(sim.model(), 0).plastic_curvature_1pm, s.wire.bend.yield);
}
