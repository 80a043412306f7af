#include "coil_winding_sim/core/implicit/spatial_assembly.hpp"

namespace cws {

void SpatialAssembly::resize(int capacity_points) {
  const int unknowns = kPerPoint * capacity_points + 2;
  force_.setZero(unknowns);
  scale_.setOnes(unknowns);
  f_work.setZero(3, capacity_points);
  f_dissipative.setZero(3, capacity_points);
  fq_work.setZero(4, capacity_points);
  fq_dissipative.setZero(4, capacity_points);
  // Every coupling is between a point's block and its neighbours' (bending
  // and stretching j to j+1, a frame's rows to p_i-1); the port's two rows
  // form a block of their own after the last point's.
  matrix_.resize(unknowns);
}

void SpatialAssembly::begin(int first, int n, bool port, bool jacobian, double alpha,
                            int jacobian_top) {
  first_ = first;
  n_ = n;
  unknowns_ = unknownsFor(first, n, port);
  jacobian_ = jacobian;
  const bool partial = jacobian_top >= first && jacobian_top < n - 1;
  jacobian_top_ = partial ? jacobian_top : n;  // (n: also the port's rows)
  alpha_ = alpha;
  force_.head(unknowns_).setZero();
  const int from = std::max(0, first - 1);
  f_work.middleCols(from, n - from).setZero();
  f_dissipative.middleCols(from, n - from).setZero();
  fq_work.middleCols(from, n - from).setZero();
  fq_dissipative.middleCols(from, n - from).setZero();
  power_external = 0.0;
  power_dissipated = 0.0;
  boundary_force.setZero();
  boundary_fq.setZero();
  if (jacobian_) {
    matrix_.setZero(unknowns_, port, partial ? jacobian_top - first : -1);
    pair_count_ = 0;
  }
}

void SpatialAssembly::setConstraint(int row, double g, double scale) {
  scale_[row] = scale;
  force_[row] = -scale * g;
}

void SpatialAssembly::addConstraintGradientP(int row, int i, const Eigen::Vector3d& grad) {
  if (!jacobian_ || i < first_) return;
  const int c = pRow(i);
  const bool row_wanted = rowWanted(row), col_wanted = rowWanted(c);
  for (int a = 0; a < 3; ++a) {
    if (row_wanted) matrix_.at(row, c + a) += -scale_[row] * grad[a];
    if (col_wanted) matrix_.at(c + a, row) += -grad[a];
  }
}

void SpatialAssembly::addConstraintGradientQ(int row, int i, const Eigen::Vector4d& grad) {
  if (!jacobian_ || i < first_) return;
  const int c = qRow(i);
  const bool row_wanted = rowWanted(row), col_wanted = rowWanted(c);
  for (int a = 0; a < 4; ++a) {
    if (row_wanted) matrix_.at(row, c + a) += -scale_[row] * grad[a];
    if (col_wanted) matrix_.at(c + a, row) += -grad[a];
  }
}

}  // namespace cws
