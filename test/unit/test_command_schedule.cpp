// Setpoints scheduled by simulated time (command_schedule.hpp): taken in
// time order when the time reaches them (within rounding), equal times in
// the order given; and a run that steps to the schedule's times turns the
// core at the commanded speeds from exactly those times on.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "coil_winding_sim/core/run/command_schedule.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"

using cws::Setpoint;

TEST(CommandSchedule, TakesDueCommandsInTimeOrder) {
  cws::CommandSchedule s;
  EXPECT_TRUE(std::isinf(s.nextTime()));
  s.add(0.2, Setpoint::supplyTension(40.0));
  s.add(0.1, Setpoint::coreSpeed(10.0));
  s.add(0.1, Setpoint::coreSpeed(20.0));       // same time: after the first
  s.add(-INFINITY, Setpoint::coreSpeed(5.0));  // at once
  std::vector<double> values;
  auto take = [&](double, const Setpoint& c) { values.push_back(c.value); };
  EXPECT_EQ(s.takeDue(0.0, take), 1);
  EXPECT_EQ(s.nextTime(), 0.1);
  EXPECT_EQ(s.takeDue(0.05, take), 0);
  // A step that lands within rounding short of 0.1 s reaches it.
  EXPECT_EQ(s.takeDue(0.1 - 1e-15, take), 2);
  EXPECT_EQ(s.takeDue(1.0, take), 1);
  EXPECT_EQ(values, (std::vector<double>{5.0, 10.0, 20.0, 40.0}));
  EXPECT_TRUE(s.empty());
}

TEST(CommandSchedule, ASpeedCommandTakesEffectAtItsTime) {
  // The paper's case, turning at speed from the start.
  const cws::Scene scene = cws::loadScene(
      CWS_SOURCE_DIR "/config/scenes/default.yaml",
      {"solver.integrator=bdf2", "process.duration=0.01", "core.start_at_speed=true"});
  cws::Simulation sim(scene);
  cws::CommandSchedule s;
  const double t_cmd = 0.0043, w_cmd = 50.0;  // [s], [rad/s]
  s.add(t_cmd, Setpoint::coreSpeed(w_cmd));
  const double w0 = sim.model().core()->omega(0.001);
  bool checked = false;
  while (sim.time() < sim.endTime()) {
    s.takeDue(sim.time(), [&](double t, const Setpoint& c) {
      EXPECT_NEAR(sim.time(), t, 1e-12);  // a step ended at the command
      sim.apply(c);
      checked = true;
    });
    sim.step(std::min(sim.endTime(), s.nextTime()));
  }
  ASSERT_TRUE(checked);
  // From t_cmd on the core ramps from w0 to w_cmd at its acceleration limit.
  const double a = scene.core.max_angular_acceleration;
  const double t_end = t_cmd + std::abs(w_cmd - w0) / a;
  ASSERT_LT(t_end, sim.endTime());
  EXPECT_NEAR(sim.model().core()->omega(sim.time()), w_cmd, 1e-9);
}
