// The Newton system's couplings outside the band (contact between two free
// segments, SpatialAssembly::PairCoupling), solved over the band's
// factorization through the Woodbury identity:
//   (A + U K U^T)^-1 b = y - W z,  y = A^-1 b,  W = A^-1 U,
//   (I + K U^T W) z = K U^T y,
// with three columns of U per pair (U_p = C_p^T) and K block-diagonal (the
// pairs' 3 x 3 blocks, which need not be invertible). A factorization costs
// three band solves per pair and a dense LU of 3 x 3 blocks per pair; a
// solve, one small solve and a product. Storage is sized for the integrated
// span and the pairs SpatialAssembly reserves, and grows with them (every
// touching pair is solved: spatial_assembly.hpp).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "coil_winding_sim/core/implicit/spatial_assembly.hpp"

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
  // C_p v for the unknowns v of pair p (rows of its points' positions).
  Eigen::Vector3d relative(const SpatialAssembly& a, int p,
                           const Eigen::Ref<const Eigen::VectorXd>& v) const;

  // Storage for systems of `unknowns` unknowns and `pairs` pairs at least
  // (twice what it holds, where that is more).
  void grow(int unknowns, int pairs);

  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  int m_ = 0;
  std::vector<SpatialAssembly::PairCoupling,
              Eigen::aligned_allocator<SpatialAssembly::PairCoupling>>
      pairs_;
  Eigen::MatrixXd w_;  // A^-1 U, unknowns x 3 per pair
  RowMajor s_;         // I + K U^T W, LU in place (rows contiguous for its updates)
  std::vector<int> pivot_;
  mutable Eigen::VectorXd g_;
};

}  // namespace cws
