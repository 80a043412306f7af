#include "coil_winding_sim/core/constraints/frame_constraints.hpp"

#include <Eigen/LU>
#include <cmath>

namespace cws {

FrameConstraints::FrameConstraints(const WireConstants& c, double nu,
                                   const Eigen::Vector3d& plane_normal_world)
    : c_(c),
      nu_(nu),
      plane_normal_world_(plane_normal_world),
      a_blk_(c.capacity),
      ap_blk_(c.capacity),
      d_blk_(c.capacity),
      off_blk_(c.capacity),
      d_inv_(c.capacity),
      elim_(c.capacity),
      b_blk_(c.capacity),
      gamma_(c.capacity),
      lambda_(c.capacity) {}

void FrameConstraints::forward(std::vector<Eigen::Vector3d>& rhs) const {
  for (int i = c_.first + 1; i < c_.n; ++i) rhs[i] -= elim_[i] * rhs[i - 1];
}

void FrameConstraints::backward(const std::vector<Eigen::Vector3d>& rhs,
                                std::vector<Eigen::Vector3d>& x) const {
  const int n = c_.n, f = c_.first;
  for (int i = n - 1; i >= f; --i) {
    Eigen::Vector3d r = rhs[i];
    if (i + 1 < n) r -= off_blk_[i] * x[i + 1];
    x[i] = d_inv_[i] * r;
  }
}

Eigen::Matrix4d FrameConstraints::rotationAboutNormal(const quat::Vec4& q) const {
  // Rates of q that scale it or turn its frame about n (in world axes): q
  // itself and E(q)^T n, orthogonal since E(q) q = 0.
  const quat::Vec4 qn = q.normalized();
  const quat::Vec4 un = (quat::E(q).transpose() * plane_normal_world_).normalized();
  return qn * qn.transpose() + un * un.transpose();
}

void FrameConstraints::accelerations(const WireKinematics& k, const WireForces& f,
                                     const Eigen::Vector3d& a0_world, const Eigen::Vector4d& qdd0,
                                     const PortMotion* port, Eigen::Matrix3Xd& a_world,
                                     Eigen::Matrix4Xd& qdd) {
  // Frames first..n-1 are constrained; point first-1 and its frame move as
  // prescribed (the clamp, or the end of the wire the core carries).
  const int n = c_.n, first = c_.first;
  const double inv_m = 1.0 / c_.point_mass;
  const double inv_mq = 1.0 / (4.0 * c_.point_inertia);

  // Unconstrained accelerations M^-1 f (in the plane for planar scenes); the
  // clamp's are prescribed.
  const Eigen::Vector3d& nrm = plane_normal_world_;
  const bool planar = !nrm.isZero();
  a_world.col(first - 1) = a0_world;
  qdd.col(first - 1) = qdd0;
  for (int i = first; i < n; ++i) {
    const Eigen::Vector3d fp = f.f_world.col(i);
    a_world.col(i) = inv_m * (fp - fp.dot(nrm) * nrm);
    qdd.col(i) = inv_mq * f.f_q.col(i);
  }

  // Jacobian blocks and the stabilized right-hand side of each frame.
  for (int i = first; i < n; ++i) {
    const Eigen::Vector3d d = k.p_world.col(i) - k.p_world.col(i - 1);
    const Eigen::Vector3d dd = k.v_world.col(i) - k.v_world.col(i - 1);
    const quat::Vec4 q = k.q.col(i);
    const quat::Vec4 qd = k.qd.col(i);
    const Eigen::Vector3d xi = quat::xi(q);
    const Eigen::Vector3d eta = quat::eta(q);
    const quat::Mat34 jx = quat::xiJacobian(q);
    const quat::Mat34 je = quat::etaJacobian(q);
    const Eigen::Vector3d xid = jx * qd;
    const Eigen::Vector3d etad = je * qd;

    Eigen::Vector3d c(q.squaredNorm() - 1.0, d.dot(xi), d.dot(eta));
    Eigen::Vector3d cd(2.0 * q.dot(qd), dd.dot(xi) + d.dot(xid), dd.dot(eta) + d.dot(etad));
    Eigen::Vector3d jdot_v(2.0 * qd.squaredNorm(),
                           2.0 * dd.dot(xid) + 2.0 * d.dot(quat::xiBilinear(qd, qd)),
                           2.0 * dd.dot(etad) + 2.0 * d.dot(quat::etaBilinear(qd, qd)));

    Eigen::Matrix3d& a = a_blk_[i];
    a.row(0).setZero();
    a.row(1) = xi.transpose();
    a.row(2) = eta.transpose();
    quat::Mat34& b = b_blk_[i];
    b.row(0) = 2.0 * q.transpose();
    b.row(1) = d.transpose() * jx;
    b.row(2) = d.transpose() * je;
    if (planar) {
      // Frame i turns about n only: its inverse mass is (1/4I) Q, and its
      // unconstrained acceleration lies in that motion.
      const Eigen::Matrix4d pq = rotationAboutNormal(q);
      b = b * pq;
      qdd.col(i) = pq * qdd.col(i);
      // Rows 1, 2 become the in-plane combination (d along n x zeta) and
      // the out-of-plane one (d along n), which neither a point nor the
      // frame can change any more: a zero row, kept with multiplier 0.
      Eigen::Vector2d t(-eta.dot(nrm), xi.dot(nrm));
      t.normalize();
      a.row(1) = t[0] * a.row(1) + t[1] * a.row(2);
      b.row(1) = t[0] * b.row(1) + t[1] * b.row(2);
      c[1] = t[0] * c[1] + t[1] * c[2];
      cd[1] = t[0] * cd[1] + t[1] * cd[2];
      jdot_v[1] = t[0] * jdot_v[1] + t[1] * jdot_v[2];
      a.row(2).setZero();
      b.row(2).setZero();
      c[2] = cd[2] = jdot_v[2] = 0.0;
    }
    Eigen::Matrix3d& ap = ap_blk_[i];
    ap = inPlane<3>(a);

    const Eigen::Vector3d j_au = a * (a_world.col(i) - a_world.col(i - 1)) + b * qdd.col(i);
    gamma_[i] = -jdot_v - 2.0 * nu_ * cd - nu_ * nu_ * c - j_au;

    // Diagonal block: point i, point i-1 unless it is prescribed, frame i.
    const double w = (i > first) ? 2.0 * inv_m : inv_m;
    d_blk_[i] = w * ap * ap.transpose() + inv_mq * b * b.transpose();
    // Planar: the zero row's pivot (its multiplier comes out 0).
    if (planar) d_blk_[i](2, 2) = 1.0;
  }
  // Off-diagonal blocks couple frames i and i+1 through point i.
  for (int i = first; i + 1 < n; ++i) {
    off_blk_[i] = -inv_m * ap_blk_[i] * ap_blk_[i + 1].transpose();
  }

  // Block LDL^T (block Thomas) factorization of the SPD system.
  for (int i = first; i < n; ++i) {
    if (i > first) {
      elim_[i] = off_blk_[i - 1].transpose() * d_inv_[i - 1];
      d_blk_[i] -= elim_[i] * off_blk_[i - 1];
    }
    d_inv_[i] = d_blk_[i].inverse();
  }

  Eigen::Vector2d mu = Eigen::Vector2d::Zero();
  Eigen::Matrix<double, 2, 3> pp;
  Eigen::Matrix<double, 2, 4> pq;
  if (!port) {
    forward(gamma_);
    backward(gamma_, lambda_);
  } else {
    // Port rows on the last point L and its frame.
    const int l = n - 1;
    const quat::Vec4 q = k.q.col(l);
    const quat::Vec4 qd = k.qd.col(l);
    const Eigen::Vector3d e = k.p_world.col(l) - port->p_world;
    const Eigen::Vector3d ed = k.v_world.col(l) - port->v_world;
    const quat::Mat34 jx = quat::xiJacobian(q);
    const quat::Mat34 je = quat::etaJacobian(q);
    const Eigen::Vector3d xi = quat::xi(q), eta = quat::eta(q);
    const Eigen::Vector3d xid = jx * qd, etad = je * qd;
    pp.row(0) = xi.transpose();
    pp.row(1) = eta.transpose();
    pq.row(0) = e.transpose() * jx;
    pq.row(1) = e.transpose() * je;
    if (planar) pq = pq * rotationAboutNormal(q);
    const Eigen::Matrix<double, 2, 3> ppp = inPlane<2>(pp);
    const Eigen::Vector2d c(e.dot(xi), e.dot(eta));
    const Eigen::Vector2d cd(ed.dot(xi) + e.dot(xid), ed.dot(eta) + e.dot(etad));
    const Eigen::Vector2d jdot_v(
        -port->a_world.dot(xi) + 2.0 * ed.dot(xid) + 2.0 * e.dot(quat::xiBilinear(qd, qd)),
        -port->a_world.dot(eta) + 2.0 * ed.dot(etad) + 2.0 * e.dot(quat::etaBilinear(qd, qd)));
    const Eigen::Vector2d g =
        -jdot_v - 2.0 * nu_ * cd - nu_ * nu_ * c - (pp * a_world.col(l) + pq * qdd.col(l));
    // Border: coupling of frame block L with the port rows, and the port's
    // own block.
    const Eigen::Matrix<double, 3, 2> border =
        inv_m * ap_blk_[l] * ppp.transpose() + inv_mq * b_blk_[l] * pq.transpose();
    const Eigen::Matrix2d corner = inv_m * ppp * ppp.transpose() + inv_mq * pq * pq.transpose();
    // The border touches the last block only, so one block solve does: a
    // right-hand side nonzero only in the last block passes the forward
    // elimination unchanged, and back substitution starts with the last
    // block. Forward-eliminate gamma; the last block of S^-1 gamma and of
    // S^-1 border give the 2x2 Schur complement and mu; back-substitute
    // gamma - border mu.
    forward(gamma_);
    const Eigen::Matrix<double, 3, 2> x_border = d_inv_[l] * border;
    const Eigen::Matrix2d schur = corner - border.transpose() * x_border;
    const Eigen::Vector2d rhs = g - border.transpose() * (d_inv_[l] * gamma_[l]);
    if (!planar) {
      mu = schur.inverse() * rhs;
    } else {
      // Planar: the out-of-plane combination of the two port rows, with
      // weights (xi . n, eta . n), holds p_L - p_s along n, which neither
      // p_L nor frame L can change (the port lies in the plane), and makes
      // the 2x2 Schur complement singular. Keep the in-plane combination only.
      Eigen::RowVector2d t(-eta.dot(plane_normal_world_), xi.dot(plane_normal_world_));
      t.normalize();
      mu = t.transpose() * (t * rhs) / (t * schur * t.transpose());
    }
    gamma_[l] -= border * mu;
    backward(gamma_, lambda_);
  }

  // Constraint forces J^T lambda added to the accelerations (M^-1 J^T lambda,
  // with the points' inverse mass P / M).
  for (int i = first; i < n; ++i) {
    Eigen::Vector3d fp = ap_blk_[i].transpose() * lambda_[i];
    if (i + 1 < n) fp -= ap_blk_[i + 1].transpose() * lambda_[i + 1];
    a_world.col(i) += inv_m * fp;
    qdd.col(i) += inv_mq * (b_blk_[i].transpose() * lambda_[i]);
  }
  port_power_ = 0.0;
  if (port) {
    // The port rows depend on time through p_s: dc/dt = -P v_s.
    port_power_ = mu.dot(pp * port->v_world);
    a_world.col(n - 1) += inv_m * (inPlane<2>(pp).transpose() * mu);
    qdd.col(n - 1) += inv_mq * (pq.transpose() * mu);
  }
}

double FrameConstraints::maxResidual(const WireKinematics& k) const {
  double r = 0.0;
  // Frames of carried wire are not integrated: their residuals were
  // measured while they were.
  for (int i = c_.first; i < c_.n; ++i) {
    const Eigen::Vector3d d = k.p_world.col(i) - k.p_world.col(i - 1);
    const quat::Vec4 q = k.q.col(i);
    const double len = d.norm();
    r = std::max(r, std::abs(q.squaredNorm() - 1.0));
    r = std::max(r, std::abs(d.dot(quat::xi(q))) / len);
    r = std::max(r, std::abs(d.dot(quat::eta(q))) / len);
  }
  return r;
}

}  // namespace cws
