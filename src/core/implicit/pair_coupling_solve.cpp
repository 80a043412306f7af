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
  // Its LU with partial pivoting, in place.
  for (int c = 0; c < cols; ++c) {
    int best = c;
    for (int r = c + 1; r < cols; ++r) {
      if (std::abs(s_(r, c)) > std::abs(s_(best, c))) best = r;
    }
    if (!(std::abs(s_(best, c)) > 0.0) || !std::isfinite(s_(best, c))) return false;
    pivot_[c] = best;
    if (best != c) s_.row(c).head(cols).swap(s_.row(best).head(cols));
    const int rest = cols - c - 1;
    for (int r = c + 1; r < cols; ++r) {
      const double f = s_(r, c) / s_(c, c);
      s_(r, c) = f;
      if (f != 0.0) s_.row(r).segment(c + 1, rest) -= f * s_.row(c).segment(c + 1, rest);
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
