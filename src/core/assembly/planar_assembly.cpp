#include "coil_winding_sim/core/assembly/planar_assembly.hpp"

namespace cws {

PlaneBasis PlaneBasis::through(const Eigen::Vector3d& origin_world,
                               const Eigen::Vector3d& n_world) {
  PlaneBasis b;
  b.origin_world = origin_world;
  b.n_world = n_world.normalized();
  // e1: the world axis least parallel to n, made normal to it.
  Eigen::Vector3d ref = Eigen::Vector3d::UnitX();
  if (std::abs(b.n_world.x()) > 0.9) ref = Eigen::Vector3d::UnitY();
  b.e1_world = (ref - ref.dot(b.n_world) * b.n_world).normalized();
  b.e2_world = b.n_world.cross(b.e1_world);
  return b;
}

void PlanarAssembly::resize(int capacity_points) {
  const int unknowns = 2 * capacity_points + 1;
  force_.setZero(unknowns);
  f_work.setZero(2, capacity_points);
  f_dissipative.setZero(2, capacity_points);
  matrix_.resize(unknowns);
}

void PlanarAssembly::begin(int first, int n, bool multiplier, bool jacobian, double alpha) {
  first_ = first;
  n_ = n;
  unknowns_ = 2 * (n - first) + (multiplier ? 1 : 0);
  jacobian_ = jacobian;
  alpha_ = alpha;
  force_.head(unknowns_).setZero();
  const int from = std::max(0, first - 1);
  f_work.middleCols(from, n - from).setZero();
  f_dissipative.middleCols(from, n - from).setZero();
  power_external = 0.0;
  power_dissipated = 0.0;
  boundary_force.setZero();
  boundary_torque = 0.0;
  // The multiplier's row has a zero diagonal: its block is inverted
  // together with the one before it.
  if (jacobian_) matrix_.setZero(unknowns_, multiplier);
}

void PlanarAssembly::addConstraintGradient(int i, const Eigen::Vector2d& grad) {
  if (!jacobian_ || i < first_) return;
  const int m = multiplierRow(), c = dof(i);
  for (int a = 0; a < 2; ++a) {
    // Row of the constraint: d(-scale g)/dx; column of the multiplier:
    // d(-F)/d lambda = -dg/dx.
    matrix_.at(m, c + a) += -constraint_scale_ * grad[a];
    matrix_.at(c + a, m) += -grad[a];
  }
}

}  // namespace cws
