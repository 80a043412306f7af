// The commanded supply port (Simulation::setPortCommand) against closed
// forms: the port is the straight-line interpolation of the samples, steps
// end at sample times, a command that reproduces the traverse law winds the
// same wire as the law, bad commands are refused and leave the run as it
// was, and snapshots carry the commanded path.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "coil_winding_sim/core/run/simulation.hpp"

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kR = 5.0e-3;  // drum radius [m]

// A drum (one cylinder) in 3-D turning at 600 rpm from the start, wire
// drawn at 30 N through a port 30 mm away; symplectic Euler at its fixed
// step, so that two runs with the same step times take the same steps.
cws::Scene drum3d(double duration, double pitch) {
  cws::Scene s;
  const double r = 0.5 * s.wire.diameter;
  s.wire.segment_length = 2.0e-3;
  s.physics.gravity = false;
  s.physics.damping = false;
  s.physics.contact = true;
  s.physics.friction = true;
  s.physics.supply = true;
  s.physics.planar = false;
  s.core.start_at_speed = true;
  s.core.cylinders = {cws::CylinderParams{{0.0, 0.0}, kR}};
  s.start.frame = "core";
  s.start.position = {kR + r, 0.0, 0.0};
  s.supply.port_position_world = {kR + r, -0.03, 0.0};
  s.process.core_speed_rpm = 600.0;
  s.process.tension = 30.0;
  s.process.traverse_pitch = pitch;
  s.process.duration = duration;
  s.solver.integrator = "symplectic_euler";
  s.solver.fixed_step = 5.0e-8;
  s.end.load = {cws::LoadKeyframe{}};
  return s;
}

struct Sample {
  double t_s;
  Eigen::Vector3d p_world;
};

// Steps end at sample times within rounding: 1e-12 relative (1e-12 s
// below 1 s), as at the end of a core speed ramp.
bool atSample(double t, double t_k) { return std::abs(t - t_k) <= 1e-12 * std::max(1.0, t_k); }

// Closed form: the straight line between the samples around t, the first
// sample before, the last after; velocity of the segment that starts at t
// (the one the next step follows), a time within rounding of a sample
// counting as that sample's.
void interpolate(const std::vector<Sample>& s, double t, Eigen::Vector3d& p, Eigen::Vector3d& v) {
  v.setZero();
  for (const Sample& k : s) {
    if (atSample(t, k.t_s)) t = k.t_s;
  }
  if (t < s.front().t_s) {
    p = s.front().p_world;
    return;
  }
  for (std::size_t k = 0; k + 1 < s.size(); ++k) {
    if (t >= s[k].t_s && t < s[k + 1].t_s) {
      const double w = (t - s[k].t_s) / (s[k + 1].t_s - s[k].t_s);
      p = (1.0 - w) * s[k].p_world + w * s[k + 1].p_world;
      v = (s[k + 1].p_world - s[k].p_world) / (s[k + 1].t_s - s[k].t_s);
      return;
    }
  }
  p = s.back().p_world;
}
}  // namespace

TEST(PortCommand, PortIsTheInterpolationOfTheSamplesAndStepsEndAtThem) {
  cws::Simulation sim(drum3d(2.5e-3, 0.0));
  const Eigen::Vector3d p0 = sim.scene().supply.port_position_world;
  // Irregular stamps; the port moves along the axis, outwards and back.
  std::vector<Sample> samples = {{0.0, p0},
                                 {0.3e-3, p0 + Eigen::Vector3d(0.0, 0.0, 1e-4)},
                                 {0.7e-3, p0 + Eigen::Vector3d(0.0, -1e-3, 3e-4)},
                                 {1.61e-3, p0 + Eigen::Vector3d(5e-4, -1e-3, 3e-4)},
                                 {2.0e-3, p0 + Eigen::Vector3d(5e-4, 0.0, 0.0)}};
  for (std::size_t k = 1; k < samples.size(); ++k) {
    sim.apply(cws::Setpoint::portPosition(samples[k].p_world, samples[k].t_s));
  }
  ASSERT_TRUE(sim.portCommanded());
  EXPECT_EQ(sim.portCommandEnd(), 2.0e-3);
  std::vector<bool> hit(samples.size(), false);
  double worst_p = 0.0, worst_v = 0.0;
  while (sim.time() < sim.endTime()) {
    sim.step(sim.endTime());
    const double t = sim.time();
    for (std::size_t k = 1; k < samples.size(); ++k) {
      if (atSample(t, samples[k].t_s)) hit[k] = true;
    }
    Eigen::Vector3d p, v;
    interpolate(samples, t, p, v);
    const cws::PortMotion m = sim.model().supply()->port(t);
    worst_p = std::max(worst_p, (m.p_world - p).norm());
    worst_v = std::max(worst_v, (m.v_world - v).norm());
    EXPECT_EQ(m.a_world, Eigen::Vector3d::Zero());
  }
  std::printf("port command: worst position error %.3e m, velocity error %.3e m/s\n", worst_p,
              worst_v);
  // Rounding of a few operations on positions of 3e-2 m and of a step end
  // 1e-19 s off a sample at speeds of 2 m/s.
  EXPECT_LT(worst_p, 1e-14);
  EXPECT_LT(worst_v, 1e-11);
  for (std::size_t k = 1; k < samples.size(); ++k) {
    EXPECT_TRUE(hit[k]) << "no step ended at the sample at " << samples[k].t_s << " s";
  }
  // Held after the last sample.
  EXPECT_EQ(sim.model().supply()->port(sim.time()).p_world, samples.back().p_world);
  EXPECT_LT(sim.maxConstraintResidual(), 1e-6);
}

