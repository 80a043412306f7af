// The block-tridiagonal LU against a dense LU with partial pivoting, on
// matrices shaped like the 3-D Newton system: each diagonal block a local
// saddle point (zero diagonal in its multiplier rows), so that no
// elimination without pivoting would pass its first multiplier row.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstdio>
#include <limits>
#include <random>
#include <string>

#include "coil_winding_sim/core/linear_algebra/block_tridiagonal_lu.hpp"

namespace {

constexpr int kB = 10;
constexpr int kC = 7;  // the 3-D system's coupling: q and p, not the multipliers

// Random block-tridiagonal matrix of size n: per block, rows 4..6 are
// "multiplier" rows with a zero diagonal block, coupled to the other rows
// both ways; the rest is diagonally heavy as inertia over h^2 makes it.
// With coupling C < B the off-diagonal blocks are zero beyond their first
// C rows (above the diagonal) and columns (below it).
// port: the last two unknowns are a port's multipliers (zero diagonal, a
// block singular on its own, factored with the block before it).
// top_block >= 0: only block rows 0..top_block go into lu (setZero's top).
template <int C>
void fill(int n, std::mt19937& rng, Eigen::MatrixXd& dense, cws::BlockTridiagonalLu<kB, C>& lu,
          bool port = false, int top_block = -1) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  dense.setZero(n, n);
  lu.setZero(n, port, top_block);
  auto multiplier = [&](int i) {
    if (port && i >= n - 2) return true;
    return C < kB ? i % kB >= C : i % kB >= 4 && i % kB < 7;
  };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (std::abs(i / kB - j / kB) > 1) continue;
      if (i / kB < j / kB && i % kB >= C) continue;
      if (i / kB > j / kB && j % kB >= C) continue;
      double a = u(rng);
      if (multiplier(i) && multiplier(j)) a = 0.0;
      if (i == j && !multiplier(i)) a += 20.0;
      dense(i, j) = a;
      if (top_block < 0 || i / kB <= top_block) lu.at(i, j) = a;
    }
  }
}

template <int C = kB>
void check(int n, std::mt19937& rng, bool port = false) {
  cws::BlockTridiagonalLu<kB, C> lu;
  lu.resize(n + 25);  // room for more than this matrix, as in a run
  Eigen::MatrixXd dense;
  fill(n, rng, dense, lu, port);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) b[i] = u(rng);
  const Eigen::VectorXd x_dense = dense.partialPivLu().solve(b);
  ASSERT_TRUE(lu.factor());
  Eigen::VectorXd x = b;
  lu.solve(x);
  const double residual = (dense * x - b).norm() / b.norm();
  const double residual_dense = (dense * x_dense - b).norm() / b.norm();
  const double diff = (x - x_dense).norm() / x_dense.norm();
  std::printf(
      "block-tridiagonal LU n=%d, coupling %d: residual %.1e (dense LU's %.1e), vs dense LU %.1e\n",
      n, C, residual, residual_dense, diff);
  // Random saddle points are not well conditioned: within rounding of the
  // dense LU's own result, far from any wrong elimination's O(1).
  EXPECT_LT(residual, 1e-9);
  EXPECT_LT(diff, 1e-10);
  // Three right-hand sides at once, zero after a row `last` (the sweep up
  // starts there): in the first block, mid-matrix, in the last two blocks
  // (the merged port pair) and at the end.
  for (int last : {0, n / 2, std::max(0, n - kB - 3), n - 1}) {
    Eigen::Matrix<double, Eigen::Dynamic, 3> r = Eigen::MatrixXd::Zero(lu.paddedSize(), 3);
    for (int i = 0; i <= last; ++i) {
      for (int j = 0; j < 3; ++j) r(i, j) = u(rng);
    }
    const Eigen::MatrixXd r_dense = r.topRows(n);
    lu.template solveColumns<3>(r, last);
    const Eigen::MatrixXd x3 = dense.partialPivLu().solve(r_dense);
    EXPECT_LT((r.topRows(n) - x3).norm() / x3.norm(), 1e-10) << "n = " << n << ", last " << last;
  }
}

TEST(BlockTridiagonalLu, MatchesADenseLuOnSaddlePointBlocks) {
  std::mt19937 rng(7);
  check(10, rng);   // one block
  check(402, rng);  // 40 points and the port's two rows (a padded block)
  check(127, rng);  // a size that is no multiple of the block
  // Coupling through the first 7 unknowns of a block only (multipliers in
  // the last three rows of the block here, as the 3-D system orders them).
  check<kC>(10, rng);
  check<kC>(402, rng);
  check<kC>(127, rng);
  // A port's two multipliers after the last point (the 3-D system with a
  // supply): a last block singular on its own.
  check<kC>(402, rng, true);
  check<kC>(12, rng, true);
  check<kC>(22, rng, true);
  // The same storage reused for a smaller and a larger matrix.
  cws::BlockTridiagonalLu<kB> lu;
  lu.resize(300);
  Eigen::MatrixXd dense;
  for (int n : {300, 37, 212}) {
    fill(n, rng, dense, lu);
    ASSERT_TRUE(lu.factor());
    Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0), x = b;
    lu.solve(x);
    EXPECT_LT((dense * x - b).norm() / b.norm(), 1e-9) << "n = " << n;
  }
}

