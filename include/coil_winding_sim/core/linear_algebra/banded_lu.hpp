// LU factorization with partial pivoting of a banded matrix (kl sub- and ku
// super-diagonals), in LAPACK's band layout: A(i, j) is stored at row
// kl + ku + i - j of column j, so that the fill-in of row exchanges (up to
// kl + ku super-diagonals) has room. Factor and solve cost O(n kl (kl + ku))
// and O(n (2 kl + ku)); storage is sized once for the largest n, and a
// matrix of any n up to it is factored without allocation.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace cws {

class BandedLu {
 public:
  BandedLu() = default;
  BandedLu(int capacity, int kl, int ku) { resize(capacity, kl, ku); }
  void resize(int capacity, int kl, int ku);

  int kl() const { return kl_; }
  int ku() const { return ku_; }
  // Starts a matrix of size n (<= capacity): all zero.
  void setZero(int n);
  // Entry (i, j) of the matrix before factoring; |i - j| within the band.
  double& at(int i, int j) { return ab_(kl_ + ku_ + i - j, j); }
  bool inBand(int i, int j) const { return i - j <= kl_ && j - i <= ku_; }
  // Factors in place; false if a pivot is exactly zero (singular).
  bool factor();
  // Solves A x = b in place (b holds n components).
  void solve(Eigen::Ref<Eigen::VectorXd> b) const;

 private:
  int kl_ = 0, ku_ = 0, n_ = 0;
  Eigen::MatrixXd ab_;  // (2 kl + ku + 1) x capacity
  std::vector<int> pivot_;
};

}  // namespace cws
