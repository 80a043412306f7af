// The Newton system's factorization and solve against the block size
// (design input for fewer unknowns per point,
// docs/history/2026-11-24-block-size-and-elimination-order.md): 40
// points, blocks of 10 unknowns coupling through 7 (today's 3-D system:
// position, quaternion, three frame multipliers), of 8 coupling through 6
// (a rotation increment in the quaternion's tangent space instead of the
// quaternion, and no multiplier for its unit norm), of 7, and of 4
// (position and a twist); and 20 blocks of 8, two points of 4 unknowns each, for a
// formulation whose bending couples a point with the next but one (the
// system is then block-pentadiagonal in points of 4). Arg 0 fills the
// matrix only, arg 1 also factors and solves: the difference is the
// factorization's and the solve's cost. Instruction counts: valgrind
// --tool=callgrind bench_block_lu.
#include <benchmark/benchmark.h>

#include "coil_winding_sim/core/linear_algebra/block_tridiagonal_lu.hpp"

namespace {

template <int B, int C, int kPoints = 40>
void fillAndSolve(benchmark::State& st) {
  cws::BlockTridiagonalLu<B, C> lu;
  lu.resize(kPoints * B);
  Eigen::VectorXd b = Eigen::VectorXd::Ones(kPoints * B);
  for (auto _ : st) {
    lu.setZero(kPoints * B);
    // Diagonally dominant blocks, coupled through their first C unknowns.
    for (int k = 0; k < kPoints; ++k) {
      auto& d = lu.blockAt(k, k);
      d.setRandom();
      d.diagonal().array() += 4.0 * B;
      if (k == 0) continue;
      lu.blockAt(k, k - 1).template leftCols<C>().setRandom();
      lu.blockAt(k - 1, k).template topRows<C>().setRandom();
    }
    if (st.range(0) != 0) {
      benchmark::DoNotOptimize(lu.factor());
      lu.solve(b);
    }
    benchmark::DoNotOptimize(b.data());
  }
}

}  // namespace

BENCHMARK_TEMPLATE(fillAndSolve, 10, 7)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(fillAndSolve, 8, 6)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(fillAndSolve, 7, 7)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(fillAndSolve, 4, 4)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(fillAndSolve, 8, 8, 20)->Arg(0)->Arg(1);
BENCHMARK_MAIN();