// Refactoring the first blocks only: the factors of the later block rows
// are kept, so the solve is that of the matrix whose first block rows are
// the new ones and whose later rows are the old ones (a dense LU of that
// hybrid is the independent answer). A matrix of another size is factored
// whole.
TEST(BlockTridiagonalLu, FactorFromKeepsTheLaterBlockRows) {
  std::mt19937 rng(11);
  cws::BlockTridiagonalLu<kB, kC> lu;
  lu.resize(402);
  for (bool port : {false, true}) {
    for (int n : {402, 127}) {
      for (int top : {0, 3, 9}) {
        Eigen::MatrixXd old_rows, new_rows;
        fill(n, rng, old_rows, lu, port);
        ASSERT_TRUE(lu.factor()) << "n = " << n << ", top " << top << ", port " << port;
        // The new matrix is set only in the rows factored again, as a
        // flag round assembles it.
        ASSERT_TRUE(lu.keepsFactorsFrom(top, n, port));
        fill(n, rng, new_rows, lu, port, top);
        // Rows past top are not read: poisoned, they change nothing.
        for (int i = (top + 1) * kB; i < n; ++i) {
          for (int j = 0; j < n; ++j) {
            if (lu.inBand(i, j)) lu.at(i, j) = std::numeric_limits<double>::quiet_NaN();
          }
        }
        ASSERT_TRUE(lu.factorFrom(top));
        const int rows = std::min(n, (top + 1) * kB);
        Eigen::MatrixXd hybrid = old_rows;
        hybrid.topRows(rows) = new_rows.topRows(rows);
        Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0), x = b;
        lu.solve(x);
        const Eigen::VectorXd x_dense = hybrid.partialPivLu().solve(b);
        const std::string what =
            "n = " + std::to_string(n) + ", top " + std::to_string(top) + (port ? ", port" : "");
        // (Random saddle points: the residual within rounding of a poorly
        // conditioned matrix; the dense LU's solution is the sharper check.)
        EXPECT_LT((hybrid * x - b).norm() / b.norm(), 1e-8) << what;
        EXPECT_LT((x - x_dense).norm() / x_dense.norm(), 1e-10) << what;
        // Not the new matrix's solution: the later rows are old.
        EXPECT_GT((new_rows * x - b).norm() / b.norm(), 1e-3) << what;
      }
    }
  }
  // Another size after the last factorization, or a top at the last single
  // block or beyond: factored whole (so assembled whole).
  // (The last factorization: 127 unknowns in 13 blocks, with the port's,
  // so blocks 11 and 12 are one pivot and block 10 the last single one.)
  EXPECT_TRUE(lu.keepsFactorsFrom(9, 127, true));
  EXPECT_FALSE(lu.keepsFactorsFrom(10, 127, true));
  EXPECT_FALSE(lu.keepsFactorsFrom(9, 127, false));
  EXPECT_FALSE(lu.keepsFactorsFrom(2, 212, false));
  Eigen::MatrixXd dense;
  fill(212, rng, dense, lu);
  ASSERT_TRUE(lu.factorFrom(2));
  Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(212, -1.0, 2.0), x = b;
  lu.solve(x);
  EXPECT_LT((dense * x - b).norm() / b.norm(), 1e-9);
}

TEST(BlockTridiagonalLu, ReportsASingularBlock) {
  cws::BlockTridiagonalLu<kB> lu;
  lu.resize(20);
  lu.setZero(20);
  for (int i = 0; i < 20; ++i) lu.at(i, i) = 1.0;
  // The second block's pivot block loses a rank: rows 13 and 14 equal.
  lu.at(13, 13) = 0.0;
  lu.at(13, 14) = 1.0;
  lu.at(14, 14) = 1.0;
  lu.at(14, 13) = 0.0;
  lu.at(13, 12) = 0.0;
  EXPECT_FALSE(lu.factor());
  // A non-finite entry is refused too.
  lu.setZero(20);
  for (int i = 0; i < 20; ++i) lu.at(i, i) = 1.0;
  lu.at(3, 3) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(lu.factor());
}

}  // namespace

// The planar Newton system's layout (PlanarAssembly::Matrix): two
// coordinates per point in blocks of two points, every point coupled to the
// points up to two away (bending), and a port multiplier last whose row and
// column touch the last two points only, with a zero diagonal. With an
// even number of points the multiplier sits alone in a padded block, with
// an odd one beside the last point; either way its block is inverted
// together with the one before it (merge_last).
TEST(BlockTridiagonalLu, MatchesADenseLuOnThePlanarSystem) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int points : {40, 41, 2, 3}) {
    const int n = 2 * points + 1, m = n - 1;  // m: the multiplier's row
    cws::BlockTridiagonalLu<4> lu;
    lu.resize(n + 9);
    lu.setZero(n, true);
    Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(n, n);
    auto set = [&](int i, int j, double a) {
      dense(i, j) = a;
      ASSERT_TRUE(lu.inBand(i, j)) << i << ", " << j;
      lu.at(i, j) = a;
    };
    for (int i = 0; i < m; ++i) {
      for (int j = 0; j < m; ++j) {
        if (std::abs(i / 2 - j / 2) > 2) continue;
        set(i, j, u(rng) + (i == j ? 20.0 : 0.0));
      }
    }
    for (int j = std::max(0, m - 4); j < m; ++j) {
      set(m, j, u(rng));
      set(j, m, u(rng));
    }
    Eigen::VectorXd b(n);
    for (int i = 0; i < n; ++i) b[i] = u(rng);
    const Eigen::VectorXd x_dense = dense.partialPivLu().solve(b);
    ASSERT_TRUE(lu.factor()) << points << " points";
    Eigen::VectorXd x = b;
    lu.solve(x);
    EXPECT_LT((dense * x - b).norm() / b.norm(), 1e-10) << points << " points";
    EXPECT_LT((x - x_dense).norm() / x_dense.norm(), 1e-10) << points << " points";
  }
}
