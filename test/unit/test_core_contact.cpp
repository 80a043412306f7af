// The rotating core's kinematics and frictionless contact, against closed
// forms: constant-acceleration ramps, rigid-body velocities, and the tip
// reaction of a propped cantilever (Euler-Bernoulli superposition).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "wire_test_support.hpp"

namespace {
constexpr double kPi = 3.14159265358979323846;
}

TEST(RotatingCore, SpeedRampFollowsTheAccelerationLimit) {
  cws::CoreParams p;
  p.max_angular_acceleration = 100.0;  // [rad/s^2]
  p.start_at_speed = false;
  cws::RotatingCore core(p, 50.0);
  // Ramp for 0.5 s, then constant speed: angle = a t^2 / 2, then w (t - 0.25).
  EXPECT_NEAR(core.omega(0.2), 20.0, 1e-12);
  EXPECT_NEAR(core.angle(0.2), 0.5 * 100.0 * 0.04, 1e-12);
  EXPECT_NEAR(core.omega(1.0), 50.0, 1e-12);
  EXPECT_NEAR(core.angle(1.0), 50.0 * (1.0 - 0.25), 1e-12);
  EXPECT_EQ(core.angularAcceleration(0.3), 100.0);
  EXPECT_EQ(core.angularAcceleration(0.6), 0.0);
  // A commit mid-ramp and a new, lower command: decelerate from there.
  core.commit(0.2);
  core.setCommand(-10.0);  // 30 rad/s below: 0.3 s at -100 rad/s^2
  EXPECT_NEAR(core.omega(0.4), 0.0, 1e-12);
  EXPECT_NEAR(core.omega(0.6), -10.0, 1e-12);
  const double angle_at_05 = 2.0 + 20.0 * 0.3 - 0.5 * 100.0 * 0.09;
  EXPECT_NEAR(core.angle(0.5), angle_at_05, 1e-12);
  EXPECT_NEAR(core.angle(0.7), angle_at_05 - 10.0 * 0.2, 1e-12);
}

// core.start_at_speed: at rest at t = 0, at speed after the instant ramp,
// which ends a step (rampEnd) and gives way to the acceleration limit.
TEST(RotatingCore, InstantStartReachesSpeedWithinItsRamp) {
  cws::CoreParams p;
  p.start_at_speed = true;
  p.max_angular_acceleration = 100.0;  // [rad/s^2]
  cws::RotatingCore core(p, 50.0);
  const double ramp = cws::RotatingCore::kInstantRamp_s;
  EXPECT_EQ(core.omega(0.0), 0.0);
  EXPECT_NEAR(core.omega(0.5 * ramp), 25.0, 1e-6);
  EXPECT_DOUBLE_EQ(core.rampEnd(), ramp);
  EXPECT_EQ(core.omega(ramp), 50.0);
  EXPECT_NEAR(core.angle(1.0), 50.0 * (1.0 - 0.5 * ramp), 1e-12);
  core.commit(ramp);
  EXPECT_EQ(core.rampEnd(), std::numeric_limits<double>::infinity());
  // Later commands ramp at the machine's limit.
  core.setCommand(0.0);
  EXPECT_NEAR(core.rampEnd(), ramp + 0.5, 1e-12);
}

