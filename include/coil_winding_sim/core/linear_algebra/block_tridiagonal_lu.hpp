// LU factorization of a block-tridiagonal matrix with square B x B blocks
// (block elimination, the block form of the Thomas algorithm): each
// diagonal block, less what the block above passes down, is factored with
// partial pivoting within the block; no rows are exchanged between blocks.
// That suits systems whose diagonal blocks are each nonsingular, such as the
// 3-D Newton system (a point's inertia and springs plus its frame
// constraints: a local saddle point, docs/MODEL.md), and runs on fixed-size
// blocks that the compiler unrolls and vectorizes. A size n that is not a
// multiple of B is padded with identity rows. Storage is sized once; factor
// and solve allocate nothing.
//
// Coupling C <= B: only the first C unknowns of a block couple to the
// neighbouring blocks (an off-diagonal block is zero outside its first C
// rows above the diagonal and its first C columns below it). The 3-D system
// puts a point's positions and frame first and its frame multipliers last:
// a multiplier acts on its own point and the one before, never on the next
// point's unknowns. The elimination's products then run over C instead of B
// (debug builds check the zeros).
#pragma once

#include <Eigen/Core>
#include <cassert>
#include <cmath>
#include <vector>

namespace cws {

template <int B, int C = B>
class BlockTridiagonalLu {
  static_assert(C > 0 && C <= B, "coupling within the block size");

 public:
  using Block = Eigen::Matrix<double, B, B>;
  using Segment = Eigen::Matrix<double, B, 1>;

  // Storage for matrices of up to `capacity` unknowns.
  void resize(int capacity) {
    const int blocks = (capacity + B - 1) / B;
    diag_.assign(blocks, Block::Zero());
    lower_.assign(blocks, Block::Zero());
    upper_.assign(blocks, Block::Zero());
    work_.setZero(static_cast<Eigen::Index>(blocks) * B);
    n_ = 0;
    m_ = 0;
  }
  // Starts a matrix of size n (<= capacity): all zero.
  void setZero(int n) {
    n_ = n;
    m_ = (n + B - 1) / B;
    for (int k = 0; k < m_; ++k) {
      diag_[k].setZero();
      lower_[k].setZero();
      upper_[k].setZero();
    }
  }
  int size() const { return n_; }
  // Entry (i, j) before factoring; i and j in the same or adjacent blocks.
  bool inBand(int i, int j) const { return std::abs(i / B - j / B) <= 1; }
  double& at(int i, int j) { return blockAt(i / B, j / B)(i % B, j % B); }
  // Block (bi, bj), |bi - bj| <= 1: diagonal, lower (bi = bj + 1) or upper.
  Block& blockAt(int bi, int bj) {
    assert(bi >= 0 && bj >= 0 && bi < m_ && bj < m_ && std::abs(bi - bj) <= 1);
    return bi == bj ? diag_[bi] : (bi > bj ? lower_[bi] : upper_[bi]);
  }

  // Factors in place: diag_[k] becomes the inverse of the k-th pivot block
  // S_k = D_k - L_k S_k-1^-1 U_k-1 and upper_[k] becomes S_k^-1 U_k. False
  // if a pivot block is singular or not finite.
  bool factor() {
    for (int r = n_; r < m_ * B; ++r) diag_[m_ - 1](r % B, r % B) = 1.0;
    for (int k = 0; k < m_; ++k) {
      assert(k == 0 || lower_[k].template rightCols<B - C>().isZero(0.0));
      if (k > 0) {
        diag_[k].noalias() -=
            lower_[k].template leftCols<C>().lazyProduct(upper_[k - 1].template topRows<C>());
      }
      if (!invert(diag_[k])) return false;
      if (k + 1 < m_) {
        assert(upper_[k].template bottomRows<B - C>().isZero(0.0));
        const Eigen::Matrix<double, C, B> u = upper_[k].template topRows<C>();
        upper_[k].noalias() = diag_[k].template leftCols<C>().lazyProduct(u);
      }
    }
    return true;
  }

  // Solves A x = b in place (b holds n components).
  void solve(Eigen::Ref<Eigen::VectorXd> b) const {
    work_.head(n_) = b.head(n_);
    work_.segment(n_, m_ * B - n_).setZero();
    // Forward: y_k = S_k^-1 (b_k - L_k y_k-1).
    Segment y = diag_[0].lazyProduct(work_.template segment<B>(0));
    work_.template segment<B>(0) = y;
    for (int k = 1; k < m_; ++k) {
      Segment r = work_.template segment<B>(k * B);
      r.noalias() -= lower_[k].template leftCols<C>().lazyProduct(y.template head<C>());
      y.noalias() = diag_[k].lazyProduct(r);
      work_.template segment<B>(k * B) = y;
    }
    // Back: x_k = y_k - (S_k^-1 U_k) x_k+1.
    for (int k = m_ - 2; k >= 0; --k) {
      const Segment x_next = work_.template segment<B>((k + 1) * B);
      work_.template segment<B>(k * B).noalias() -= upper_[k].lazyProduct(x_next);
    }
    b.head(n_) = work_.head(n_);
  }

 private:
  // Gauss-Jordan inversion in place with partial pivoting (rows of a
  // row-major copy, so each update is one contiguous fixed-size row): the
  // pivot column becomes the inverse's column as it is eliminated, and the
  // row exchanges are undone as column exchanges at the end.
  static bool invert(Block& a_inout) {
    using RowBlock = Eigen::Matrix<double, B, B, Eigen::RowMajor>;
    RowBlock w = a_inout;
    int pivot_row[B];
    for (int c = 0; c < B; ++c) {
      int p = c;
      double best = std::abs(w(c, c));
      for (int r = c + 1; r < B; ++r) {
        if (std::abs(w(r, c)) > best) {
          best = std::abs(w(r, c));
          p = r;
        }
      }
      if (!(best > 0.0) || !std::isfinite(best)) return false;
      pivot_row[c] = p;
      if (p != c) w.row(p).swap(w.row(c));
      const double inv = 1.0 / w(c, c);
      w(c, c) = 1.0;
      w.row(c) *= inv;
      for (int r = 0; r < B; ++r) {
        if (r == c) continue;
        const double f = w(r, c);
        if (f == 0.0) continue;
        // (Its own column set after the row's update: a store before it
        // would hold up the vectorized row.)
        w.row(r) -= f * w.row(c);
        w(r, c) = -f * inv;
      }
    }
    for (int c = B - 1; c >= 0; --c) {
      if (pivot_row[c] != c) w.col(c).swap(w.col(pivot_row[c]));
    }
    a_inout = w;
    return true;
  }

  int n_ = 0, m_ = 0;
  std::vector<Block, Eigen::aligned_allocator<Block>> diag_, lower_, upper_;
  mutable Eigen::VectorXd work_;
};

}  // namespace cws
