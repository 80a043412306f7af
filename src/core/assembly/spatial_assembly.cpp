#include "coil_winding_sim/core/assembly/spatial_assembly.hpp"

#include <algorithm>

#include "coil_winding_sim/core/base/quaternion.hpp"

namespace cws {

void SpatialAssembly::resize(int capacity_points) {
  f_work.setZero(3, capacity_points);
  f_dissipative.setZero(3, capacity_points);
  fq_work.setZero(4, capacity_points);
  fq_dissipative.setZero(4, capacity_points);
  // Every coupling is between a point's block and its neighbours' (bending
  // and stretching j to j+1, a frame's rows to p_i-1); the port's two rows
  // form a block of their own after the last point's.
  basis_.assign(capacity_points, Eigen::Matrix<double, 4, 3>::Zero());
  q_.assign(capacity_points, Eigen::Vector4d::Zero());
  radial_.setZero(capacity_points);
  fq4_.setZero(4, capacity_points);
  force_.resize(0);
  scale_.resize(0);
  kqq_.clear();
  kpq_.clear();
  kqp_.clear();
  reserveSpan(std::min(capacity_points, kReservedSpan));
}

void SpatialAssembly::reserveSpan(int points) {
  const int unknowns = kPerPoint * points + 2;
  matrix_.reserve(unknowns);
  if (unknowns > force_.size()) {
    const Eigen::Index grown = std::max<Eigen::Index>(unknowns, 2 * force_.size());
    force_.setZero(grown);
    scale_.setOnes(grown);
  }
  if (3 * points <= static_cast<int>(kqq_.size())) return;
  const std::size_t slots =
      static_cast<std::size_t>(3 * std::max(points, 2 * static_cast<int>(kqq_.size() / 3)));
  kqq_.assign(slots, Eigen::Matrix4d::Zero());
  kpq_.assign(slots, Eigen::Matrix<double, 3, 4>::Zero());
  kqp_.assign(slots, Eigen::Matrix<double, 4, 3>::Zero());
}

void SpatialAssembly::finish() {
  for (int i = first_; i < n_; ++i) {
    const Eigen::Vector4d f = fq4_.col(i);
    force_.segment<3>(qRow(i)) += basis_[i].transpose() * f;
    radial_[i] = q_[i].dot(f);
  }
  if (!jacobian_) return;
  const int top = std::min(n_ - 1, jacobian_top_);
  for (int i = first_; i <= top; ++i) {
    for (int j = std::max(first_, i - 1); j <= std::min(n_ - 1, i + 1); ++j) {
      const int k = slot(i, j);
      auto& b = matrix_.blockAt(i - first_, j - first_);
      b.template block<3, 3>(kQ, kQ) += basis_[i].transpose() * kqq_[k] * basis_[j];
      b.template block<3, 3>(kP, kQ) += kpq_[k] * basis_[j];
      b.template block<3, 3>(kQ, kP) += basis_[i].transpose() * kqp_[k];
    }
  }
}

void SpatialAssembly::setFrames(const Eigen::Matrix4Xd& q, int first, int n) {
  for (int i = first; i < n; ++i) {
    q_[i] = q.col(i);
    basis_[i] = 0.5 * quat::G(q_[i]).transpose();
  }
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
  reserveSpan(n - first);
  force_.head(unknowns_).setZero();
  fq4_.middleCols(first, n - first).setZero();
  if (jacobian) {
    const int top = std::min(n - 1, jacobian_top_);
    for (int k = 0; k < 3 * (top + 1 - first); ++k) {
      kqq_[k].setZero();
      kpq_[k].setZero();
      kqp_[k].setZero();
    }
  }
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

}  // namespace cws
