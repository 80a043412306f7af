#include "coil_winding_sim/core/external_forces/damping.hpp"

#include "coil_winding_sim/core/assembly/planar_assembly.hpp"
#include "coil_winding_sim/core/assembly/spatial_assembly.hpp"
#include "coil_winding_sim/core/base/quaternion.hpp"

namespace cws {

void Damping::addForces(double, const WireKinematics& k, WireForces& f) const {
  const double c_lin = p_.translational * c_.point_length;  // [N s/m]
  const double c_rot = p_.rotational * c_.point_length;     // [N m s]
  for (int i = c_.first; i < c_.n; ++i) {
    const Eigen::Vector3d v = k.v_world.col(i);
    f.f_world.col(i) -= c_lin * v;
    f.f_dissipative_world.col(i) -= c_lin * v;
    if (c_rot > 0.0) {
      // Moment -c omega_world, as a generalized force 2 E(q)^T m on q.
      const quat::Mat34 e = quat::E(k.q.col(i));
      const Eigen::Vector3d omega_world = 2.0 * e * k.qd.col(i);
      const Eigen::Vector4d fq = -2.0 * c_rot * e.transpose() * omega_world;
      f.f_q.col(i) += fq;
      f.fq_dissipative.col(i) += fq;
    }
  }
}

void Damping::addPlanarForces(const PlanarState& s, PlanarAssembly& a) const {
  const double c_lin = p_.translational * c_.point_length;  // [N s/m]
  const double c_rot = p_.rotational * c_.point_length;     // [N m s]
  const Eigen::Matrix2d id = Eigen::Matrix2d::Identity();
  for (int i = s.first; i < s.n; ++i) {
    const Eigen::Vector2d f = -c_lin * s.v.col(i);
    a.addForce(i, f);
    a.f_dissipative.col(i) += f;
    a.addDamping(i, i, -c_lin * id);
    if (c_rot <= 0.0) continue;
    // Frame i turns with segment i-1 at omega = g . (v_i - v_{i-1}), g the
    // gradient of its angle: the moment -c omega as forces on both points.
    const Eigen::Vector2d d = s.segment(i - 1);
    const Eigen::Vector2d g = planar::angleGradient(d);
    const Eigen::Vector2d w = s.v.col(i) - s.v.col(i - 1);
    const double omega = g.dot(w);
    a.addForce(i, -c_rot * omega * g);
    a.addForce(i - 1, c_rot * omega * g);
    a.f_dissipative.col(i) += -c_rot * omega * g;
    if (i - 1 >= s.first) a.f_dissipative.col(i - 1) += c_rot * omega * g;
    const Eigen::Matrix2d dv = -c_rot * g * g.transpose();
    const Eigen::Matrix2d hs = planar::angleHessian(d);
    const Eigen::Matrix2d dx = -c_rot * (g * (hs * w).transpose() + omega * hs);
    const int pts[2] = {i - 1, i};
    const double sgn[2] = {-1.0, 1.0};
    for (int r = 0; r < 2; ++r) {
      for (int c = 0; c < 2; ++c) {
        a.addDamping(pts[r], pts[c], sgn[r] * sgn[c] * dv);
        a.addStiffness(pts[r], pts[c], sgn[r] * sgn[c] * dx);
      }
    }
  }
}

void Damping::addSpatialForces(const SpatialState& s, SpatialAssembly& a) const {
  // As addForces: -c v on the points, and the moment -c omega_world as the
  // generalized force -4 c E(q)^T E(q) qdot on the quaternions (E is
  // linear in q: column k of d(E(q) x)/dq is E(e_k) x).
  const double c_lin = p_.translational * c_.point_length;  // [N s/m]
  const double c_rot = p_.rotational * c_.point_length;     // [N m s]
  const Eigen::Matrix3d id = Eigen::Matrix3d::Identity();
  for (int i = s.first; i < s.n; ++i) {
    const Eigen::Vector3d f = -c_lin * s.v.col(i);
    a.addForce(i, f);
    a.f_dissipative.col(i) += f;
    a.addDampingPP(i, i, -c_lin * id);
    if (c_rot <= 0.0) continue;
    const quat::Vec4 q = s.q.col(i), qd = s.qd.col(i);
    const quat::Mat34 e = quat::E(q);
    const Eigen::Vector3d u = e * qd;  // omega_world / 2
    const Eigen::Vector4d fq = -4.0 * c_rot * e.transpose() * u;
    a.addQForce(i, fq);
    a.fq_dissipative.col(i) += fq;
    Eigen::Matrix4d dq;  // d (E^T u) / dq at fixed qd
    for (int k = 0; k < 4; ++k) {
      const quat::Vec4 ek = quat::Vec4::Unit(k);
      dq.col(k) = quat::E(ek).transpose() * u + e.transpose() * (quat::E(ek) * qd);
    }
    a.addStiffnessQQ(i, i, -4.0 * c_rot * dq);
    a.addDampingQQ(i, i, -4.0 * c_rot * e.transpose() * e);
  }
}

}  // namespace cws
