// The frame constraint (5) as rows of the 3-D implicit Newton system:
// unlike the explicit model (frame_constraints.cpp), which keeps (4) and
// (5) at acceleration level with Baumgarte's stabilization, an implicit
// step holds (5) exactly at its end. (4), the unit norm, needs no row: the
// step moves each quaternion by a rotation (SpatialAssembly's frames).
#include "coil_winding_sim/core/constraints/frame_constraints.hpp"
#include "coil_winding_sim/core/implicit/spatial_assembly.hpp"

namespace cws {

void addSpatialFrameConstraints(const SpatialState& s, double scale_direction, SpatialAssembly& a) {
  for (int i = s.first; i < s.n; ++i) {
    const quat::Vec4 q = s.q.col(i);
    const Eigen::Vector3d d = s.segment(i - 1);
    const Eigen::Vector3d mu = s.mu.col(i);
    const int row = a.muRow(i);
    const bool jacobian = a.wantsJacobianAt(i - 1);
    // (5): d . xi and d . eta, d = p_i - p_{i-1} (multipliers mu[1], mu[2]).
    const Eigen::Vector3d axis[2] = {quat::xi(q), quat::eta(q)};
    const Eigen::Vector4d grads_q[2] = {quat::xiJacobianTransposeTimes(q, d),
                                        quat::etaJacobianTransposeTimes(q, d)};
    for (int r = 0; r < 2; ++r) {
      const double m = mu[1 + r];
      const Eigen::Vector4d& grad_q = grads_q[r];
      a.addForce(i, m * axis[r]);
      a.addForce(i - 1, -m * axis[r]);
      a.addQForce(i, m * grad_q);
      a.setConstraint(row + r, d.dot(axis[r]), scale_direction);
      if (!jacobian) continue;
      const quat::Mat34 jac = r == 0 ? quat::xiJacobian(q) : quat::etaJacobian(q);
      a.addConstraintGradientP(row + r, i, axis[r]);
      a.addConstraintGradientP(row + r, i - 1, -axis[r]);
      a.addConstraintGradientQ(row + r, i, grad_q);
      a.addStiffnessPQ(i, i, m * jac);
      a.addStiffnessPQ(i - 1, i, -m * jac);
      a.addStiffnessQP(i, i, m * jac.transpose());
      a.addStiffnessQP(i, i - 1, -m * jac.transpose());
    }
    if (jacobian) {
      a.addStiffnessQQ(i, i, mu[1] * quat::xiHessian(d) + mu[2] * quat::etaHessian(d));
    }
  }
}

}  // namespace cws
