// The 3-D implicit formulation's view of the wire (its trial state) and the
// Newton system every effect adds its forces and Jacobian blocks to.
//
// A 3-D wire keeps the explicit model's state: per integrated point i its
// position p_i and the quaternion q_i of frame i. Newton's unknowns for a
// frame are a rotation dtheta_i in its own axes (q_i moves along
// dq/dtheta = G(q_i)^T / 2 and stays of unit norm, constraint (4)); the
// constraint (5), zeta_i along segment i-1, is held exactly by two
// Lagrange multipliers per frame, and with a supply the port constraint by
// its two. The effects' generalized forces are the explicit model's (forces
// on p, generalized forces on q) with their derivatives; the assembly
// projects those on q onto the rotations (finish()). docs/MODEL.md
// ("Implicit integration of 3-D scenes") derives the system.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <vector>

#include "coil_winding_sim/core/assembly/one_leg_step.hpp"
#include "coil_winding_sim/core/linear_algebra/block_tridiagonal_lu.hpp"

namespace cws {

// Trial state at the end of an implicit step (capacity columns; point
// first-1 is prescribed: the clamp, or the boundary of the carried wire).
struct SpatialState {
  double t = 0.0;      // time at the step's end [s]
  double dt = 0.0;     // the step's length [s]
  double alpha = 0.0;  // d v / d x of the scheme [1/s]: v = alpha (x - x_hat)
  int first = 1;       // integrated points first..n-1
  int n = 0;
  Eigen::Matrix3Xd p, v;   // positions [m], velocities [m/s], world frame
  Eigen::Matrix4Xd q, qd;  // frames (scalar first) and their rates [1/s]
  Eigen::Matrix3Xd mu;     // frame constraint multipliers, per frame i >= first
  Eigen::Vector2d lambda_port = Eigen::Vector2d::Zero();  // port constraint multipliers [N]
  CarriedRate carried;  // the scheme velocity of the core's material
  // The highest point whose blocks a flag recheck changed (-1: none): the
  // factorization is made again from there to the first point only.
  mutable int changed_top = -1;
  // The solve's last rounds (NewtonSettings::return_mapping_round): each two-line
  // law takes the line its strain lies on at every evaluation.
  bool return_mapping = false;

  Eigen::Vector3d segment(int j) const { return p.col(j + 1) - p.col(j); }
  void flagChangedAt(int i) const { changed_top = std::max(changed_top, i); }
};

// The Newton system over the integrated points' unknowns, in blocks of
// kPerPoint per point: the rotation of frame i, then p_i, then the frame's
// two multipliers;
// with a supply the port's two multipliers last. Every effect couples a
// point only to its neighbours, so the matrix is block-tridiagonal, one
// block per point (the port's rows a block of their own); frame i's
// multipliers act on p_i-1, p_i and frame i only, so a block couples to the next
// through its first kCoupled unknowns (BlockTridiagonalLu's C). The matrix holds
//   -(d F / d x + alpha d F / d v)
// to which the formulation adds the inertia; a constraint row holds
// -scale g and -scale dg/dx, and the multiplier's column -dg/dx (the
// constraint's force mu dg/dx is added by whoever owns the constraint).
class SpatialAssembly {
 public:
  static constexpr int kPerPoint = 8;
  static constexpr int kQ = 0, kP = 3, kMu = 6;  // offsets in a point's block
  static constexpr int kCoupled = 6;             // the rotation and p
  static constexpr int kMultipliers = 2;         // per frame: zeta along the segment
  // The frames' tangent bases dq/dtheta = G(q)^T / 2 (4 x 3) from the trial
  // quaternions of points first..n-1 (unit): the effects' generalized
  // forces and blocks on q are projected with them.
  void setFrames(const Eigen::Matrix4Xd& q, int first, int n);
  const Eigen::Matrix<double, 4, 3>& frameBasis(int i) const { return basis_[i]; }
  // q_i . (the generalized forces added on q_i): their part along q_i,
  // which the projection drops.
  double radialForce(int i) const { return radial_[i]; }
  // Projects what the effects added on q (forces and blocks, kept in the
  // quaternion's coordinates while they add) onto the frames' rotations.
  void finish();
  // Storage for up to `capacity_points` points (once, before a run). The
  // system's rows and the Jacobian's blocks, which only the integrated
  // points use, are sized for kReservedSpan of them (fewer if the capacity
  // is less); a longer integrated span grows them (begin), which a coil
  // meets only when wound wire is released over many turns.
  static constexpr int kReservedSpan = 1024;
  void resize(int capacity_points);
  // Starts the system of points first..n-1 (with the port's multipliers if
  // asked); `jacobian` false: forces only. jacobian_top >= first: only the
  // Jacobian's rows of points first..jacobian_top are wanted (a flag
  // round's factorization keeps the later rows' factors).
  void begin(int first, int n, bool port, bool jacobian, double alpha, int jacobian_top = -1);

