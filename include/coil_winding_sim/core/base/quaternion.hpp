// Quaternion algebra on plain 4-vectors (q0, q1, q2, q3), scalar first.
//
// The frame axes xi, eta, zeta are the columns of the rotation matrix written
// as quadratic forms of q, so that they stay polynomial (and their
// derivatives simple) off the unit sphere too; the unit-norm constraint (4)
// keeps |q| = 1.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace cws {
namespace quat {

using Vec4 = Eigen::Vector4d;
using Mat34 = Eigen::Matrix<double, 3, 4>;

inline Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

// G(q): body angular velocity omega_body = 2 G(q) qdot; the paper's Q_i (3).
// Also Im(conj(a) * b) = G(a) b.
inline Mat34 G(const Vec4& q) {
  Mat34 m;
  m << -q[1], q[0], q[3], -q[2],  //
      -q[2], -q[3], q[0], q[1],   //
      -q[3], q[2], -q[1], q[0];
  return m;
}

// G(a) b = Im(conj(a) * b) without forming G (the hot path of the
// rotational springs).
inline Eigen::Vector3d gTimes(const Vec4& a, const Vec4& b) {
  return {-a[1] * b[0] + a[0] * b[1] + a[3] * b[2] - a[2] * b[3],
          -a[2] * b[0] - a[3] * b[1] + a[0] * b[2] + a[1] * b[3],
          -a[3] * b[0] + a[2] * b[1] - a[1] * b[2] + a[0] * b[3]};
}

// G(q)^T v without forming G (a matrix built on the stack entry by entry and
// read back at once stalls the CPU's store forwarding).
inline Vec4 gTransposeApply(const Vec4& q, const Eigen::Vector3d& v) {
  return Vec4(-q[1] * v[0] - q[2] * v[1] - q[3] * v[2], q[0] * v[0] - q[3] * v[1] + q[2] * v[2],
              q[3] * v[0] + q[0] * v[1] - q[1] * v[2], -q[2] * v[0] + q[1] * v[1] + q[0] * v[2]);
}

// E(q): world angular velocity omega_world = 2 E(q) qdot.
inline Mat34 E(const Vec4& q) {
  Mat34 m;
  m << -q[1], q[0], -q[3], q[2],  //
      -q[2], q[3], q[0], -q[1],   //
      -q[3], -q[2], q[1], q[0];
  return m;
}

// Symmetric bilinear forms whose diagonal is the frame axis: xi(q) = Bxi(q, q).
inline Eigen::Vector3d xiBilinear(const Vec4& a, const Vec4& b) {
  return {a[0] * b[0] + a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
          a[1] * b[2] + a[2] * b[1] + a[0] * b[3] + a[3] * b[0],
          a[1] * b[3] + a[3] * b[1] - a[0] * b[2] - a[2] * b[0]};
}
inline Eigen::Vector3d etaBilinear(const Vec4& a, const Vec4& b) {
  return {a[1] * b[2] + a[2] * b[1] - a[0] * b[3] - a[3] * b[0],
          a[0] * b[0] - a[1] * b[1] + a[2] * b[2] - a[3] * b[3],
          a[2] * b[3] + a[3] * b[2] + a[0] * b[1] + a[1] * b[0]};
}
inline Eigen::Vector3d zetaBilinear(const Vec4& a, const Vec4& b) {
  return {a[1] * b[3] + a[3] * b[1] + a[0] * b[2] + a[2] * b[0],
          a[2] * b[3] + a[3] * b[2] - a[0] * b[1] - a[1] * b[0],
          a[0] * b[0] - a[1] * b[1] - a[2] * b[2] + a[3] * b[3]};
}

inline Eigen::Vector3d xi(const Vec4& q) { return xiBilinear(q, q); }
inline Eigen::Vector3d eta(const Vec4& q) { return etaBilinear(q, q); }
inline Eigen::Vector3d zeta(const Vec4& q) { return zetaBilinear(q, q); }

// d xi / d q and d eta / d q (3x4).
inline Mat34 xiJacobian(const Vec4& q) {
  Mat34 m;
  m << q[0], q[1], -q[2], -q[3],  //
      q[3], q[2], q[1], q[0],     //
      -q[2], q[3], -q[0], q[1];
  return 2.0 * m;
}
inline Mat34 etaJacobian(const Vec4& q) {
  Mat34 m;
  m << -q[3], q[2], q[1], -q[0],  //
      q[0], -q[1], q[2], -q[3],   //
      q[1], q[0], q[3], q[2];
  return 2.0 * m;
}

// (d xi / d q)^T d and (d eta / d q)^T d without forming the 3x4 matrices
// (the frame constraints' hot path: a matrix built on the stack entry by
// entry and read back by columns stalls the CPU's store forwarding).
inline Vec4 xiJacobianTransposeTimes(const Vec4& q, const Eigen::Vector3d& d) {
  return 2.0 *
         Vec4(q[0] * d[0] + q[3] * d[1] - q[2] * d[2], q[1] * d[0] + q[2] * d[1] + q[3] * d[2],
              -q[2] * d[0] + q[1] * d[1] - q[0] * d[2], -q[3] * d[0] + q[0] * d[1] + q[1] * d[2]);
}
inline Vec4 etaJacobianTransposeTimes(const Vec4& q, const Eigen::Vector3d& d) {
  return 2.0 *
         Vec4(-q[3] * d[0] + q[0] * d[1] + q[1] * d[2], q[2] * d[0] - q[1] * d[1] + q[0] * d[2],
              q[1] * d[0] + q[2] * d[1] + q[3] * d[2], -q[0] * d[0] - q[3] * d[1] + q[2] * d[2]);
}

// Derivatives of the bilinear forms: d f(q, q) / d q (3x4) and
// d^2 (w . f(q, q)) / d q^2 (4x4, constant in q) for f = xiBilinear,
// etaBilinear or zetaBilinear.
template <class Bilinear>
Mat34 bilinearJacobian(Bilinear f, const Vec4& q) {
  Mat34 m;
  for (int k = 0; k < 4; ++k) m.col(k) = 2.0 * f(q, Vec4::Unit(k));
  return m;
}
template <class Bilinear>
Eigen::Matrix4d bilinearHessian(Bilinear f, const Eigen::Vector3d& w) {
  Eigen::Matrix4d h;
  for (int k = 0; k < 4; ++k) {
    for (int l = 0; l < 4; ++l) h(k, l) = 2.0 * w.dot(f(Vec4::Unit(k), Vec4::Unit(l)));
  }
  return h;
}
inline Mat34 zetaJacobian(const Vec4& q) { return bilinearJacobian(zetaBilinear, q); }

// The same Hessians from tables made once: d^2 (w . f(q, q)) / d q^2 =
// sum_c w_c T_c with T_c(k, l) = 2 f(e_k, e_l)_c.
struct BilinearTensor {
  Eigen::Matrix4d t[3];
  template <class Bilinear>
  explicit BilinearTensor(Bilinear f) {
    for (int c = 0; c < 3; ++c) t[c] = bilinearHessian(f, Eigen::Vector3d::Unit(c));
  }
  Eigen::Matrix4d operator()(const Eigen::Vector3d& w) const {
    return w[0] * t[0] + w[1] * t[1] + w[2] * t[2];
  }
};
inline Eigen::Matrix4d xiHessian(const Eigen::Vector3d& w) {
  static const BilinearTensor tensor(xiBilinear);
  return tensor(w);
}
inline Eigen::Matrix4d etaHessian(const Eigen::Vector3d& w) {
  static const BilinearTensor tensor(etaBilinear);
  return tensor(w);
}

// G(q)^T m as a linear function of q: the 4x4 matrix whose column k is
// G(e_k)^T m.
inline Eigen::Matrix4d gTransposeTimes(const Eigen::Vector3d& m) {
  Eigen::Matrix4d r;
  r << 0.0, -m[0], -m[1], -m[2],  //
      m[0], 0.0, m[2], -m[1],     //
      m[1], -m[2], 0.0, m[0],     //
      m[2], m[1], -m[0], 0.0;
  return r;
}

// Quaternion whose zeta axis is `dir` (need not be unit); deterministic choice
// of xi (the world axis least parallel to dir, projected).
inline Vec4 fromZetaDirection(const Eigen::Vector3d& dir) {
  const Eigen::Vector3d z = dir.normalized();
  Eigen::Vector3d ref = Eigen::Vector3d::UnitX();
  if (std::abs(z.x()) > 0.9) ref = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d x = (ref - ref.dot(z) * z).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d r;
  r.col(0) = x;
  r.col(1) = y;
  r.col(2) = z;
  const Eigen::Quaterniond qe(r);
  return {qe.w(), qe.x(), qe.y(), qe.z()};
}

// Rotation angle [rad] between two frames (relative rotation conj(a) * b).
inline double relativeAngle(const Vec4& a, const Vec4& b) {
  const Eigen::Vector3d v = gTimes(a, b);
  const double w = a.dot(b);
  return 2.0 * std::atan2(v.norm(), std::abs(w));
}

}  // namespace quat
}  // namespace cws
