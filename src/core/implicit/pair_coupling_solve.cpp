#include "coil_winding_sim/core/implicit/pair_coupling_solve.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace cws {

void PairCouplingSolve::resize(int unknowns) {
  w_.resize(0, 0);
  pairs_.clear();
  grow(unknowns, SpatialAssembly::kReservedPairCouplings);
  m_ = 0;
}

void PairCouplingSolve::grow(int unknowns, int pairs) {
  const int rows = static_cast<int>(w_.rows()), have = static_cast<int>(pairs_.size());
  if (unknowns <= rows && pairs <= have) return;
  const int cap = pairs <= have ? have : std::max(pairs, 2 * have);
  pairs_.resize(cap);
  w_.setZero(unknowns <= rows ? rows : std::max(unknowns, 2 * rows), 3 * cap);
  s_.setZero(3 * cap, 3 * cap);
  g_.setZero(3 * cap);
  pivot_.assign(3 * cap, 0);
}

Eigen::Vector3d PairCouplingSolve::relative(const SpatialAssembly& a, int p,
                                            const Eigen::Ref<const Eigen::VectorXd>& v) const {
  // (The prescribed boundary point has no unknowns.)
  const SpatialAssembly::PairCoupling& c = pairs_[p];
  Eigen::Vector3d r = v.segment<3>(a.pRow(c.a)) - c.t * v.segment<3>(a.pRow(c.b + 1));
  if (c.b >= a.first()) r -= (1.0 - c.t) * v.segment<3>(a.pRow(c.b));
  return r;
}

bool PairCouplingSolve::factor(SpatialAssembly& a) {
  m_ = a.pairCouplings();
  if (m_ == 0) return true;
  const int unknowns = a.unknowns(), cols = 3 * m_;
  grow(unknowns, m_);
  // W = A^-1 U, column by column.
  for (int p = 0; p < m_; ++p) {
    pairs_[p] = a.pairCoupling(p);
    const SpatialAssembly::PairCoupling& c = pairs_[p];
    for (int d = 0; d < 3; ++d) {
      auto w = w_.col(3 * p + d).head(unknowns);
      w.setZero();
      w[a.pRow(c.a) + d] = 1.0;
      w[a.pRow(c.b + 1) + d] = -c.t;
      if (c.b >= a.first()) w[a.pRow(c.b) + d] = -(1.0 - c.t);
      a.matrix().solve(w);
    }
  }
  // S = I + K U^T W, block (p, q) = delta_pq I + K_p C_p W_q.
  for (int q = 0; q < cols; ++q) {
    const auto w = w_.col(q).head(unknowns);
    for (int p = 0; p < m_; ++p) s_.block<3, 1>(3 * p, q) = pairs_[p].k * relative(a, p, w);
    s_(q, q) += 1.0;
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
  const int cols = 3 * m_;
  // g = K U^T y, then S z = g (forward and back substitution), x -= W z.
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
  x.noalias() -= w_.leftCols(cols).topRows(x.size()) * g_.head(cols);
}

}  // namespace cws