  // The system's size for points first..n-1 (and the port's rows).
  static int unknownsFor(int first, int n, bool port) {
    return kPerPoint * (n - first) + (port ? 2 : 0);
  }
  bool wantsJacobian() const { return jacobian_; }
  // Whether an element whose lowest point is i adds to a wanted row.
  bool wantsJacobianAt(int i) const { return jacobian_ && i <= jacobian_top_; }
  // The last point whose rows were assembled (n-1: all).
  int jacobianTop() const { return jacobian_top_; }
  int unknowns() const { return unknowns_; }
  int first() const { return first_; }
  int blockRow(int i) const { return kPerPoint * (i - first_); }
  int muRow(int i) const { return blockRow(i) + kMu; }
  int pRow(int i) const { return blockRow(i) + kP; }
  int qRow(int i) const { return blockRow(i) + kQ; }
  int portRow() const { return unknowns_ - 2; }

  // Force on point i [N] and generalized force on its quaternion [N m]; on
  // the prescribed point first-1 they are booked as what the wire does to
  // the clamp.
  void addForce(int i, const Eigen::Vector3d& f) {
    if (i >= first_) {
      force_.segment<3>(pRow(i)) += f;
    } else if (i == first_ - 1) {
      boundary_force += f;
    }
  }
  void addQForce(int i, const Eigen::Vector4d& f) {
    if (i >= first_) {
      fq4_.col(i) += f;
    } else if (i == first_ - 1) {
      boundary_fq += f;
    }
  }
  // d f_i / d x_j (x: p or q of point j) and d f_i / d xdot_j.
  void addStiffnessPP(int i, int j, const Eigen::Matrix3d& k) { block(i, kP, j, kP, -k); }
  // The same by the planar assembly's name (code shared by both).
  void addStiffness(int i, int j, const Eigen::Matrix3d& k) { addStiffnessPP(i, j, k); }
  void addStiffnessPQ(int i, int j, const Eigen::Matrix<double, 3, 4>& k) {
    if (wanted(i, j)) kpq_[slot(i, j)] -= k;
  }
  void addStiffnessQP(int i, int j, const Eigen::Matrix<double, 4, 3>& k) {
    if (wanted(i, j)) kqp_[slot(i, j)] -= k;
  }
  void addStiffnessQQ(int i, int j, const Eigen::Matrix4d& k) {
    if (wanted(i, j)) kqq_[slot(i, j)] -= k;
  }
  void addDampingPP(int i, int j, const Eigen::Matrix3d& d) { block(i, kP, j, kP, -alpha_ * d); }
  void addDampingQQ(int i, int j, const Eigen::Matrix4d& d) {
    if (wanted(i, j)) kqq_[slot(i, j)] -= alpha_ * d;
  }

  // Constraint row `row` (a frame's or the port's): its scaled residual.
  // (Inline, as the other adders: every evaluation makes a few per point.)
  void setConstraint(int row, double g, double scale) {
    scale_[row] = scale;
    force_[row] = -scale * g;
  }
  // Its gradient with respect to p_i or q_i (nothing for the prescribed point).
  void addConstraintGradientP(int row, int i, const Eigen::Vector3d& grad) {
    if (!jacobian_ || i < first_) return;
    addConstraintColumns(row, pRow(i), grad);
  }
  void addConstraintGradientQ(int row, int i, const Eigen::Vector4d& grad_q) {
    if (!jacobian_ || i < first_) return;
    addConstraintColumns(row, qRow(i), basis_[i].transpose() * grad_q);
  }

  // A coupling outside the band (contact between two free segments,
  // free_wire_contact.hpp): the Jacobian term C^T k C, where C x = p_a -
  // (1 - t) p_b - t p_b+1 is the point's position relative to the segment's
  // point, and k [N/m] is the block in that relative position as the matrix
  // holds it (-(dF/dx + alpha dF/dv)). Solved through the Woodbury identity
  // (pair_coupling_solve.hpp). Every touching pair is kept: with the 40 of
  // an earlier cap, wire released onto free wire (50-90 pairs) left the
  // rest to the iteration, which then converged only at steps below the
  // contact spring's period (docs/history/2026-11-29-every-pair-in-the-jacobian.md).
  // Room for kReservedPairCouplings, grown on demand.
  struct PairCoupling {
    int a = 0, b = 0;
    double t = 0.0;
    Eigen::Matrix3d k = Eigen::Matrix3d::Zero();
  };
  static constexpr int kReservedPairCouplings = 40;
  void addPairCoupling(int a, int b, double t, const Eigen::Matrix3d& k) {
    if (!jacobian_) return;
    if (pair_count_ == static_cast<int>(pairs_.size())) pairs_.resize(2 * pairs_.size());
    pairs_[pair_count_++] = PairCoupling{a, b, t, k};
  }
  int pairCouplings() const { return pair_count_; }
  const PairCoupling& pairCoupling(int x) const { return pairs_[x]; }

