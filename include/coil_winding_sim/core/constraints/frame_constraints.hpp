// The unit-quaternion constraint (4) and the rotational constraint (5),
// stabilized with Baumgarte's method (6) and solved together with the
// equations of motion (2).
//
// Generalized coordinates are the point positions p_i (mass M) and the
// quaternions q_i (mass 4 I, I = 2/5 M r^2: on |q| = 1 the kinetic energy
// 2 I |qdot|^2 equals I |omega|^2 / 2). For frame i >= 1 the constraints are
//   c_i = ( |q_i|^2 - 1,  (p_i - p_{i-1}) . xi_i,  (p_i - p_{i-1}) . eta_i ).
// Each RHS evaluation solves  J M^-1 J^T lambda = gamma  with
//   gamma = -Jdot v - 2 nu cdot - nu^2 c - J M^-1 f,
// so that  cddot + 2 nu cdot + nu^2 c = 0  holds exactly at acceleration
// level. Constraint i touches p_{i-1}, p_i and q_i only, so J M^-1 J^T is
// block tridiagonal (3x3 blocks) and the solve costs O(n) with no allocation.
#pragma once

#include <vector>

#include "coil_winding_sim/core/quaternion.hpp"
#include "coil_winding_sim/core/wire_types.hpp"

namespace cws {

class FrameConstraints {
 public:
  FrameConstraints(const WireConstants& c, double nu);

  // Accelerations of all points [m/s^2] and quaternion second derivatives
  // [1/s^2] from the generalized forces; point 0 and frame 0 follow the given
  // prescribed accelerations (the clamp).
  void accelerations(const WireKinematics& k, const WireForces& f, const Eigen::Vector3d& a0_world,
                     const Eigen::Vector4d& qdd0, Eigen::Matrix3Xd& a_world, Eigen::Matrix4Xd& qdd);

  // Largest constraint residual over all frames [-]: |q|^2 - 1, and the
  // sines of the angles between zeta_i and segment i-1 in the xi and eta
  // directions (d . xi / |d|).
  double maxResidual(const WireKinematics& k) const;

 private:
  WireConstants c_;
  double nu_;
  // Per frame i (index 0 unused): Jacobian blocks, Schur-complement blocks,
  // right-hand side and multipliers.
  std::vector<Eigen::Matrix3d> a_blk_, d_blk_, off_blk_, d_inv_;
  std::vector<quat::Mat34> b_blk_;
  std::vector<Eigen::Vector3d> gamma_, lambda_;
};

}  // namespace cws
