// Cost of the right-hand side and of one integration step against the
// number of mass points (Google Benchmark). `make bench` runs it.
#include <benchmark/benchmark.h>

#include "coil_winding_sim/core/run/simulation.hpp"

namespace {
// A plastic wire with torsion, gravity and damping, clamped at one end,
// bent by a tip load: every inner force and the constraint solve at work.
cws::Scene scene(int points) {
  cws::Scene s;
  s.wire.segment_length = 1e-3;
  s.wire.length = (points - 1) * 1e-3;
  s.physics.gravity = true;
  s.physics.damping = true;
  s.damping.translational = 1.0;
  cws::LoadKeyframe a, b;
  b.time = 1e-3;
  b.force_world = {0.0, 0.2, 0.1};
  s.end.load = {a, b};
  s.process.duration = 1.0;
  return s;
}

void BM_Derivative(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  cws::Simulation sim(scene(n));
  for (int i = 0; i < 50; ++i) sim.step(sim.endTime());
  cws::WireModel& model = sim.model();
  Eigen::VectorXd dydt = Eigen::VectorXd::Zero(model.capacity());
  const Eigen::VectorXd y = sim.state();
  for (auto _ : state) {
    model.derivative(sim.time(), y.head(model.size()), dydt.head(model.size()));
    benchmark::DoNotOptimize(dydt.data());
  }
  state.counters["points"] = n;
  state.counters["per_point"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate |
                                                     benchmark::Counter::kInvert);
}

// One accepted step of an explicit integrator.
void BM_Step(benchmark::State& state, const char* integrator) {
  const int n = static_cast<int>(state.range(0));
  cws::Scene s = scene(n);
  s.solver.integrator = integrator;
  s.solver.fixed_step = 1e-7;
  cws::Simulation sim(s);
  for (int i = 0; i < 50; ++i) sim.step(sim.endTime());
  const cws::StepCounts before = sim.stepper().counts();
  for (auto _ : state) sim.step(sim.endTime());
  // Work per accepted step: right-hand sides (Jacobian builds included) and
  // rejected attempts, so that a growth in time per point can be told apart
  // from a growth in work.
  const cws::StepCounts& after = sim.stepper().counts();
  const double steps = static_cast<double>(after.accepted - before.accepted);
  state.counters["rhs_per_step"] =
      (after.derivative_evaluations - before.derivative_evaluations) / steps;
  state.counters["rejected_per_step"] = (after.rejected - before.rejected) / steps;
  state.counters["points"] = n;
  state.counters["per_point"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate |
                                                     benchmark::Counter::kInvert);
}
}  // namespace

BENCHMARK(BM_Derivative)->Arg(100)->Arg(1000)->Arg(10000)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Step, rkf45, "rkf45")
    ->Arg(100)
    ->Arg(1000)
    ->Arg(10000)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Step, symplectic_euler, "symplectic_euler")
    ->Arg(100)
    ->Arg(1000)
    ->Arg(10000)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
