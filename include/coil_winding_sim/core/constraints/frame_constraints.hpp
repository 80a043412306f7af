// The unit-quaternion constraint (4), the rotational constraint (5) and,
// with a wire supply, the port constraint (22), stabilized with Baumgarte's
// method (6) and solved together with the equations of motion (2).
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
//
// The port constraint keeps the supply port p_s on the line of the last
// segment: (p_L - p_s) . xi_L = 0 and (p_L - p_s) . eta_L = 0 for the last
// point L (the paper's boundary segment lies on that line, eq. 21). Its two
// rows touch only block L; they border the block system and are solved by a
// 2x2 Schur complement within one O(n) block solve.
//
// Planar scenes hold every point in the plane normal to the core axis n.
// That linear constraint enters as the points' inverse mass (1/M) P with
// P = I - n n^T: forces and constraint reactions move a point only in the
// plane, and the frame constraints are solved for that motion, so the
// reaction that keeps zeta along an in-plane segment acts on the frame too
// (removing the out-of-plane acceleration after the solve would leave the
// frames' share of it unbalanced). The frames likewise turn about n only:
// their inverse mass is (1/4I) Q, Q projecting the quaternion rates onto
// scaling q and turning it about n, so that a frame's turn about its own
// tangent, which nothing stiffens when torsion is off, cannot grow from
// rounding (docs/MODEL.md, "Planar mode"). With both, each frame's two direction rows
// reduce to one, d . (n x zeta) = 0: d . n is zero by construction and is
// kept as a zero row with multiplier 0. Every integrator's update of q is a
// sum of such rates, so zeta stays in the plane to rounding.
#pragma once

#include <vector>

#include "coil_winding_sim/core/base/quaternion.hpp"
#include "coil_winding_sim/core/base/wire_types.hpp"

namespace cws {

struct PlanarState;
class PlanarAssembly;
struct SpatialState;
class SpatialAssembly;
struct PortMotion;

// The 3-D implicit formulation's frame constraints for frames first..n-1,
// held exactly by the multipliers s.mu(1..2, i) (frame_constraints_spatial.cpp):
// (5) (p_i - p_{i-1}) . (xi_i, eta_i) = 0, rows scaled by scale_direction
// [N/m]; their forces mu . dc/dx and the derivatives of those. (4), the
// unit norm, holds by construction: Newton turns the frames (SpatialAssembly).
void addSpatialFrameConstraints(const SpatialState& s, double scale_direction, SpatialAssembly& a);

// The port constraint (22) of a Newton step with a supply, the port at
// `port` (port_constraint.cpp): in the plane g = cross(u, x_L - p_s) = 0
// (u the last segment's direction), in 3-D (p_L - p_s) . (xi_L, eta_L) =
// 0, held by the multipliers s.lambda_port. Adds their forces lambda
// dg/dx, the moving port's work on the wire, the rows -scale g (scale
// [N/m]: a row in N, like the force rows, EA / l) and, with the Jacobian,
// their gradients and lambda's second-derivative blocks.
void addPlanarPortConstraint(const PlanarState& s, const PortMotion& port, double scale,
                             PlanarAssembly& a);
void addSpatialPortConstraint(const SpatialState& s, const PortMotion& port, double scale,
                              SpatialAssembly& a);

// Motion of the supply port [m], [m/s], [m/s^2], world frame.
struct PortMotion {
  Eigen::Vector3d p_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d a_world = Eigen::Vector3d::Zero();
};

class FrameConstraints {
 public:
  // plane_normal_world: unit normal of the plane the points keep, or zero
  // for 3-D motion.
  FrameConstraints(const WireConstants& c, double nu,
                   const Eigen::Vector3d& plane_normal_world = Eigen::Vector3d::Zero());

  // Accelerations of points first..n-1 [m/s^2] and their quaternion second
  // derivatives [1/s^2] from the generalized forces; point first-1 and its
  // frame follow the given prescribed accelerations (the clamp, or the end
  // of the wire the core carries). With `port` the last point is held on the
  // port line.
  void accelerations(const WireKinematics& k, const WireForces& f, const Eigen::Vector3d& a0_world,
                     const Eigen::Vector4d& qdd0, const PortMotion* port, Eigen::Matrix3Xd& a_world,
                     Eigen::Matrix4Xd& qdd);

  // Force [N] the constraints of the last accelerations() call exert on the
  // prescribed point first-1 (through frame first's rotational constraint).
  Eigen::Vector3d forceOnBoundary() const {
    return -a_blk_[c_.first].transpose() * lambda_[c_.first];
  }

  // Power [W] the moving port did on the wire in the last accelerations()
  // call (a constraint that moves does work).
  double portPower() const { return port_power_; }

  // Largest constraint residual over the integrated frames [-]: |q|^2 - 1, and the
  // sines of the angles between zeta_i and segment i-1 in the xi and eta
  // directions (d . xi / |d|).
  double maxResidual(const WireKinematics& k) const;

 private:
  // S x = rhs with the factorization of the last accelerations() call, in
  // two halves: forward elimination (in place), then back substitution.
  void forward(std::vector<Eigen::Vector3d>& rhs) const;
  void backward(const std::vector<Eigen::Vector3d>& rhs, std::vector<Eigen::Vector3d>& x) const;

  // Planar: the projector onto the quaternion rates that keep frame q
  // turning about the plane normal n only (and scale q): Q = q q^T + u u^T
  // with u = E(q)^T n, both normalized [-].
  Eigen::Matrix4d rotationAboutNormal(const quat::Vec4& q) const;
  // Row block r times P: r with its component along the plane normal removed.
  template <int Rows>
  Eigen::Matrix<double, Rows, 3> inPlane(const Eigen::Matrix<double, Rows, 3>& r) const {
    return r - (r * plane_normal_world_) * plane_normal_world_.transpose();
  }

  const WireConstants& c_;  // the model's: n grows with a supply
  double nu_;
  Eigen::Vector3d plane_normal_world_;  // zero: 3-D
  // Per frame i (index 0 unused), capacity long: Jacobian blocks, Schur
  // blocks and their factorization, right-hand sides and multipliers.
  // a_blk_ holds the point rows of the Jacobian, ap_blk_ the same times P.
  std::vector<Eigen::Matrix3d> a_blk_, ap_blk_, d_blk_, off_blk_, d_inv_, elim_;
  std::vector<quat::Mat34> b_blk_;
  std::vector<Eigen::Vector3d> gamma_, lambda_;
  double port_power_ = 0.0;
};

}  // namespace cws
