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
#pragma once

#include <Eigen/Core>
#include <cassert>
#include <cmath>
#include <vector>

namespace cws {

template <int B>
class BlockTridiagonalLu {
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
      if (k > 0) diag_[k].noalias() -= lower_[k].lazyProduct(upper_[k - 1]);
      if (!invert(diag_[k])) return false;
      if (k + 1 < m_) {
        const Block u = upper_[k];
        upper_[k].noalias() = diag_[k].lazyProduct(u);
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
      r.noalias() -= lower_[k].lazyProduct(y);
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
  // row-major copy, so each update is one contiguous fixed-size row).
  static bool invert(Block& a_inout) {
    using RowBlock = Eigen::Matrix<double, B, 2 * B, Eigen::RowMajor>;
    RowBlock w;
    w.template leftCols<B>() = a_inout;
    w.template rightCols<B>().setIdentity();
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
      if (p != c) w.row(p).swap(w.row(c));
      w.row(c) *= 1.0 / w(c, c);
      for (int r = 0; r < B; ++r) {
        if (r == c) continue;
        const double f = w(r, c);
        if (f != 0.0) w.row(r) -= f * w.row(c);
      }
    }
    a_inout = w.template rightCols<B>();
    return true;
  }

  int n_ = 0, m_ = 0;
  std::vector<Block, Eigen::aligned_allocator<Block>> diag_, lower_, upper_;
  mutable Eigen::VectorXd work_;
};

}  // namespace cws
