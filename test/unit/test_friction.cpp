// Static and kinetic friction against closed forms: the tip of a clamped
// wire is pressed onto a cylinder whose surface slides along the wire's axis
// beneath it. The friction force on the tip is carried to the clamp as the
// wire's axial force, so the axial force of segment 0 measures it. Each
// closed form holds for both friction laws (contact.friction_law), with
// explicit steps and with the Newton steps of bdf2.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "wire_test_support.hpp"

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kL = 0.1;        // wire length [m]
constexpr double kRadius = 0.01;  // cylinder radius [m]
constexpr double kPress = 1.0;    // tip force pressing onto the cylinder [N]

// The tip rests on the top of a cylinder (axis along y, under the tip) that
// turns so that the core material at the tip's centre (radius R + r) moves at
// `surface_speed` [m/s] in +x, away from the clamp. (Contact uses the core's
// rigid-body velocity at the mass point, u_j of eqs. 16-17, so that wire
// carried by the core has no relative velocity.)
cws::Scene pressedTip(double surface_speed, double duration, const std::string& law = "stick_speed",
                      const std::string& integrator = "") {
  cws::Scene s = cws_test::cantilever(kL, 10);
  s.contact.friction_law = law;
  if (!integrator.empty()) s.solver.integrator = integrator;
  // Newton steps of 1e-4 s: the slip events of a tip on a surface this slow
  // are faster than the core's revolution sets the step for (at 4e-4 s the
  // tip on the creeping surface slips once and does not stick again).
  s.solver.implicit_step = 1e-4;
  s.physics.plasticity = false;
  s.physics.contact = true;
  s.physics.friction = true;
  s.physics.damping = true;
  s.damping.translational = 4.0;
  s.damping.rotational = 1e-6;
  const double r_wire = 0.5 * s.wire.diameter;
  s.core.position_world = {kL, 0.0, -(kRadius + r_wire)};
  s.core.axis_world = {0.0, 1.0, 0.0};  // +y: the top moves in +x
  s.core.cylinders = {cws::CylinderParams{{0.0, 0.0}, kRadius}};
  s.process.core_speed_rpm = surface_speed / (kRadius + r_wire) * 60.0 / (2.0 * kPi);
  cws::LoadKeyframe a, b;
  b.time = 0.002;
  b.force_world = {0.0, 0.0, -kPress};
  s.end.load = {a, b};
  s.process.duration = duration;
  return s;
}

// Normal force on the tip [N] from its penetration, from the geometry.
double normalForce(const cws::Simulation& sim) {
  const cws::Scene& s = sim.scene();
  const Eigen::Vector3d d = cws_test::tipPosition(sim) - s.core.position_world;
  const double h = kRadius + 0.5 * s.wire.diameter - Eigen::Vector2d(d.x(), d.z()).norm();
  return s.contact.stiffness * h;
}

// A friction law and an integrator ("": the cantilever's explicit one).
struct LawCase {
  const char* law;
  const char* integrator;
};
class FrictionLaw : public ::testing::TestWithParam<LawCase> {
 protected:
  cws::Scene tip(double surface_speed, double duration) const {
    return pressedTip(surface_speed, duration, GetParam().law, GetParam().integrator);
  }
};
}  // namespace

INSTANTIATE_TEST_SUITE_P(Laws, FrictionLaw,
                         ::testing::Values(LawCase{"stick_speed", ""}, LawCase{"elastic_slip", ""},
                                           LawCase{"elastic_slip", "bdf2"}),
                         [](const ::testing::TestParamInfo<LawCase>& info) {
                           return std::string(info.param.law) +
                                  (info.param.integrator[0] ? "_" : "") + info.param.integrator;
                         });

TEST_P(FrictionLaw, SlidingSurfaceDragsWithKineticFriction) {
  // 0.05 m/s is far above contact.stick_speed: the tip slides all along and
  // the wire carries mu_d N (eq. 18). (Elastic slip: the stick spring's
  // trial force leaves the cone at every step.)
  cws::Simulation sim(tip(0.05, 0.03));
  sim.run();
  const int tip = sim.model().constants().n - 1;
  const double n = normalForce(sim);
  const double expected = sim.scene().contact.kinetic_friction * n;
  const double axial = sim.model().axialForce(0);
  std::printf("kinetic: normal %.5f N, axial %.5f N, mu_d N %.5f N, rel. error %.2e\n", n, axial,
              expected, axial / expected - 1.0);
  EXPECT_NEAR(n, kPress, 0.01 * kPress);
  EXPECT_NEAR(axial / expected, 1.0, 0.01);
  EXPECT_TRUE(cws::wirePoint(sim.model(), tip).in_contact);
  EXPECT_FALSE(cws::wirePoint(sim.model(), tip).stick);
}

