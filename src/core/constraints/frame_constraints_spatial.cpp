// The frame constraint (5) as rows of the 3-D implicit Newton system:
// unlike the explicit model (frame_constraints.cpp), which keeps (4) and
// (5) at acceleration level with Baumgarte's stabilization, an implicit
// step holds (5) exactly at its end. (4), the unit norm, needs no row: the
// step moves each quaternion by a rotation (SpatialAssembly's frames).
#include "coil_winding_sim/core/assembly/spatial_assembly.hpp"
#include "coil_winding_sim/core/constraints/frame_constraints.hpp"

namespace cws {

void addSpatialFrameConstraints(const SpatialState& s, double scale_direction, SpatialAssembly& a) {
  for (int i = s.first; i < s.n; ++i) {
    const quat::Vec4 q = s.q.col(i);
    const Eigen::Vector3d d = s.segment(i - 1);
    const double m_xi = s.mu(1, i), m_eta = s.mu(2, i);
    const int row = a.muRow(i);
    // (5): d . xi and d . eta, d = p_i - p_{i-1} (multipliers mu[1], mu[2]);
    // the two rows' forces on p_i, p_i-1 and q_i summed before they are added.
    const Eigen::Vector3d xi = quat::xi(q), eta = quat::eta(q);
    const Eigen::Vector3d f = m_xi * xi + m_eta * eta;
    a.addForce(i, f);
    a.addForce(i - 1, -f);
    const Eigen::Vector4d grad_xi = quat::xiJacobianTransposeTimes(q, d),
                          grad_eta = quat::etaJacobianTransposeTimes(q, d);
    a.addQForce(i, m_xi * grad_xi + m_eta * grad_eta);
    a.setConstraint(row, d.dot(xi), scale_direction);
    a.setConstraint(row + 1, d.dot(eta), scale_direction);
    if (!a.wantsJacobianAt(i - 1)) continue;
    a.addConstraintGradientP(row, i, xi);
    a.addConstraintGradientP(row, i - 1, -xi);
    a.addConstraintGradientQ(row, i, grad_xi);
    a.addConstraintGradientP(row + 1, i, eta);
    a.addConstraintGradientP(row + 1, i - 1, -eta);
    a.addConstraintGradientQ(row + 1, i, grad_eta);
    const quat::Mat34 k = m_xi * quat::xiJacobian(q) + m_eta * quat::etaJacobian(q);
    a.addStiffnessPQ(i, i, k);
    a.addStiffnessPQ(i - 1, i, -k);
    a.addStiffnessQP(i, i, k.transpose());
    a.addStiffnessQP(i, i - 1, -k.transpose());
    a.addStiffnessQQ(i, i, m_xi * quat::xiHessian(d) + m_eta * quat::etaHessian(d));
  }
}

}  // namespace cws