TEST(PortCommand, FirstCommandStartsWhereTheTraversingPortIs) {
  // Half-way through the traverse law, a command takes over: no jump.
  cws::Simulation sim(drum3d(1.0e-3, 1.0e-3));
  while (sim.time() < 5e-4) sim.step(5e-4);
  const Eigen::Vector3d before = sim.model().supply()->port(sim.time()).p_world;
  EXPECT_GT(before.z(), 0.0);
  sim.apply(cws::Setpoint::portPosition(before + Eigen::Vector3d(0.0, 0.0, 1e-4), 8e-4));
  const cws::PortMotion m = sim.model().supply()->port(sim.time());
  EXPECT_EQ(m.p_world, before);
  EXPECT_NEAR(m.v_world.z(), 1e-4 / (8e-4 - sim.time()), 1e-12);
}

TEST(PortCommand, CommandedTraverseLawWindsLikeTheLaw) {
  // The traverse law at constant speed: p(t) = p0 + pitch / (2 pi) angle(t)
  // axis with angle(t) = omega (t - t_i / 2) after the instant start of
  // t_i = 1 ns, a straight line. Two runs under the law to t1 = 1 ms (the
  // same numbers); from there one follows commanded samples every 0.5 ms on
  // that line: the command starts where the port is, at the law's speed
  // (no velocity jump), and the wire must follow the same path (steps end at
  // sample times that are multiples of the fixed step).
  const double pitch = 1.0e-3, duration = 1.2e-2, t1 = 1.0e-3;
  cws::Simulation law(drum3d(duration, pitch));
  cws::Simulation cmd(drum3d(duration, pitch));
  while (law.time() < t1) law.step(t1);
  while (cmd.time() < t1) cmd.step(t1);
  const double omega = 600.0 * 2.0 * kPi / 60.0;
  const double t_i = cws::RotatingCore::kInstantRamp_s;
  const Eigen::Vector3d p0 = law.scene().supply.port_position_world;
  const Eigen::Vector3d axis(0.0, 0.0, 1.0);
  for (int k = 1; k <= 22; ++k) {
    const double t = t1 + 5.0e-4 * k;
    cmd.apply(
        cws::Setpoint::portPosition(p0 + pitch / (2.0 * kPi) * omega * (t - 0.5 * t_i) * axis, t));
  }
  while (law.time() < law.endTime()) law.step(law.endTime());
  while (cmd.time() < cmd.endTime()) cmd.step(cmd.endTime());
  ASSERT_EQ(law.model().constants().n, cmd.model().constants().n);
  const auto& a = law.model().committed();
  const auto& b = cmd.model().committed();
  const int n = law.model().constants().n;
  const double worst = (a.p_world.leftCols(n) - b.p_world.leftCols(n)).colwise().norm().maxCoeff();
  const double port_diff = (law.model().supply()->port(law.time()).p_world -
                            cmd.model().supply()->port(cmd.time()).p_world)
                               .norm();
  std::printf(
      "port command vs traverse law: %d points, port %.3e m apart, wire points at most %.3e m "
      "apart (port travelled %.3e m)\n",
      law.model().constants().n, port_diff, worst,
      (law.model().supply()->port(law.time()).p_world - p0).norm());
  EXPECT_GT(law.model().constants().n, 16) << "the wire should have grown";
  EXPECT_LT(port_diff, 1e-14);
  // The port paths differ by rounding (1e-18 m); the wire's answer stays
  // within 1e-12 m (the stretch of a 2 mm segment at 30 N is 1.2e-6 m).
  EXPECT_LT(worst, 1e-12);
}

