// The planar implicit formulation's view of the wire (its trial state) and
// the Newton system every effect adds its forces and Jacobian blocks to.
//
// In a planar scene (physics.planar) every frame stays tied to its segment
// and turns about the plane normal n only, so the positions alone describe
// the wire: each integrated point has two coordinates in the plane. The
// frames follow from the segments (frame i >= 1 belongs to segment i-1), and
// the prescribed point first-1 (the clamp, or the boundary of the wire the
// core carries) brings its own frame, whose tangent enters the bending of
// the first joint. docs/MODEL.md ("Implicit integration") derives the system.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "coil_winding_sim/core/assembly/one_leg_step.hpp"
#include "coil_winding_sim/core/linear_algebra/block_tridiagonal_lu.hpp"

namespace cws {

// An orthonormal basis of the plane, e1 x e2 = n: world <-> plane coordinates.
struct PlaneBasis {
  Eigen::Vector3d origin_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d e1_world = Eigen::Vector3d::UnitX();
  Eigen::Vector3d e2_world = Eigen::Vector3d::UnitY();
  Eigen::Vector3d n_world = Eigen::Vector3d::UnitZ();

  // The plane through origin_world normal to n_world (need not be unit).
  static PlaneBasis through(const Eigen::Vector3d& origin_world, const Eigen::Vector3d& n_world);
  Eigen::Vector2d toPlane(const Eigen::Vector3d& p_world) const {
    const Eigen::Vector3d d = p_world - origin_world;
    return {d.dot(e1_world), d.dot(e2_world)};
  }
  Eigen::Vector2d vectorToPlane(const Eigen::Vector3d& v_world) const {
    return {v_world.dot(e1_world), v_world.dot(e2_world)};
  }
  Eigen::Vector3d toWorld(const Eigen::Vector2d& x) const {
    return origin_world + x.x() * e1_world + x.y() * e2_world;
  }
  Eigen::Vector3d vectorToWorld(const Eigen::Vector2d& v) const {
    return v.x() * e1_world + v.y() * e2_world;
  }
};

// Plane geometry of a segment vector d: its angle phi about n and the
// derivatives of phi.
namespace planar {
// n x d: d turned by +90 degrees.
inline Eigen::Vector2d perp(const Eigen::Vector2d& d) { return {-d.y(), d.x()}; }
inline double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}
// The matrix of perp().
inline Eigen::Matrix2d perpMatrix() {
  Eigen::Matrix2d r;
  r << 0.0, -1.0, 1.0, 0.0;
  return r;
}
// d phi / d d [1/m].
inline Eigen::Vector2d angleGradient(const Eigen::Vector2d& d) { return perp(d) / d.squaredNorm(); }
// d^2 phi / d d^2 [1/m^2] (symmetric).
inline Eigen::Matrix2d angleHessian(const Eigen::Vector2d& d) {
  const double r4 = d.squaredNorm() * d.squaredNorm();
  Eigen::Matrix2d h;
  h << 2.0 * d.x() * d.y(), d.y() * d.y() - d.x() * d.x(), d.y() * d.y() - d.x() * d.x(),
      -2.0 * d.x() * d.y();
  return h / r4;
}
// The angle from direction a to direction b, in (-pi, pi] [rad].
inline double turn(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return std::atan2(cross(a, b), a.dot(b));
}
// What a joint needs of one of its two frames' segments, worked out once per
// segment: its unit tangent and the derivatives of its angle. A prescribed
// frame has a tangent and no unknowns (zero derivatives).
struct SegmentGeometry {
  Eigen::Vector2d tangent = Eigen::Vector2d::UnitX();
  Eigen::Vector2d gradient = Eigen::Vector2d::Zero();  // d phi / d d [1/m]
  Eigen::Matrix2d hessian = Eigen::Matrix2d::Zero();   // [1/m^2]

  void set(const Eigen::Vector2d& d, bool with_hessian) {
    const double l2 = d.squaredNorm();
    tangent = d / std::sqrt(l2);
    gradient = perp(d) / l2;
    if (with_hessian) hessian = angleHessian(d);
  }
  void setPrescribed(const Eigen::Vector2d& unit_tangent) {
    tangent = unit_tangent;
    gradient.setZero();
    hessian.setZero();
  }
};
// Curvature of the joint from frame a to frame b over the joint length
// lambda [1/m], with the sine and cosine of half its turn angle, from the
// tangents' dot and cross products (no trigonometry): cos(dphi / 2) =
// sqrt((1 + c) / 2) for |dphi| < pi.
inline double jointCurvature(const SegmentGeometry& a, const SegmentGeometry& b, double lambda,
                             double& sin_half, double& cos_half) {
  const double c = a.tangent.dot(b.tangent), sn = cross(a.tangent, b.tangent);
  cos_half = std::sqrt(std::max(0.0, 0.5 * (1.0 + c)));
  sin_half = cos_half > 0.0 ? 0.5 * sn / cos_half : 1.0;
  return (2.0 / lambda) * sin_half;
}
}  // namespace planar