TEST_P(FrictionLaw, StickHoldsBelowStaticLimitThenSlips) {
  // The surface creeps at 1e-4 m/s, below contact.stick_speed: the tip sticks
  // and is dragged along, loading the wire through the stick spring and the
  // wire's axial stiffness in series (k = 1 / (1/k_t + L/EA)), until the
  // friction force reaches mu_s N (eqs. 19-20); then it slips.
  const double v_s = 1e-4;
  cws::Scene s = tip(v_s, 0.006);
  cws::Simulation sim(s);
  // Let the press settle before the creep is measured: the surface is
  // already moving, so record time and force when the tip first sticks under
  // full load.
  const int tip = sim.model().constants().n - 1;
  const double mu_s_n = s.contact.static_friction * kPress;
  double peak = 0.0, t_first_slip = -1.0;
  bool loaded = false;
  double t_loaded = 0.0, f_loaded = 0.0;
  double max_rate_error = 0.0;
  const double k_series =
      1.0 / (1.0 / s.contact.stick_stiffness + kL / s.wire.stretch.elastic_rigidity);
  while (sim.time() < sim.endTime()) {
    sim.step(sim.endTime());
    const double f = sim.model().axialForce(0);
    const bool stuck = cws::wirePoint(sim.model(), tip).stick;
    if (!loaded && sim.time() > 0.003 && stuck) {
      loaded = true;
      t_loaded = sim.time();
      f_loaded = f;
    }
    if (loaded && t_first_slip < 0.0) {
      if (stuck) {
        peak = std::max(peak, f);
        // While stuck the force grows at k v_s (after 0.2 ms of transients).
        if (sim.time() > t_loaded + 2e-4 && f < 0.9 * mu_s_n) {
          const double predicted = f_loaded + k_series * v_s * (sim.time() - t_loaded);
          max_rate_error = std::max(max_rate_error, std::abs(f - predicted) / mu_s_n);
        }
      } else {
        t_first_slip = sim.time();
      }
    }
  }
  std::printf(
      "static: first slip at t = %.5f s, peak axial force %.5f N, mu_s N %.5f N "
      "(rel. error %.2e), stuck loading follows k v_s within %.2e of mu_s N\n",
      t_first_slip, peak, mu_s_n, peak / mu_s_n - 1.0, max_rate_error);
  ASSERT_TRUE(loaded) << "the tip never stuck";
  ASSERT_GT(t_first_slip, 0.0) << "the tip never slipped";
  EXPECT_NEAR(peak / mu_s_n, 1.0, 0.02);
  EXPECT_LT(max_rate_error, 0.01);
}

TEST_P(FrictionLaw, StickSlipRepeatsAtTheStaticLimit) {
  // Creeping surface: after a slip the tip's sliding speed falls below
  // contact.stick_speed (elastic slip: its sliding stops), it sticks again
  // where it is, is loaded again and slips again at mu_s N: a stick-slip
  // sawtooth whose peaks of the friction force are mu_s N, N measured from
  // the penetration. (The clamp's axial force rings after each slip, so the
  // friction force is read at the tip.)
  cws::Scene s = tip(1e-4, 0.02);
  cws::Simulation sim(s);
  const int tip = sim.model().constants().n - 1;
  const double mu_s = s.contact.static_friction;
  std::vector<double> peaks;
  double peak = 0.0;
  bool was_stuck = false;
  int sticks = 0;
  while (sim.time() < sim.endTime()) {
    sim.step(sim.endTime());
    const bool stuck = cws::wirePoint(sim.model(), tip).stick;
    if (sim.time() < 0.003) {  // the press settles
      was_stuck = stuck;
      continue;
    }
    if (stuck) {
      peak = std::max(peak, sim.model().contact()->frictionForce(tip).norm() / normalForce(sim));
    }
    if (stuck && !was_stuck) ++sticks;
    if (!stuck && was_stuck) {
      peaks.push_back(peak);
      peak = 0.0;
    }
    was_stuck = stuck;
  }
  std::printf("stick-slip: %zu slips, %d re-sticks, peak friction / normal force", peaks.size(),
              sticks);
  for (double p : peaks) std::printf(" %.4f", p);
  std::printf(" (mu_s = %.4f)\n", mu_s);
  ASSERT_GE(peaks.size(), 2u);
  EXPECT_GE(sticks, 2);
  for (double p : peaks) EXPECT_NEAR(p / mu_s, 1.0, 0.02);
}

// Friction coefficients changed mid-run (Simulation::setFriction, the
// node's dynamic_reconfigure): the sliding tip then carries the new mu_d N;
// a change the scene's rules refuse (kinetic above static) is named and
// leaves the run as it was; the scene, and so a snapshot, takes the change.
TEST(Friction, CoefficientsChangedMidRunActFromTheNextStep) {
  cws::Simulation sim(pressedTip(0.05, 0.06));
  while (sim.time() < 0.03) sim.step(0.03);
  const double mu_d = sim.scene().contact.kinetic_friction;
  EXPECT_NEAR(sim.model().axialForce(0) / (mu_d * normalForce(sim)), 1.0, 0.01);
  try {
    sim.apply(cws::Setpoint::friction(0.1, 0.3));
    ADD_FAILURE() << "kinetic above static was taken";
  } catch (const cws::SceneError& e) {
    EXPECT_EQ(e.key(), "contact.kinetic_friction");
  }
  EXPECT_EQ(sim.scene().contact.kinetic_friction, mu_d);
  sim.apply(cws::Setpoint::friction(0.6, 0.45));
  sim.run();  // to 0.06 s
  EXPECT_EQ(sim.scene().contact.kinetic_friction, 0.45);
  EXPECT_NE(sim.saveState().scene_yaml.find("kinetic_friction: 0.45"), std::string::npos);
  const double axial = sim.model().axialForce(0), n = normalForce(sim);
  std::printf("after the change: axial %.5f N, mu_d N %.5f N\n", axial, 0.45 * n);
  EXPECT_NEAR(axial / (0.45 * n), 1.0, 0.01);
  // Damping changes the same way; a scene without friction refuses it.
  sim.apply(cws::Setpoint::damping(8.0, 2e-6));
  EXPECT_EQ(sim.scene().damping.translational, 8.0);
  cws::Scene plain = pressedTip(0.05, 0.01);
  plain.physics.friction = false;
  cws::Simulation frictionless(plain);
  EXPECT_THROW(frictionless.apply(cws::Setpoint::friction(0.3, 0.2)), cws::SceneError);
}
