#include "coil_winding_sim/core/implicit/pair_coupling_solve.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace cws {

void PairCouplingSolve::resize(int unknowns) {
  r_.resize(0);
  pairs_.clear();
  grow(unknowns, SpatialAssembly::kReservedPairCouplings);
  m_ = 0;
}

void PairCouplingSolve::grow(int unknowns, int pairs) {
  // (Rows for `unknowns` and a block more: the band's padded size.)
  constexpr int kMargin = SpatialAssembly::kPerPoint;
  const int rows = std::max(0, static_cast<int>(r_.size()) - kMargin);
  const int have = static_cast<int>(pairs_.size());
  if (unknowns <= rows && pairs <= have) return;
  const int cap = pairs <= have ? have : std::max(pairs, 2 * have);
  const int room = unknowns <= rows ? rows : std::max(unknowns, 2 * rows);
  pairs_.resize(cap);
  w_.setZero(room + kMargin, 3);
  r_.setZero(room + kMargin);
  s_.setZero(3 * cap, 3 * cap);
  g_.setZero(3 * cap);
  pivot_.assign(3 * cap, 0);
}

template <class V>
Eigen::Matrix<double, 3, V::ColsAtCompileTime> PairCouplingSolve::relative(const SpatialAssembly& a,
                                                                           int p,
                                                                           const V& v) const {
  // (The prescribed boundary point has no unknowns.)
  const SpatialAssembly::PairCoupling& c = pairs_[p];
  Eigen::Matrix<double, 3, V::ColsAtCompileTime> r =
      v.template middleRows<3>(a.pRow(c.a)) - c.t * v.template middleRows<3>(a.pRow(c.b + 1));
  if (c.b >= a.first()) r -= (1.0 - c.t) * v.template middleRows<3>(a.pRow(c.b));
  return r;
}

template <class V, class Z>
void PairCouplingSolve::scatter(const SpatialAssembly& a, int p, const Z& z, V& v) const {
  const SpatialAssembly::PairCoupling& c = pairs_[p];
  v.template middleRows<3>(a.pRow(c.a)) += z;
  v.template middleRows<3>(a.pRow(c.b + 1)) -= c.t * z;
  if (c.b >= a.first()) v.template middleRows<3>(a.pRow(c.b)) -= (1.0 - c.t) * z;
}

bool PairCouplingSolve::factor(SpatialAssembly& a) {
  m_ = a.pairCouplings();
  if (m_ == 0) return true;
  const SpatialAssembly::Matrix& band = a.matrix();
  const int padded = band.paddedSize(), cols = 3 * m_;
  grow(padded, m_);
  for (int p = 0; p < m_; ++p) pairs_[p] = a.pairCoupling(p);
  // S = I + K U^T A^-1 U, block (q, p) = delta_qp I + K_q C_q A^-1 C_p^T:
  // a pair's three columns of A^-1 U at once, then their rows each pair
  // reads.
  for (int p = 0; p < m_; ++p) {
    const SpatialAssembly::PairCoupling& c = pairs_[p];
    auto w = w_.topRows(padded);
    w.setZero();
    scatter(a, p, Eigen::Matrix3d::Identity(), w);
    band.solveColumns<3>(w, std::max(a.pRow(c.a), a.pRow(c.b + 1)) + 2);
    for (int q = 0; q < m_; ++q) s_.block<3, 3>(3 * q, 3 * p) = pairs_[q].k * relative(a, q, w);
    s_.block<3, 3>(3 * p, 3 * p) += Eigen::Matrix3d::Identity();
  }
  return factorSmall(cols);
}

