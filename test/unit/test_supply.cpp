// The wire supply (paper's section IV) against closed forms: a drum (one
// cylinder) turning at 600 rpm draws wire through a port at 30 N.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "coil_winding_sim/core/base/quaternion.hpp"
#include "wire_test_support.hpp"

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kR = 5.0e-3;  // drum radius [m]

// The wire is clamped on the drum's surface, leaves it tangentially towards
// the port 30 mm away and winds on as the drum turns counter-clockwise.
cws::Scene drum(double duration) {
  cws::Scene s;
  const double r = 0.5 * s.wire.diameter;
  s.wire.segment_length = 2.0e-3;
  s.physics.gravity = false;
  s.physics.damping = false;
  s.physics.contact = true;
  s.physics.friction = true;
  s.physics.supply = true;
  s.physics.planar = true;
  s.core.start_at_speed = false;
  s.core.max_angular_acceleration = 2.0e4;  // 600 rpm after 3.1 ms
  s.core.cylinders = {cws::CylinderParams{{0.0, 0.0}, kR}};
  s.start.frame = "core";
  s.start.position = {kR + r, 0.0, 0.0};
  s.supply.port_position_world = {kR + r, -0.03, 0.0};
  s.process.core_speed_rpm = 600.0;
  s.process.tension = 30.0;
  s.process.duration = duration;
  s.end.load = {cws::LoadKeyframe{}};
  return s;
}
}  // namespace

TEST(Supply, DrumDrawsWireAtConstantTension) {
  const cws::Scene s = drum(0.02);
  cws::Simulation sim(s);
  const double r = 0.5 * s.wire.diameter;
  const double ea = s.wire.stretch.elastic_rigidity;
  const double eps_t = s.process.tension / ea;  // 6.1e-4, below yield
  const int n0 = sim.model().constants().n;

  // Steady drawing after the spin-up: the last segment (at the port) carries
  // the set tension, and the natural length fed grows with the wound length.
  // The wound points lie on the circle of radius R + r as a polygon of
  // chords l (1 + eps_T), each spanning theta = 2 asin(l (1 + eps_T) /
  // (2 (R + r))): d(fed)/d(angle) = l / theta.
  double force_sum = 0.0, weight = 0.0, fed1 = 0.0, angle1 = 0.0;
  double worst_fixed_end = 0.0;
  while (sim.time() < sim.endTime()) {
    sim.step(sim.endTime());
    const auto& k = sim.model().committed();
    worst_fixed_end =
        std::max(worst_fixed_end, std::abs(k.p_world.col(0).head<2>().norm() - (kR + r)));
    if (sim.time() > 0.008) {
      const double dt = sim.stepper().lastStep();
      force_sum += sim.model().axialForce(sim.model().constants().n - 2) * dt;
      weight += dt;
      if (fed1 == 0.0) {
        fed1 = sim.model().fedLength();
        angle1 = sim.model().core()->angle(sim.time());
      }
    }
  }
  const double force = force_sum / weight;
  const double fed_rate =
      (sim.model().fedLength() - fed1) / (sim.model().core()->angle(sim.time()) - angle1);
  const double theta = 2.0 * std::asin(s.wire.segment_length * (1.0 + eps_t) / (2.0 * (kR + r)));
  const double fed_rate_expected = s.wire.segment_length / theta;
  const int n = sim.model().constants().n;
  std::printf(
      "supply: %d -> %d points, port force %.4f N (set 30 N), fed per radian %.6e m "
      "(closed form %.6e m, rel. error %.2e), fed %.3f mm\n",
      n0, n, force, fed_rate, fed_rate_expected, fed_rate / fed_rate_expected - 1.0,
      1e3 * sim.model().fedLength());
  EXPECT_NEAR(force / s.process.tension, 1.0, 0.01);
  EXPECT_NEAR(fed_rate / fed_rate_expected, 1.0, 3e-3);
  EXPECT_GT(n, n0 + 1) << "the wire should have grown";

  // New points arrive at the segment length, stretched by the tension: the
  // free span's segments are l (1 + T / EA) long.
  const auto& k = sim.model().committed();
  for (int i = n - 3; i < n - 1; ++i) {
    const double len = (k.p_world.col(i + 1) - k.p_world.col(i)).norm();
    EXPECT_NEAR(len / (s.wire.segment_length * (1.0 + eps_t)), 1.0, 1e-4) << "segment " << i;
  }
  // The port stays on the line of the last segment (eq. 22).
  const Eigen::Vector3d zeta = cws::quat::zeta(k.q.col(n - 1)).normalized();
  const Eigen::Vector3d e = s.supply.port_position_world - k.p_world.col(n - 1);
  EXPECT_LT((e - e.dot(zeta) * zeta).norm(), 1e-9);
  // Wire wound tight at 30 N lies on the drum: no bulging.
  const cws::BulgeReport bulge = cws::bulging(sim.model());
  std::printf("supply bulging: %.3e m over %d wound points\n", bulge.height_m, bulge.wound_points);
  ASSERT_TRUE(bulge.valid);
  EXPECT_LT(bulge.height_m, 0.02 * r);
  // The fixed end stays on its cylinder (centreline at R + r).
  EXPECT_LT(worst_fixed_end, 1e-12);
  EXPECT_TRUE(cws::wirePoint(sim.model(), 1).in_contact);
  // Energy: the core's and the supply's work, including the energy the
  // drawn-in wire brings, balance kinetic + elastic + dissipated.
  const cws::EnergyReport en = sim.energy();
  std::printf("supply energy: W %.6e J, KE %.3e J, U %.3e J, D %.3e J, imbalance %.2e J\n",
              en.work_done, en.kinetic, en.elastic, en.dissipated(), en.imbalance());
  EXPECT_LT(std::abs(en.imbalance()), 1e-5 * (en.kinetic + en.elastic + en.dissipated()));
  EXPECT_LT(sim.maxConstraintResidual(), 1e-6);
}