TEST(RotatingCore, MaterialPointsMoveRigidly) {
  cws::CoreParams p;
  p.position_world = {0.01, -0.02, 0.03};
  p.axis_world = {0.0, 0.0, 2.0};
  p.start_at_speed = true;
  cws::RotatingCore core(p, 2.0 * kPi * 10.0);  // 600 rpm
  const Eigen::Vector3d p_core(0.004, 0.003, 0.001);
  // A quarter turn takes 25 ms (after the instant start, which lags the
  // angle by half its duration); the radius stays 5 mm and z is kept.
  const double lag = 0.5 * cws::RotatingCore::kInstantRamp_s;
  const Eigen::Vector3d a = core.pointWorld(0.0, p_core) - p.position_world;
  const Eigen::Vector3d b = core.pointWorld(0.025 + lag, p_core) - p.position_world;
  EXPECT_NEAR(a.head<2>().norm(), 0.005, 1e-15);
  EXPECT_NEAR(a.head<2>().dot(b.head<2>()), 0.0, 1e-15);
  EXPECT_NEAR(a.head<2>().x() * b.head<2>().y() - a.head<2>().y() * b.head<2>().x(), 2.5e-5,
              1e-15);  // counter-clockwise
  EXPECT_NEAR(a.z(), b.z(), 1e-15);
  // Velocity by finite difference of the motion.
  const double t = 0.013, dt = 1e-7;
  const Eigen::Vector3d x = core.pointWorld(t, p_core);
  const Eigen::Vector3d fd =
      (core.pointWorld(t + dt, p_core) - core.pointWorld(t - dt, p_core)) / (2 * dt);
  EXPECT_LT((core.velocityWorld(t, x) - fd).norm(), 1e-8);
  EXPECT_LT((core.pointCore(t, x) - p_core).norm(), 1e-15);
  // Quaternion and matrix agree.
  EXPECT_LT((core.quaternionWorldCore(t).toRotationMatrix() - core.rotationWorldCore(t)).norm(),
            1e-14);
}

namespace {
// A horizontal wire clamped at the origin along +x, sagging in gravity, its
// tip resting on a still core surface whose top is at the clamp's height:
// a cylinder (axis along y) or a flat face. Beam theory: a load P at
// distance a from the clamp of a cantilever propped at its tip L gives the
// prop reaction P a^2 (3L - a) / (2 L^3); summed over the point weights M g
// (eq. 1 masses). Returns the relative error of the measured reaction.
double proppedCantileverError(bool face) {
  const double length = 0.1, radius = 0.01;
  const int segments = 10;
  cws::Scene s = cws_test::cantilever(length, segments);
  s.physics.gravity = true;
  s.physics.plasticity = false;
  s.physics.contact = true;
  s.physics.damping = true;
  s.damping.translational = 4.0;
  s.damping.rotational = 1e-6;
  s.process.core_speed_rpm = 0.0;
  s.process.duration = 0.08;
  const double r_wire = 0.5 * s.wire.diameter;
  s.core.axis_world = {0.0, 1.0, 0.0};  // core x = world x, core y = world -z
  if (face) {
    s.core.position_world = {length, 0.0, 0.0};
    s.core.faces = {cws::FaceParams{{-5e-3, r_wire}, {5e-3, r_wire}}};  // top at z = -r
  } else {
    s.core.position_world = {length, 0.0, -(radius + r_wire)};
    s.core.cylinders = {cws::CylinderParams{{0.0, 0.0}, radius}};
  }
  cws::Simulation sim(s);
  sim.run();

  const double m_point = s.wire.line_density * length / (segments + 1);
  double expected = 0.0;
  for (int i = 1; i <= segments; ++i) {
    const double a = i * length / segments;
    expected += m_point * 9.81 * a * a * (3 * length - a) / (2 * std::pow(length, 3));
  }
  // The reaction from the tip's penetration, measured from the geometry.
  const Eigen::Vector3d tip = cws_test::tipPosition(sim);
  const Eigen::Vector3d d = tip - s.core.position_world;
  const double h =
      face ? r_wire - (tip.z() + r_wire) : radius + r_wire - Eigen::Vector2d(d.x(), d.z()).norm();
  const double reaction = s.contact.stiffness * h;
  std::printf(
      "propped cantilever on a %s: tip reaction %.6e N, beam theory %.6e N, rel. error "
      "%.2e, penetration %.2e of the wire radius\n",
      face ? "face" : "cylinder", reaction, expected, reaction / expected - 1.0, h / r_wire);
  EXPECT_TRUE(cws::wirePoint(sim.model(), segments).in_contact);
  EXPECT_FALSE(cws::wirePoint(sim.model(), segments - 1).in_contact);
  EXPECT_LT(sim.model().contact()->maxPenetration(), 0.01 * r_wire);
  return reaction / expected - 1.0;
}
}  // namespace