TEST(PortCommand, BadCommandsAreRefusedAndTheRunGoesOn) {
  cws::Simulation sim(drum3d(1.0e-3, 0.0));
  const Eigen::Vector3d p0 = sim.scene().supply.port_position_world;
  while (sim.time() < 2e-4) sim.step(2e-4);
  sim.apply(cws::Setpoint::portPosition(p0 + Eigen::Vector3d(0.0, 0.0, 1e-4), 5e-4));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto expectRefused = [&](const Eigen::Vector3d& p, double t, const std::string& words) {
    const cws::PortMotion before = sim.model().supply()->port(sim.time());
    const double end = sim.portCommandEnd();
    try {
      sim.apply(cws::Setpoint::portPosition(p, t));
      ADD_FAILURE() << "accepted (" << p.transpose() << ") at " << t << " s";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos)
          << "message '" << e.what() << "' lacks '" << words << "'";
    }
    const cws::PortMotion after = sim.model().supply()->port(sim.time());
    EXPECT_EQ(before.p_world, after.p_world);
    EXPECT_EQ(before.v_world, after.v_world);
    EXPECT_EQ(end, sim.portCommandEnd());
  };
  expectRefused(Eigen::Vector3d(nan, 0.0, 0.0), 6e-4, "not finite");
  expectRefused(p0, nan, "stamp is not finite");
  expectRefused(p0, 4e-4, "go backwards");
  expectRefused(p0, 1e-4, "before the simulated time");
  expectRefused(Eigen::Vector3d(0.0, 1e-3, 3e-4), 6e-4, "inside the turning core");
  expectRefused(p0, 5e-4, "jump");
  // The run goes on along the good command.
  while (sim.time() < sim.endTime()) sim.step(sim.endTime());
  EXPECT_EQ(sim.model().supply()->port(sim.time()).p_world, p0 + Eigen::Vector3d(0.0, 0.0, 1e-4));
  // A scene without a supply has no port to command.
  cws::Scene plain;
  plain.wire.length = 0.01;
  plain.wire.segment_length = 0.002;
  cws::Simulation no_supply(plain);
  EXPECT_THROW(no_supply.apply(cws::Setpoint::portPosition(p0, 1e-3)), std::invalid_argument);
}

TEST(PortCommand, SnapshotCarriesTheCommandedPath) {
  cws::Simulation a(drum3d(1.5e-3, 0.0));
  const Eigen::Vector3d p0 = a.scene().supply.port_position_world;
  for (int k = 1; k <= 6; ++k)
    a.apply(cws::Setpoint::portPosition(p0 + Eigen::Vector3d(0.0, 0.0, 5e-5 * k), 2e-4 * k));
  while (a.time() < 5e-4) a.step(5e-4);
  const cws::SimulationState st = a.saveState();
  ASSERT_FALSE(st.model.port_command.empty());
  auto b = cws::Simulation::fromState(st);
  while (a.time() < a.endTime()) a.step(a.endTime());
  while (b->time() < b->endTime()) b->step(b->endTime());
  EXPECT_EQ(a.time(), b->time());
  ASSERT_EQ(a.model().constants().n, b->model().constants().n);
  const int size = a.model().size();
  EXPECT_EQ(a.state().head(size), b->state().head(size));
  EXPECT_LT(
      (b->model().supply()->port(b->time()).p_world - p0 - Eigen::Vector3d(0.0, 0.0, 3e-4)).norm(),
      1e-15);
  // A corrupt path is refused.
  cws::SimulationState bad = st;
  bad.model.port_command.pop_back();
  EXPECT_THROW(cws::Simulation::fromState(bad), std::runtime_error);
  bad = st;
  bad.model.port_command[4] = bad.model.port_command[0];  // times not increasing
  EXPECT_THROW(cws::Simulation::fromState(bad), std::runtime_error);
}