  Eigen::VectorXd& forces() { return force_; }
  const Eigen::VectorXd& forces() const { return force_; }
  using Matrix = BlockTridiagonalLu<kPerPoint, kCoupled>;
  Matrix& matrix() { return matrix_; }
  const Matrix& matrix() const { return matrix_; }

  // Bookkeeping at the trial state, as WireForces does for the explicit
  // model: rates not paired with the wire's velocities, and the forces that
  // are (applied loads do work, friction and damping dissipate).
  double power_external = 0.0;               // [W]
  double power_dissipated = 0.0;             // [W]
  Eigen::Matrix3Xd f_work, f_dissipative;    // per point [N] (capacity)
  Eigen::Matrix4Xd fq_work, fq_dissipative;  // per frame [N m]
  // What the effects do to the prescribed point and its frame.
  Eigen::Vector3d boundary_force = Eigen::Vector3d::Zero();
  Eigen::Vector4d boundary_fq = Eigen::Vector4d::Zero();

 private:
  // Whether matrix row r belongs to a wanted point's rows (the port's rows
  // follow the last point's).
  bool rowWanted(int r) const { return r / kPerPoint + first_ <= jacobian_top_; }
  // (Relative to the first integrated point: the blocks cover the span.)
  int slot(int i, int j) const { return 3 * (i - first_) + (j - i + 1); }
  // Rows and Jacobian storage for `points` integrated points at least.
  void reserveSpan(int points);
  // Constraint row `row`'s gradient on the unknowns c..c+2 (one point's p
  // or rotation): the row's entries, scaled, and the multiplier's column.
  void addConstraintColumns(int row, int c, const Eigen::Vector3d& grad) {
    // The three unknowns from column c lie in one block: the row's entries,
    // and the multiplier's column in those unknowns' rows.
    const int br = row / kPerPoint, ro = row % kPerPoint;
    const int bc = c / kPerPoint, co = c % kPerPoint;
    if (rowWanted(row)) {
      matrix_.blockAt(br, bc).template block<1, 3>(ro, co) -= scale_[row] * grad.transpose();
    }
    if (rowWanted(c)) matrix_.blockAt(bc, br).template block<3, 1>(co, ro) -= grad;
  }
  bool wanted(int i, int j) const {
    return jacobian_ && i >= first_ && j >= first_ && i <= jacobian_top_;
  }
  // Adds b at the rows of point i from offset `row` and the columns of
  // point j from offset `col`; nothing for the prescribed point.
  template <class Derived>
  void block(int i, int row, int j, int col, const Eigen::MatrixBase<Derived>& b) {
    if (!jacobian_ || i < first_ || j < first_ || i > jacobian_top_) return;
    matrix_.blockAt(i - first_, j - first_)
        .template block<Derived::RowsAtCompileTime, Derived::ColsAtCompileTime>(row, col) += b;
  }

  std::vector<PairCoupling, Eigen::aligned_allocator<PairCoupling>> pairs_ =
      std::vector<PairCoupling, Eigen::aligned_allocator<PairCoupling>>(kReservedPairCouplings);
  int pair_count_ = 0;
  int first_ = 1, n_ = 0, unknowns_ = 0, jacobian_top_ = -1;
  bool jacobian_ = false;
  double alpha_ = 0.0;
  Eigen::VectorXd force_, scale_;  // scale_: each constraint row's
  std::vector<Eigen::Matrix<double, 4, 3>, Eigen::aligned_allocator<Eigen::Matrix<double, 4, 3>>>
      basis_;
  std::vector<Eigen::Vector4d, Eigen::aligned_allocator<Eigen::Vector4d>> q_;
  Eigen::VectorXd radial_;
  // What the effects add on q before finish() projects it.
  Eigen::Matrix4Xd fq4_;
  std::vector<Eigen::Matrix4d, Eigen::aligned_allocator<Eigen::Matrix4d>> kqq_;
  std::vector<Eigen::Matrix<double, 3, 4>, Eigen::aligned_allocator<Eigen::Matrix<double, 3, 4>>>
      kpq_;
  std::vector<Eigen::Matrix<double, 4, 3>, Eigen::aligned_allocator<Eigen::Matrix<double, 4, 3>>>
      kqp_;
  Matrix matrix_;
};

}  // namespace cws