bool PairCouplingSolve::factorSmall(int n) {
  // S's LU with partial pivoting, in place, by panels of kPanel columns
  // (LAPACK's getrf, right-looking): the panel is factored on its own, its
  // rows of U are solved for, and the rest of S is updated by the panel's
  // rank-kPanel product, row by row, while those rows of U stay in cache.
  // Updating the rest at every column instead streamed all of S through
  // memory 3 m times: at 250 pairs (750 unknowns, 4.5 MB) that was most of
  // a step's time (docs/history/2026-12-07-friction-decided-at-commits.md).
  // Whole rows are swapped, so the factors and pivots are getrf's.
  for (int k0 = 0; k0 < n; k0 += kPanel) {
    const int k1 = std::min(n, k0 + kPanel), rest = n - k1;
    for (int c = k0; c < k1; ++c) {
      int best = c;
      for (int r = c + 1; r < n; ++r) {
        if (std::abs(s_(r, c)) > std::abs(s_(best, c))) best = r;
      }
      if (!(std::abs(s_(best, c)) > 0.0) || !std::isfinite(s_(best, c))) return false;
      pivot_[c] = best;
      if (best != c) s_.row(c).head(n).swap(s_.row(best).head(n));
      const int width = k1 - c - 1;
      for (int r = c + 1; r < n; ++r) {
        const double f = s_(r, c) / s_(c, c);
        s_(r, c) = f;
        if (f != 0.0 && width > 0)
          s_.row(r).segment(c + 1, width) -= f * s_.row(c).segment(c + 1, width);
      }
    }
    if (rest == 0) break;
    // U's rows of the panel: L11^-1 A12 (L11 unit lower triangular).
    for (int c = k0; c < k1; ++c) {
      for (int r = c + 1; r < k1; ++r) {
        const double f = s_(r, c);
        if (f != 0.0) s_.row(r).segment(k1, rest) -= f * s_.row(c).segment(k1, rest);
      }
    }
    // A22 -= L21 U12, four rows at a time (each row of U12 read once for
    // four: the rows stay in L1, U12 in L2).
    int r = k1;
    for (; r + 4 <= n; r += 4) {
      double* a0 = &s_(r, k1);
      double* a1 = &s_(r + 1, k1);
      double* a2 = &s_(r + 2, k1);
      double* a3 = &s_(r + 3, k1);
      for (int c = k0; c < k1; ++c) {
        const double f0 = s_(r, c), f1 = s_(r + 1, c), f2 = s_(r + 2, c), f3 = s_(r + 3, c);
        const double* u = &s_(c, k1);
        for (int j = 0; j < rest; ++j) {
          const double uj = u[j];
          a0[j] -= f0 * uj;
          a1[j] -= f1 * uj;
          a2[j] -= f2 * uj;
          a3[j] -= f3 * uj;
        }
      }
    }
    for (; r < n; ++r) {
      auto row = s_.row(r).segment(k1, rest);
      for (int c = k0; c < k1; ++c) row -= s_(r, c) * s_.row(c).segment(k1, rest);
    }
  }
  return true;
}

void PairCouplingSolve::correct(const SpatialAssembly& a, Eigen::Ref<Eigen::VectorXd> x) const {
  if (m_ == 0) return;
  const int cols = 3 * m_, unknowns = static_cast<int>(x.size());
  // g = K U^T y, then S z = g (forward and back substitution), x -= A^-1 U z.
  for (int p = 0; p < m_; ++p) g_.segment<3>(3 * p) = pairs_[p].k * relative(a, p, x);
  for (int c = 0; c < cols; ++c) {
    if (pivot_[c] != c) std::swap(g_[c], g_[pivot_[c]]);
  }
  for (int c = 0; c < cols; ++c) {
    for (int r = c + 1; r < cols; ++r) g_[r] -= s_(r, c) * g_[c];
  }
  for (int c = cols - 1; c >= 0; --c) {
    for (int k = c + 1; k < cols; ++k) g_[c] -= s_(c, k) * g_[k];
    g_[c] /= s_(c, c);
  }
  auto r = r_.head(unknowns);
  r.setZero();
  for (int p = 0; p < m_; ++p) scatter(a, p, g_.segment<3>(3 * p), r);
  a.matrix().solve(r);
  x -= r;
}

}  // namespace cws