TEST(Contact, ProppedCantileverTipReactionOnACylinder) {
  EXPECT_NEAR(proppedCantileverError(false), 0.0, 0.01);
}

TEST(Contact, ProppedCantileverTipReactionOnAFace) {
  EXPECT_NEAR(proppedCantileverError(true), 0.0, 0.01);
}

TEST(Contact, SceneNeedsACylinderAndShortSegments) {
  cws::Scene s = cws_test::cantilever(0.1, 10);
  s.physics.contact = true;
  try {
    cws::validateScene(s);
    FAIL() << "contact without cylinders must be refused";
  } catch (const cws::SceneError& e) {
    EXPECT_EQ(e.key(), "core.cylinders");
  }
  s.core.cylinders = {cws::CylinderParams{{0.0, 0.0}, 2.5e-3}};  // radius < l = 10 mm
  try {
    cws::validateScene(s);
    FAIL() << "segments longer than the cylinder radius must be refused";
  } catch (const cws::SceneError& e) {
    EXPECT_EQ(e.key(), "wire.segment_length");
  }
  s.physics.contact = false;
  s.physics.friction = true;
  EXPECT_THROW(cws::validateScene(s), cws::SceneError);
}

TEST(CoreClamp, SpinningWireCarriesCentrifugalTension) {
  // A wire clamped radially 5 mm off the axis of a core that spins up slowly
  // to omega turns with it; the axial force of segment 0 is the centrifugal
  // load of the points outside it, sum M omega^2 r_i (rigid-body rotation).
  const double length = 0.05, omega = 1000.0, r0 = 0.005;  // [m], [rad/s], [m]
  const int segments = 10;
  cws::Scene s = cws_test::cantilever(length, segments);
  s.physics.plasticity = false;
  s.start.frame = "core";
  s.start.position = {r0, 0.0, 0.0};
  s.core.start_at_speed = false;
  s.core.max_angular_acceleration = 2.0e4;  // 50 ms ramp
  s.process.max_core_speed_rpm = 20000.0;
  s.process.core_speed_rpm = omega * 60.0 / (2.0 * kPi);
  s.process.duration = 0.08;
  cws::Simulation sim(s);
  // Average the root force over the last 20 ms (after the ramp).
  // Also the tip's mean position in the core frame: the spin-up leaves a
  // bending oscillation, about the radial line.
  double sum = 0.0, weight = 0.0;
  Eigen::Vector3d tip_sum = Eigen::Vector3d::Zero();
  while (sim.time() < sim.endTime()) {
    sim.step(sim.endTime());
    if (sim.time() > 0.06) {
      const double dt = sim.stepper().lastStep();
      sum += sim.model().axialForce(0) * dt;
      tip_sum += dt * sim.model().core()->pointCore(sim.time(), cws_test::tipPosition(sim));
      weight += dt;
    }
  }
  const double m_point = s.wire.line_density * length / (segments + 1);
  double expected = 0.0;
  for (int i = 1; i <= segments; ++i)
    expected += m_point * omega * omega * (r0 + i * length / segments);
  const double measured = sum / weight;
  const Eigen::Vector3d tip_core = tip_sum / weight;
  std::printf(
      "spinning wire: root axial force %.5f N, rigid rotation %.5f N, rel. error %.2e; "
      "mean tip (core frame) %.5f, %.2e m; largest constraint residual %.2e\n",
      measured, expected, measured / expected - 1.0, tip_core.x(), tip_core.y(),
      sim.maxConstraintResidual());
  EXPECT_NEAR(measured / expected, 1.0, 0.02);
  // The wire points where the core's x axis points, on average.
  EXPECT_NEAR(tip_core.x(), r0 + length, 2e-4);
  EXPECT_LT(std::abs(tip_core.y()), 5e-4);
  // The clamp's acceleration is fed to the constraints: residuals stay at the
  // integration-error level (frames turning at 1000 rad/s, rtol 1e-6 on
  // their rates); without it they reach 8e-4.
  EXPECT_LT(sim.maxConstraintResidual(), 1e-6);
}
