#include "coil_winding_sim/core/linear_algebra/banded_lu.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace cws {

void BandedLu::resize(int capacity, int kl, int ku) {
  kl_ = kl;
  ku_ = ku;
  ab_.setZero(2 * kl + ku + 1, capacity);
  pivot_.assign(capacity, 0);
  n_ = 0;
}

void BandedLu::setZero(int n) {
  n_ = n;
  ab_.leftCols(n).setZero();
}

bool BandedLu::factor() {
  const int kv = kl_ + ku_;  // row of the diagonal in the band layout
  int ju = 0;                // last column touched by the row exchanges so far
  for (int j = 0; j < n_; ++j) {
    // Pivot: the largest entry of column j on or below the diagonal.
    const int km = std::min(kl_, n_ - 1 - j);
    int jp = 0;
    double best = std::abs(ab_(kv, j));
    for (int r = 1; r <= km; ++r) {
      if (std::abs(ab_(kv + r, j)) > best) {
        best = std::abs(ab_(kv + r, j));
        jp = r;
      }
    }
    pivot_[j] = j + jp;
    if (best == 0.0 || !std::isfinite(best)) return false;
    ju = std::max(ju, std::min(j + ku_ + jp, n_ - 1));
    // Exchange rows j and j + jp in columns j..ju.
    if (jp != 0) {
      for (int c = j; c <= ju; ++c) std::swap(ab_(kv + j - c, c), ab_(kv + j + jp - c, c));
    }
    // Multipliers, then the rank-one update of the trailing band.
    // (Column segments: contiguous in the band layout, so Eigen vectorizes
    // them; each entry sees the same operations as a scalar loop.)
    const double inv = 1.0 / ab_(kv, j);
    ab_.col(j).segment(kv + 1, km) *= inv;
    for (int c = j + 1; c <= ju; ++c) {
      const double u = ab_(kv + j - c, c);
      if (u == 0.0) continue;
      ab_.col(c).segment(kv + j + 1 - c, km) -= u * ab_.col(j).segment(kv + 1, km);
    }
  }
  return true;
}

void BandedLu::solve(Eigen::Ref<Eigen::VectorXd> b) const {
  const int kv = kl_ + ku_;
  // L y = P b, with the row exchanges applied as they were made.
  for (int j = 0; j + 1 < n_; ++j) {
    const int km = std::min(kl_, n_ - 1 - j);
    if (pivot_[j] != j) std::swap(b[j], b[pivot_[j]]);
    const double bj = b[j];
    if (bj == 0.0) continue;
    b.segment(j + 1, km) -= bj * ab_.col(j).segment(kv + 1, km);
  }
  // U x = y; U has kl + ku super-diagonals.
  for (int j = n_ - 1; j >= 0; --j) {
    b[j] /= ab_(kv, j);
    const double bj = b[j];
    if (bj == 0.0) continue;
    const int r0 = std::max(0, j - kv);
    b.segment(r0, j - r0) -= bj * ab_.col(j).segment(kv + r0 - j, j - r0);
  }
}

}  // namespace cws
