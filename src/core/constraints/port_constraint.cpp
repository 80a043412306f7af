// The supply's port constraint (22) as rows of the Newton systems: the
// port lies on the line of the last frame's zeta (in the plane, of the
// last segment) through the last point, held exactly at the step's end by
// the port multipliers. The explicit model keeps it at acceleration level
// (FrameConstraints::accelerations); the supply's pull is its own effect.
#include "coil_winding_sim/core/assembly/planar_assembly.hpp"
#include "coil_winding_sim/core/assembly/spatial_assembly.hpp"
#include "coil_winding_sim/core/constraints/frame_constraints.hpp"

namespace cws {

void addPlanarPortConstraint(const PlanarState& s, const PortMotion& pm, double scale,
                             PlanarAssembly& a) {
  const int last = s.n - 1;
  const Eigen::Vector2d d = s.segment(last - 1);
  const double len = d.norm();
  const Eigen::Vector2d u = d / len;
  const Eigen::Matrix2d proj = Eigen::Matrix2d::Identity() - u * u.transpose();
  // Port constraint (eq. 22 in the plane): the port lies on the line of the
  // last segment, g = cross(u, e) = 0 with e = x_L - p_s [m]. Its force
  // lambda dg/dx; the row holds -scale g.
  const Eigen::Vector2d e = s.x.col(last) - s.plane.toPlane(pm.p_world);
  const double g = planar::cross(u, e);
  const Eigen::Vector2d w = -planar::perp(e);
  const Eigen::Vector2d g_d = proj * w / len;   // dg/dd
  const Eigen::Vector2d g_e = planar::perp(u);  // dg/de
  const Eigen::Vector2d grad_last = g_d + g_e, grad_prev = -g_d;
  const double lambda = s.lambda_port;
  a.addForce(last, lambda * grad_last);
  a.addForce(last - 1, lambda * grad_prev);
  // The moving port works on the wire through the constraint force.
  a.power_external += lambda * g_e.dot(s.plane.vectorToPlane(pm.v_world));
  a.setConstraint(g, scale);
  if (!a.wantsJacobian()) return;
  a.addConstraintGradient(last, grad_last);
  a.addConstraintGradient(last - 1, grad_prev);
  // lambda d^2 g / dx^2 over (x_{L-1}, x_L), with d = x_L - x_{L-1} and e.
  const Eigen::Vector2d pw = proj * w;
  const Eigen::Matrix2d h_dd =
      -(u.dot(w) * proj + u * pw.transpose() + pw * u.transpose()) / (len * len);
  const Eigen::Matrix2d h_ed = planar::perpMatrix() * proj / len;  // d g_e / dd
  a.addStiffness(last, last, lambda * (h_dd + h_ed + h_ed.transpose()));
  a.addStiffness(last, last - 1, lambda * (-h_dd - h_ed));
  a.addStiffness(last - 1, last, lambda * (-h_dd - h_ed.transpose()));
  a.addStiffness(last - 1, last - 1, lambda * h_dd);
}

void addSpatialPortConstraint(const SpatialState& s, const PortMotion& pm, double scale,
                              SpatialAssembly& a) {
  const int last = s.n - 1;
  const quat::Vec4 q = s.q.col(last);
  const Eigen::Vector3d e = s.p.col(last) - pm.p_world;
  const Eigen::Vector3d axis[2] = {quat::xi(q), quat::eta(q)};
  const quat::Mat34 jac[2] = {quat::xiJacobian(q), quat::etaJacobian(q)};
  for (int r = 0; r < 2; ++r) {
    const double lambda = s.lambda_port[r];
    a.addForce(last, lambda * axis[r]);
    a.addQForce(last, lambda * jac[r].transpose() * e);
    // The moving port works on the wire through the constraint force.
    a.power_external += lambda * axis[r].dot(pm.v_world);
    const int row = a.portRow() + r;
    a.setConstraint(row, e.dot(axis[r]), scale);
    if (!a.wantsJacobian()) continue;
    a.addConstraintGradientP(row, last, axis[r]);
    a.addConstraintGradientQ(row, last, jac[r].transpose() * e);
    a.addStiffnessPQ(last, last, lambda * jac[r]);
    a.addStiffnessQP(last, last, lambda * jac[r].transpose());
  }
  if (!a.wantsJacobian()) return;
  a.addStiffnessQQ(last, last,
                   s.lambda_port[0] * quat::xiHessian(e) + s.lambda_port[1] * quat::etaHessian(e));
}

}  // namespace cws