// Trial state at the end of an implicit step.
struct PlanarState {
  double t = 0.0;      // time at the step's end [s]
  double dt = 0.0;     // the step's length [s]
  double alpha = 0.0;  // d v / d x of the scheme [1/s]: v = alpha (x - x_hat)
  int first = 1;       // integrated points first..n-1; point first-1 is prescribed
  int n = 0;
  Eigen::Matrix2Xd x;  // plane coordinates of every point [m] (capacity columns)
  Eigen::Matrix2Xd v;  // [m/s]
  // Unit tangent of the prescribed frame first-1 (the clamp's, or the
  // carried wire's last) in the plane, and its angular velocity [rad/s].
  Eigen::Vector2d boundary_tangent = Eigen::Vector2d::UnitX();
  double boundary_omega = 0.0;
  double lambda_port = 0.0;  // port constraint multiplier [N]
  CarriedRate carried;       // the scheme velocity of the core's material
  // The plane normal in the frames' material axes (xi, eta, zeta): the
  // same for every frame of a planar wire, so a bend about n is the
  // curvature vector kappa n_material.
  Eigen::Vector3d n_material = Eigen::Vector3d::UnitX();
  PlaneBasis plane;
  // The solve's last rounds (NewtonSettings::return_mapping_round): each two-line
  // law takes the line its strain lies on at every evaluation.
  bool return_mapping = false;

  Eigen::Vector2d segment(int j) const { return x.col(j + 1) - x.col(j); }
  // (The planar system is factored whole after a flag change.)
  void flagChangedAt(int) const {}
};

// The Newton system of one implicit step over the integrated points'
// coordinates (2 per point, from point first on) and, with a supply, the port
// constraint's multiplier (last unknown). Effects add forces and their
// derivatives; entries of the prescribed point are booked apart (the work
// the clamp does) and leave the matrix. The matrix holds
//   -(d F / d x + alpha d F / d v)
// to which the formulation adds the inertia alpha^2 M; the constraint row
// holds -scale g(x) and its gradient.
class PlanarAssembly {
 public:
  // Storage for up to `capacity_points` points (once, before a run).
  void resize(int capacity_points);
  // Starts the system of points first..n-1 (with a multiplier if asked);
  // `jacobian` false: forces only (line search, bookkeeping).
  void begin(int first, int n, bool multiplier, bool jacobian, double alpha);

  bool wantsJacobian() const { return jacobian_; }
  // (As SpatialAssembly's: the plane assembles every row.)
  bool wantsJacobianAt(int) const { return jacobian_; }
  int unknowns() const { return unknowns_; }
  int first() const { return first_; }
  bool integrated(int i) const { return i >= first_; }
  int dof(int i) const { return 2 * (i - first_); }
  int multiplierRow() const { return unknowns_ - 1; }

  // Force on point i [N]; on the prescribed point it is booked as what the
  // wire does to the clamp.
  void addForce(int i, const Eigen::Vector2d& f) {
    if (i >= first_) {
      force_.segment<2>(dof(i)) += f;
    } else if (i == first_ - 1) {
      boundary_force += f;
    }
  }
  // d f_i / d x_j [N/m], and d f_i / d v_j [N s/m].
  void addStiffness(int i, int j, const Eigen::Matrix2d& k) { addBlock(i, j, -k); }
  void addDamping(int i, int j, const Eigen::Matrix2d& d) { addBlock(i, j, -alpha_ * d); }
  // Constraint: its scaled residual -scale g and gradient dg/dx_i; the
  // multiplier's force lambda dg/dx_i is added by the effect itself.
  void setConstraint(double g, double scale) {
    constraint_scale_ = scale;
    force_[multiplierRow()] = -scale * g;
  }
  void addConstraintGradient(int i, const Eigen::Vector2d& grad);

  // Forces on the integrated dofs [N] (and the scaled constraint residual).
  Eigen::VectorXd& forces() { return force_; }
  const Eigen::VectorXd& forces() const { return force_; }
  // Block-tridiagonal in blocks of two points' coordinates: bending
  // couples points two apart, which lie in the same or adjacent pairs; the
  // port's multiplier row, last, couples the last two points.
  using Matrix = BlockTridiagonalLu<4>;
  Matrix& matrix() { return matrix_; }

  // Bookkeeping at the trial state, as WireForces does for the explicit
  // model: rates not paired with the wire's velocities, and the forces that
  // are (applied loads do work, friction and damping dissipate).
  double power_external = 0.0;             // [W]
  double power_dissipated = 0.0;           // [W]
  Eigen::Matrix2Xd f_work, f_dissipative;  // per point [N] (capacity)
  // What the wire's effects do to the prescribed point and its frame: a
  // force [N] and a moment about n [N m] (the clamp's work).
  Eigen::Vector2d boundary_force = Eigen::Vector2d::Zero();
  double boundary_torque = 0.0;
  // Generalized moment on the prescribed frame's angle, added by bending.
  void addBoundaryTorque(double m) { boundary_torque += m; }

 private:
  void addBlock(int i, int j, const Eigen::Matrix2d& b) {
    if (!jacobian_ || i < first_ || j < first_) return;
    // A point's two coordinates start at an even row, so its 2 x 2 block
    // lies within one of the matrix's 4 x 4 blocks.
    const int r = dof(i), c = dof(j);
    matrix_.blockAt(r >> 2, c >> 2).block<2, 2>(r & 3, c & 3) += b;
  }

  int first_ = 1, n_ = 0, unknowns_ = 0;
  bool jacobian_ = false;
  double alpha_ = 0.0;
  double constraint_scale_ = 1.0;
  Eigen::VectorXd force_;
  Matrix matrix_;
};

}  // namespace cws
