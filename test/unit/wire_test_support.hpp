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

// A horizontal wire 1 m long held at one end, falling in the plane x-z
// (gravity on, elastic laws), with `integrator` in the plane or in 3-D: its
// part beyond the clamp's reach falls freely for the first tens of
// milliseconds (test_air_drag.cpp, test_damping.cpp).
inline cws::Scene fallingWire(const char* integrator, bool planar) {
  cws::Scene s = cantilever(1.0, 200);
  s.physics.gravity = true;
  s.physics.torsion = !planar;
  s.physics.planar = planar;
  s.physics.plasticity = false;         // (a yielding root would turn the wire about it)
  s.core.axis_world = {0.0, 1.0, 0.0};  // the plane x-z holds the fall
  s.solver.integrator = integrator;
  s.solver.implicit_step = 1e-4;
  return s;
}

// The mean downward velocity [m/s] and height [m] of the points at
// x >= from_x [m] at the last accepted step, and how many they are.
struct FarPart {
  double v = 0.0, z = 0.0;
  int count = 0;
};
inline FarPart farPart(const cws::Simulation& sim, double from_x) {
  FarPart f;
  for (int i = 0; i < sim.model().constants().n; ++i) {
    const cws::PointReport r = cws::wirePoint(sim.model(), i);
    if (r.p_world.x() < from_x) continue;
    f.v += sim.model().committed().v_world(2, i);
    f.z += r.p_world.z();
    ++f.count;
  }
  if (f.count > 0) {
    f.v /= f.count;
    f.z /= f.count;
  }
  return f;
}

}  // namespace cws_test