TEST(Supply, SceneChecksThePortAndTheCore) {
  cws::Scene s = drum(0.01);
  s.supply.port_position_world = {0.002, 0.0, 0.0};  // inside the drum
  try {
    cws::validateScene(s);
    FAIL() << "a port inside the core must be refused";
  } catch (const cws::SceneError& e) {
    EXPECT_EQ(e.key(), "supply.port_position");
    EXPECT_NE(std::string(e.what()).find("inside the core"), std::string::npos);
  }
  s = drum(0.01);
  s.core.cylinders.clear();
  s.physics.contact = false;
  s.physics.friction = false;
  try {
    cws::validateScene(s);
    FAIL() << "a supply without cylinders must be refused";
  } catch (const cws::SceneError& e) {
    EXPECT_EQ(e.key(), "core.cylinders");
  }
  s = drum(0.01);
  s.process.traverse_pitch = 1e-3;  // planar cannot traverse
  EXPECT_THROW(cws::validateScene(s), cws::SceneError);
}

TEST(Supply, TraversingPortWindsASpiral) {
  // The paper's core in 3-D with a port that travels one wire diameter per
  // core turn: the port follows pitch x turns exactly (also through the
  // spin-up), and the wound wire climbs the axis with it.
  const std::string path = std::string(CWS_SOURCE_DIR) + "/config/scenes/paper_case_3d.yaml";
  cws::Simulation sim(cws::loadScene(path, {"process.turns=0.3"}));
  const cws::Scene& s = sim.scene();
  const double pitch = s.process.traverse_pitch;
  ASSERT_GT(pitch, 0.0);
  double worst_port = 0.0;
  while (sim.time() < sim.endTime()) {
    sim.step(sim.endTime());
    const double expected_z = s.supply.port_position_world.z() + pitch * sim.coreTurns();
    worst_port = std::max(
        worst_port, std::abs(sim.model().supply()->port(sim.time()).p_world.z() - expected_z));
  }
  EXPECT_LT(worst_port, 1e-15);
  // Along the wire from the fixed end to the port, the axial coordinate rises
  // from 0 to the port's (0.3 mm after 0.3 turns), never beyond.
  const auto& k = sim.model().committed();
  const int n = sim.model().constants().n;
  const double port_z = pitch * 0.3;
  std::printf(
      "spiral: port at z = %.4f mm, last point at z = %.4f mm, wire twist at the port "
      "%.3e rad/m\n",
      1e3 * port_z, 1e3 * k.p_world(2, n - 1), cws::wirePoint(sim.model(), n - 2).twist_rad_per_m);
  EXPECT_NEAR(k.p_world(2, 0), 0.0, 1e-15);
  EXPECT_GT(k.p_world(2, n - 1), 0.5 * port_z);
  for (int i = 0; i < n; ++i) EXPECT_LT(k.p_world(2, i), port_z + 1e-6) << "point " << i;
}
