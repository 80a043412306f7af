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
//
// pairCouplings: the 3-D system of 234 free points (robustness case 2's
// span when wound wire was released onto free wire, issue 57) with 0, 40,
// 88, 160 or 256 pairs of touching free segments (case 2's slowest
// stretches reached 128-256), each a point against the segment about one
// turn (60 points) before it: the band's factorization, the pairs'
// (PairCouplingSolve) and one Newton direction.
#include <benchmark/benchmark.h>

#include <random>

#include "coil_winding_sim/core/assembly/spatial_assembly.hpp"
#include "coil_winding_sim/core/implicit/pair_coupling_solve.hpp"
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

void pairCouplings(benchmark::State& st) {
  using A = cws::SpatialAssembly;
  constexpr int kPoints = 234;
  A a;
  a.resize(kPoints);
  a.begin(0, kPoints, true, true, 1e4);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int x = 0; x < st.range(0); ++x) {
    const int pa = 61 + x * (kPoints - 62) / static_cast<int>(st.range(0));
    Eigen::Matrix3d k = Eigen::Matrix3d::Identity() * 2e6;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) k(r, c) += 5e5 * u(rng);
    }
    a.addPairCoupling(pa, pa - 60, 0.5 + 0.5 * u(rng), k);
  }
  const int unknowns = a.unknowns(), blocks = (unknowns + A::kPerPoint - 1) / A::kPerPoint;
  cws::PairCouplingSolve pairs;
  pairs.resize(unknowns);
  Eigen::VectorXd b = Eigen::VectorXd::Ones(unknowns);
  for (auto _ : st) {
    for (int bi = 0; bi < blocks; ++bi) {
      for (int bj = std::max(0, bi - 1); bj <= std::min(blocks - 1, bi + 1); ++bj) {
        A::Matrix::Block& m = a.matrix().blockAt(bi, bj);
        for (int r = 0; r < A::kPerPoint; ++r) {
          for (int c = 0; c < A::kPerPoint; ++c) {
            const bool coupled = bi == bj || (bi < bj ? r : c) < A::kCoupled;
            m(r, c) = coupled ? 1e6 * u(rng) : 0.0;
          }
        }
        if (bi == bj) m.diagonal().array() += 2e7;
      }
    }
    benchmark::DoNotOptimize(a.matrix().factor());
    benchmark::DoNotOptimize(pairs.factor(a));
    a.matrix().solve(b);
    pairs.correct(a, b);
    benchmark::DoNotOptimize(b.data());
  }
}

}  // namespace

BENCHMARK(pairCouplings)
    ->Arg(0)
    ->Arg(40)
    ->Arg(88)
    ->Arg(160)
    ->Arg(256)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(fillAndSolve, 10, 7)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(fillAndSolve, 8, 6)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(fillAndSolve, 7, 7)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(fillAndSolve, 4, 4)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(fillAndSolve, 8, 8, 20)->Arg(0)->Arg(1);
BENCHMARK_MAIN();
