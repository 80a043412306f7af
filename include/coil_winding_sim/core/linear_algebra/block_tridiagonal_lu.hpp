// LU factorization of a block-tridiagonal matrix with square B x B blocks
// (block elimination, the block form of the Thomas algorithm), from the last
// block to the first: each diagonal block, less what the block after it
// passes on, is inverted with partial pivoting within the block; no rows are
// exchanged between blocks. That suits systems whose diagonal blocks are
// each nonsingular, such as the 3-D Newton system (a point's inertia and
// springs plus its frame constraints: a local saddle point, docs/MODEL.md),
// and runs on fixed-size blocks that the compiler unrolls and vectorizes. A
// last block that is singular on its own (the port's two multipliers, with
// a zero diagonal) is inverted together with the block before it
// (`merge_last`). A size n that is not a multiple of B is padded with
// identity rows. Storage is sized once; factor and solve allocate nothing.
//
// Coupling C <= B: only the first C unknowns of a block couple to the
// neighbouring blocks (an off-diagonal block is zero outside its first C
// rows above the diagonal and its first C columns below it). The 3-D system
// puts a point's positions and frame first and its frame multipliers last:
// a multiplier acts on its own point and the one before, never on the next
// point's unknowns. The elimination's products then run over C instead of B
// (debug builds check the zeros).
//
// The factors are kept apart from the matrix, so that a matrix assembled
// anew can have only its first block rows factored again (factorFrom): the
// elimination ends at block 0, and the factors of the later block rows stay
// valid for those rows as they were.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <vector>

namespace cws {

// Rows of ones but a zero on the diagonal (row c: all columns but c), as a
// constant table.
template <int N>
struct MaskRows {
  double mask[N][N];
  constexpr MaskRows() : mask() {
    for (int r = 0; r < N; ++r) {
      for (int c = 0; c < N; ++c) mask[r][c] = r == c ? 0.0 : 1.0;
    }
  }
  static const MaskRows kTable;
};
template <int N>
const MaskRows<N> MaskRows<N>::kTable;

template <int B, int C = B>
class BlockTridiagonalLu {
  static_assert(C > 0 && C <= B, "coupling within the block size");

 public:
  using Block = Eigen::Matrix<double, B, B>;
  using Segment = Eigen::Matrix<double, B, 1>;
  using Coupling = Eigen::Matrix<double, B, C>;   // W_k's first C columns
  using CouplingT = Eigen::Matrix<double, C, B>;  // U_k's first C rows
  using Pair = Eigen::Matrix<double, 2 * B, 1>;

