// The Newton system's couplings outside the band (contact between two free
// segments, SpatialAssembly::PairCoupling), solved over the band's
// factorization through the Woodbury identity:
//   (A + U K U^T)^-1 b = y - A^-1 U z,  y = A^-1 b,
//   (I + K U^T A^-1 U) z = K U^T y,
// with three columns of U per pair (U_p = C_p^T) and K block-diagonal (the
// pairs' 3 x 3 blocks, which need not be invertible). A factorization
// solves the band for a pair's three columns at once and keeps only the
// rows of A^-1 U that the pairs read (the small matrix S); a solve is one
// small solve and one more band solve, of U z. Storage is sized for the
// integrated span and the pairs SpatialAssembly reserves, and grows with
// them (every touching pair is solved: spatial_assembly.hpp).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "coil_winding_sim/core/assembly/spatial_assembly.hpp"

namespace cws {

class PairCouplingSolve {
 public:
  // Storage for systems of `unknowns` unknowns; a larger system grows it
  // (factor), as SpatialAssembly's blocks grow with the integrated span.
  void resize(int unknowns);
  // After the assembly's band matrix is factored: takes its pair couplings
  // (none: nothing to do). False if the small system is singular.
  bool factor(SpatialAssembly& a);
  // x holds A^-1 b (the band's solve): makes it the full system's solution.
  void correct(const SpatialAssembly& a, Eigen::Ref<Eigen::VectorXd> x) const;
  int pairs() const { return m_; }

 private:
  using Columns = Eigen::Matrix<double, Eigen::Dynamic, 3>;
  // C_p v for the unknowns v of pair p (rows of its points' positions), for
  // one column or three.
  template <class V>
  Eigen::Matrix<double, 3, V::ColsAtCompileTime> relative(const SpatialAssembly& a, int p,
                                                          const V& v) const;
  // v += C_p^T z (v: one column or three): U's columns of pair p, times z.
  template <class V, class Z>
  void scatter(const SpatialAssembly& a, int p, const Z& z, V& v) const;

  // The LU of S's first n rows and columns in place (pivot_); false if
  // singular.
  static constexpr int kPanel = 32;
  bool factorSmall(int n);

  // Storage for systems of `unknowns` unknowns and `pairs` pairs at least
  // (twice what it holds, where that is more).
  void grow(int unknowns, int pairs);

  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  int m_ = 0;
  std::vector<SpatialAssembly::PairCoupling,
              Eigen::aligned_allocator<SpatialAssembly::PairCoupling>>
      pairs_;
  Columns w_;   // A^-1 U_p of one pair at a time (the band's padded rows)
  RowMajor s_;  // I + K U^T A^-1 U, LU in place (rows contiguous for its updates)
  std::vector<int> pivot_;
  mutable Eigen::VectorXd g_, r_;
};

}  // namespace cws
