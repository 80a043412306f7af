// Scenes and helpers shared by the physics tests.
#pragma once

#include <gtest/gtest.h>

#include "coil_winding_sim/core/base/quaternion.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"

namespace cws_test {

// The refinement a Newton-step method's error estimate reports.
inline constexpr const char* kQuarterStep =
    "a quarter of the step (solver.implicit_step and solver.strike_step / 4, "
    "solver.steps_per_revolution x 4), the difference x 4/3";

// A Table-1 wire of length L [m] in `segments` equal segments, clamped at the
// origin along +x, no gravity, no damping, no end load.
inline cws::Scene cantilever(double length, int segments) {
  cws::Scene s;
  s.wire.length = length;
  s.wire.segment_length = length / segments;
  s.physics.gravity = false;
  s.physics.damping = false;
  s.end.load = {cws::LoadKeyframe{}};
  s.solver.rtol = 1e-6;
  s.solver.atol = 1e-11;
  return s;
}

// Quasi-static loading: the end load ramps from zero to (force, moment) over
// t_ramp and holds until t_end; viscous damping near critical for the first
// bending mode of a 0.1 m wire lets the motion die out.
inline cws::Scene rampedStatic(cws::Scene s, const Eigen::Vector3d& force_world,
                               const Eigen::Vector3d& moment_world, double t_ramp, double t_end) {
  s.physics.damping = true;
  s.damping.translational = 4.0;  // [N s/m^2]
  s.damping.rotational = 1.0e-6;  // [N m s/m]
  cws::LoadKeyframe a, b;
  b.time = t_ramp;
  b.force_world = force_world;
  b.moment_world = moment_world;
  s.end.load = {a, b};
  s.process.duration = t_end;
  return s;
}

// Undamped and elastic: a tip force and moment ramp up in 2 ms and oscillate
// a 0.1 m wire in gravity for 30 ms; nothing dissipates.
inline cws::Scene elasticOscillation() {
  cws::Scene s = cantilever(0.1, 10);
  s.physics.plasticity = false;
  s.physics.gravity = true;
  cws::LoadKeyframe a, b;
  b.time = 0.002;
  b.force_world = {1.0, 0.02, 0.0};
  b.moment_world = {0.002, 0.0, 0.001};
  s.end.load = {a, b};
  s.process.duration = 0.03;
  return s;
}

// Runs a quasi-static scene to its end and checks the wire came to rest
// (kinetic energy below 1e-5 of the stored elastic energy).
inline cws::Simulation settle(const cws::Scene& s) {
  cws::Simulation sim(s);
  sim.run();
  const cws::EnergyReport e = sim.energy();
  EXPECT_LT(e.kinetic, 1e-5 * e.elastic) << "the wire did not come to rest";
  return sim;
}

inline Eigen::Vector3d tipPosition(const cws::Simulation& sim) {
  return sim.model().committed().p_world.col(sim.model().constants().n - 1);
}

// Rotation angle between the clamp frame and the last frame [rad].
inline double tipFrameAngle(const cws::Simulation& sim) {
  const auto& k = sim.model().committed();
  return cws::quat::relativeAngle(k.q.col(0), k.q.col(sim.model().constants().n - 1));
}

}  // namespace cws_test