  // Storage for matrices of up to `capacity` unknowns.
  void resize(int capacity) {
    const int blocks = (capacity + B - 1) / B;
    diag_.assign(blocks, Block::Zero());
    lower_.assign(blocks, Block::Zero());
    upper_.assign(blocks, Block::Zero());
    inv_.assign(blocks, Block::Zero());
    w_.assign(blocks, Coupling::Zero());
    u_.assign(blocks, CouplingT::Zero());
    work_.setZero(static_cast<Eigen::Index>(blocks) * B);
    n_ = m_ = 0;
    factored_n_ = -1;
    for (int c = 0; c < B; ++c) learned_[c] = c;
  }
  // Grows the storage to matrices of `unknowns` unknowns at least (twice
  // what it holds, where that is more) when it holds fewer; the factors kept
  // are lost then (a larger matrix is factored anew anyway).
  void reserve(int unknowns) {
    const int blocks = (unknowns + B - 1) / B;
    if (blocks <= static_cast<int>(diag_.size())) return;
    resize(std::max(unknowns, 2 * static_cast<int>(diag_.size()) * B));
  }
  // Starts a matrix of size n (<= capacity): all zero. merge_last: the last
  // block is inverted together with the one before it (it needs two blocks
  // at least). The factors of the last factorization stay (factorFrom).
  // top >= 0: only block rows 0..top are set (for factorFrom(top), which
  // reads no others).
  void setZero(int n, bool merge_last = false, int top = -1) {
    n_ = n;
    m_ = (n + B - 1) / B;
    merge_ = merge_last && m_ >= 2;
    const int rows = top >= 0 ? std::min(top + 1, m_) : m_;
    for (int k = 0; k < rows; ++k) {
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

  // Whether factorFrom(top) on a matrix of size n (merge_last as setZero's)
  // keeps the later block rows' factors, so that only rows 0..top need
  // assembling: the last complete factorization was of that size and form.
  bool keepsFactorsFrom(int top, int n, bool merge_last) const {
    const int m = (n + B - 1) / B;
    const bool merge = merge_last && m >= 2;
    const int last = merge ? m - 3 : m - 1;
    return factored_n_ == n && factored_merge_ == merge && top >= 0 && top < last;
  }

  // Factors the whole matrix. False if a pivot block is singular or not
  // finite.
  bool factor() { return factorFrom(m_ - 1); }

  // Factors block rows top..0 of the matrix as assembled now and keeps the
  // factors of the later rows from the last factorization of a matrix of
  // the same size and form (without one, or with top at the merged pair,
  // all rows). The result factors the matrix whose block rows 0..top are
  // today's and whose others are those of their last factorization. With k
  // from top down to 0:
  //   S_k = D_k - U_k W_k+1,  W_k = S_k^-1 L_k,
  // kept as inv_[k] = S_k^-1, w_[k] = the first C columns of W_k (the others
  // are zero) and u_[k] = the first C rows of U_k.
  bool factorFrom(int top) {
    const int last = merge_ ? m_ - 3 : m_ - 1;  // the last single block
    if (factored_n_ != n_ || factored_merge_ != merge_ || top >= last || top < 0) {
      top = last;
      factored_n_ = -1;
      for (int r = n_; r < m_ * B; ++r) diag_[m_ - 1](r % B, r % B) = 1.0;
      if (merge_ && !factorPair()) return false;
    }
    factored_n_ = -1;  // (again once every block is factored)
    for (int k = top; k >= 0; --k) {
      Block s = diag_[k];
      if (k + 1 < m_) {
        assert(upper_[k].template bottomRows<B - C>().isZero(0.0));
        u_[k] = upper_[k].template topRows<C>();
        const Coupling& w_next = (merge_ && k + 1 == m_ - 2) ? pair_w_top_ : w_[k + 1];
        s.template topLeftCorner<C, C>().noalias() -= u_[k].lazyProduct(w_next);
      }
      if (!invert(s, learned_)) return false;
      inv_[k] = s;
      if (k > 0) {
        assert(lower_[k].template rightCols<B - C>().isZero(0.0));
        w_[k].noalias() = inv_[k].lazyProduct(lower_[k].template leftCols<C>());
      }
    }
    factored_n_ = n_;
    factored_merge_ = merge_;
    return true;
  }

  // Solves A x = b in place (b holds n components).
  void solve(Eigen::Ref<Eigen::VectorXd> b) const {
    work_.head(n_) = b.head(n_);
    work_.segment(n_, m_ * B - n_).setZero();
    // From the last block up: y_k = S_k^-1 (b_k - U_k y_k+1).
    int k = m_ - 1;
    Segment y;
    if (merge_) {
      const Pair yp = pair_inv_.lazyProduct(work_.template segment<2 * B>((m_ - 2) * B));
      work_.template segment<2 * B>((m_ - 2) * B) = yp;
      y = yp.template head<B>();
      k = m_ - 3;
    } else {
      y = columnSum(inv_[k], Segment(work_.template segment<B>(k * B)));
      work_.template segment<B>(k * B) = y;
      --k;
    }
    for (; k >= 0; --k) {
      Segment r = work_.template segment<B>(k * B);
      r.template head<C>() -= columnSum(u_[k], y);
      y = columnSum(inv_[k], r);
      work_.template segment<B>(k * B) = y;
    }
    // From block 0 down: x_k = y_k - W_k x_k-1.
    const int singles = merge_ ? m_ - 2 : m_;
    for (k = 1; k < singles; ++k) {
      const Eigen::Matrix<double, C, 1> x_prev = work_.template segment<C>((k - 1) * B);
      work_.template segment<B>(k * B) -= columnSum(w_[k], x_prev);
    }
    if (merge_ && m_ > 2) {
      const Eigen::Matrix<double, C, 1> x_prev = work_.template segment<C>((m_ - 3) * B);
      work_.template segment<2 * B>((m_ - 2) * B).noalias() -= pair_w_.lazyProduct(x_prev);
    }
    b.head(n_) = work_.head(n_);
  }

  // The rows a solve works on: n rounded up to whole blocks.
  int paddedSize() const { return m_ * B; }

  // Solves A X = R for K right-hand sides at once, in place (products of a
  // block with K columns run at the CPU's throughput, where one column's
  // chain of products waits on each result). x has paddedSize() rows, zero
  // from row n on, and zero after row `last`: the sweep up starts at that
  // row's block, as the rows after it stay zero until the sweep down.
  template <int K>
  void solveColumns(Eigen::Ref<Eigen::Matrix<double, Eigen::Dynamic, K>> x, int last) const {
    using Rows = Eigen::Matrix<double, B, K>;
    using PairRows = Eigen::Matrix<double, 2 * B, K>;
    assert(x.rows() >= m_ * B);
    int k = std::min(last / B, m_ - 1);
    Rows y = Rows::Zero();
    if (merge_ && k >= m_ - 2) {
      const PairRows yp = pair_inv_.lazyProduct(x.template middleRows<2 * B>((m_ - 2) * B));
      x.template middleRows<2 * B>((m_ - 2) * B) = yp;
      y = yp.template topRows<B>();
      k = m_ - 3;
    } else if (k >= 0) {
      y = inv_[k].lazyProduct(x.template middleRows<B>(k * B));
      x.template middleRows<B>(k * B) = y;
      --k;
    }
    for (; k >= 0; --k) {
      Rows r = x.template middleRows<B>(k * B);
      r.template topRows<C>() -= u_[k].lazyProduct(y);
      y = inv_[k].lazyProduct(r);
      x.template middleRows<B>(k * B) = y;
    }
    const int singles = merge_ ? m_ - 2 : m_;
    for (k = 1; k < singles; ++k) {
      const Eigen::Matrix<double, C, K> x_prev = x.template middleRows<C>((k - 1) * B);
      x.template middleRows<B>(k * B) -= w_[k].lazyProduct(x_prev);
    }
    if (merge_ && m_ > 2) {
      const Eigen::Matrix<double, C, K> x_prev = x.template middleRows<C>((m_ - 3) * B);
      x.template middleRows<2 * B>((m_ - 2) * B) -= pair_w_.lazyProduct(x_prev);
    }
  }

 private:
  // m v for a fixed-size column-major m, as a sum of its columns in two
  // independent chains: each sweep of the solve is a chain of such
  // products, bound by their latency rather than their arithmetic.
  template <class M, class V>
  static Eigen::Matrix<double, M::RowsAtCompileTime, 1> columnSum(const M& m, const V& v) {
    constexpr int kCols = M::ColsAtCompileTime;
    using Column = Eigen::Matrix<double, M::RowsAtCompileTime, 1>;
    Column even = m.col(0) * v[0], odd = m.col(1) * v[1];
    for (int j = 2; j + 1 < kCols; j += 2) {
      even += m.col(j) * v[j];
      odd += m.col(j + 1) * v[j + 1];
    }
    if (kCols % 2 == 1) even += m.col(kCols - 1) * v[kCols - 1];
    return even + odd;
  }

  // Gauss-Jordan inversion in place with partial pivoting (rows of a
  // row-major copy, so each update is one contiguous fixed-size row): the
  // pivot column becomes the inverse's column as it is eliminated, and the
  // row exchanges are undone as column exchanges at the end. Every update
  // is a whole-row operation: the pivot column's new entries come from
  // masking that column out of a row before it is updated (a single entry
  // stored into a row that is then read as a vector stalls the CPU's store
  // forwarding: 2-3 % of the two-layer coil's run time).
  //
  // A search for each pivot puts a chain of comparisons on the critical
  // path of every column. The blocks of one system pivot alike, so a
  // diagonal block first takes the rows its last search chose (`learned`),
  // and keeps the result where each of them is at least kPivotRatio of the
  // largest entry at or below it in its column (threshold pivoting, as
  // sparse LU codes do): those comparisons run beside the elimination and
  // are judged at its end. A block that fails is inverted again with the
  // search, which teaches its rows.
  static constexpr double kPivotRatio = 0.1;
  template <int N>
  static bool invert(Eigen::Matrix<double, N, N>& a_inout, int* learned = nullptr) {
    if (learned && eliminate<N, false>(a_inout, learned)) return true;
    return eliminate<N, true>(a_inout, learned);
  }
  template <int N, bool kSearch>
  static bool eliminate(Eigen::Matrix<double, N, N>& a_inout, int* learned) {
    using RowBlock = Eigen::Matrix<double, N, N, Eigen::RowMajor>;
    using Row = Eigen::Matrix<double, 1, N>;
    RowBlock w = a_inout;
    int pivot_row[N];
    bool held = true;
    for (int c = 0; c < N; ++c) {
      int p = c;
      double best = std::abs(w(c, c));
      if (kSearch) {
        for (int r = c + 1; r < N; ++r) {
          if (std::abs(w(r, c)) > best) {
            best = std::abs(w(r, c));
            p = r;
          }
        }
      } else {
        p = learned[c];
        best = std::abs(w(p, c));
        double largest = best;
        for (int r = c; r < N; ++r) largest = std::max(largest, std::abs(w(r, c)));
        held = held && best >= kPivotRatio * largest;
      }
      if (!(best > 0.0) || !std::isfinite(best)) return false;
      pivot_row[c] = p;
      if (p != c) w.row(p).swap(w.row(c));
      const double inv = 1.0 / w(c, c);
      // mask: ones but column c (from a table: a vector made by storing
      // one entry into it would stall again); the pivot row with 1 in
      // column c, scaled.
      const Row mask = Eigen::Map<const Row>(MaskRows<N>::kTable.mask[c]);
      const Row pivot = (w.row(c).cwiseProduct(mask) + (Row::Ones() - mask)) * inv;
      for (int r = 0; r < N; ++r) {
        if (r == c) continue;
        const double f = w(r, c);
        w.row(r) = w.row(r).cwiseProduct(mask) - f * pivot;
      }
      w.row(c) = pivot;
    }
    if (!kSearch && !held) return false;
    if (kSearch && learned) std::copy(pivot_row, pivot_row + N, learned);
    for (int c = N - 1; c >= 0; --c) {
      if (pivot_row[c] != c) w.col(c).swap(w.col(pivot_row[c]));
    }
    a_inout = w;
    return true;
  }

  // The last two blocks as one pivot block (merge_last): its inverse, and
  // W of the pair, S^-1 (L_m-2 over zeros), whose top half the block before
  // reads.
  bool factorPair() {
    using PairBlock = Eigen::Matrix<double, 2 * B, 2 * B>;
    PairBlock s;
    s << diag_[m_ - 2], upper_[m_ - 2], lower_[m_ - 1], diag_[m_ - 1];
    if (!invert(s)) return false;
    pair_inv_ = s;
    if (m_ > 2) {
      assert(lower_[m_ - 2].template rightCols<B - C>().isZero(0.0));
      pair_w_.noalias() =
          pair_inv_.template leftCols<B>().lazyProduct(lower_[m_ - 2].template leftCols<C>());
      pair_w_top_ = pair_w_.template topRows<B>();
    }
    return true;
  }

  int n_ = 0, m_ = 0;
  bool merge_ = false;
  int learned_[B] = {};  // the diagonal blocks' pivot rows (invert)
  int factored_n_ = -1;  // the size of the last complete factorization
  bool factored_merge_ = false;
  std::vector<Block, Eigen::aligned_allocator<Block>> diag_, lower_, upper_, inv_;
  std::vector<Coupling, Eigen::aligned_allocator<Coupling>> w_;
  std::vector<CouplingT, Eigen::aligned_allocator<CouplingT>> u_;
  Eigen::Matrix<double, 2 * B, 2 * B> pair_inv_;  // the merged last pair's
  Eigen::Matrix<double, 2 * B, C> pair_w_;
  Coupling pair_w_top_;
  mutable Eigen::VectorXd work_;
};

}  // namespace cws
