// What the parts of a 3-D Newton iteration cost on the two-layer coil
// (config/scenes/two_layers.yaml) wound for 0.4 s (Google Benchmark): the
// assembly of the forces alone (a line search's residual), of the forces
// and the whole Jacobian, the factorization of that Jacobian and a solve
// with it (a Newton direction). Unlike
// a run of the coil, whose Newton path moves with the last bit of any
// change, these repeat exactly: `bench_newton` tells a change of the
// arithmetic apart from a change of the path.
#include <benchmark/benchmark.h>

#include <string>

#include "coil_winding_sim/core/implicit/spatial_formulation.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace {

// The coil's wire at t = 0.4 s, loaded into a formulation of its own as a
// step's start (trial state = committed state, scheme of a 1e-4 s step).
struct Wound {
  cws::Scene scene;
  cws::Simulation sim;
  cws::SpatialFormulation form;
  Wound()
      : scene(cws::loadScene(std::string(CWS_SOURCE_DIR) + "/config/scenes/two_layers.yaml",
                             {"process.duration=0.4"})),
        sim(scene),
        form((sim.run(), sim.model()), scene.solver) {
    form.load(sim.time());
    form.trialState().alpha = 1.0 / scene.solver.implicit_step;
  }
};

Wound& wound() {
  static Wound w;
  return w;
}

void BM_ForcesOnly(benchmark::State& state) {
  Wound& w = wound();
  for (auto _ : state) benchmark::DoNotOptimize(w.form.assemble(false).forces().data());
  state.counters["points"] = w.form.n() - w.form.first();
}

void BM_ForcesAndJacobian(benchmark::State& state) {
  Wound& w = wound();
  for (auto _ : state) benchmark::DoNotOptimize(w.form.assemble(true).forces().data());
  state.counters["points"] = w.form.n() - w.form.first();
}

void BM_Factorization(benchmark::State& state) {
  Wound& w = wound();
  // (A copy of the assembled matrix, factored again and again.)
  cws::SpatialAssembly::Matrix m =
      const_cast<cws::SpatialAssembly&>(w.form.assemble(true)).matrix();
  for (auto _ : state) {
    const bool ok = m.factor();
    benchmark::DoNotOptimize(ok);
  }
  state.counters["points"] = w.form.n() - w.form.first();
}

void BM_Solve(benchmark::State& state) {
  Wound& w = wound();
  const cws::SpatialAssembly& a = w.form.assemble(true);
  cws::SpatialAssembly::Matrix m = const_cast<cws::SpatialAssembly&>(a).matrix();
  m.factor();
  const Eigen::VectorXd rhs = a.forces().head(a.unknowns());
  Eigen::VectorXd x(rhs.size());
  for (auto _ : state) {
    x = rhs;
    m.solve(x);
    benchmark::DoNotOptimize(x.data());
  }
  state.counters["points"] = w.form.n() - w.form.first();
}

}  // namespace

BENCHMARK(BM_ForcesOnly);
BENCHMARK(BM_ForcesAndJacobian);
BENCHMARK(BM_Factorization);
BENCHMARK(BM_Solve);
BENCHMARK_MAIN();
