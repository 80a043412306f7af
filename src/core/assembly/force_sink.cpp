// The joint moments of the two Newton sinks (force_sink.hpp): a rotational
// spring's moment and tangent mapped to each formulation's unknowns.
#include "coil_winding_sim/core/assembly/force_sink.hpp"

namespace cws {

void PlanarSink::addJointMoment(int j, double lambda, const Eigen::Vector3d& m_vec,
                                const Eigen::Vector3d& dm_vec) {
  // The moment about n, m = sum_c m_c n_material[c], and its tangent in
  // kappa, sum_c dm_c n_material[c]^2 (the components the plane moves).
  double m = 0.0, dm = 0.0;
  for (int c = 0; c < 3; ++c) {
    const double w = s_.n_material[c];
    if (w == 0.0) continue;
    m += w * m_vec[c];
    dm += w * w * dm_vec[c];
  }
  // Generalized force on dphi: Q = -d(lambda W)/d dphi = -m cos(dphi / 2);
  // d dphi / dx is gb on point j+1, -gb - ga on j and ga on j-1.
  const bool prescribed = j == s_.first - 1;
  const double q = -m * cos_half_;
  const Eigen::Vector2d g_mid = -gb_.gradient - ga_.gradient;
  a_.addForce(j + 1, q * gb_.gradient);
  a_.addForce(j, q * g_mid);
  if (prescribed) {
    a_.addBoundaryTorque(-q);
  } else {
    a_.addForce(j - 1, q * ga_.gradient);
  }
  if (!a_.wantsJacobian()) return;
  // dq g_r g_c^T + q d^2 dphi / dx_r dx_c over points j-1, j, j+1; dphi =
  // phi_b - phi_a, whose second derivatives are +-hb and +-ha.
  const double dq = -dm * cos_half_ * cos_half_ / lambda + 0.5 * m * sin_half_;
  const Eigen::Matrix2d qhb = q * gb_.hessian;
  const Eigen::Matrix2d k_bb = dq * gb_.gradient * gb_.gradient.transpose() + qhb;
  const Eigen::Matrix2d k_bm = dq * gb_.gradient * g_mid.transpose() - qhb;
  a_.addStiffness(j + 1, j + 1, k_bb);
  a_.addStiffness(j + 1, j, k_bm);
  a_.addStiffness(j, j + 1, k_bm.transpose());
  if (prescribed) {
    a_.addStiffness(j, j, dq * g_mid * g_mid.transpose() + qhb);
    return;
  }
  const Eigen::Matrix2d qha = q * ga_.hessian;
  const Eigen::Matrix2d k_ma = dq * g_mid * ga_.gradient.transpose() + qha;
  const Eigen::Matrix2d k_ba = dq * gb_.gradient * ga_.gradient.transpose();
  a_.addStiffness(j, j, dq * g_mid * g_mid.transpose() + qhb - qha);
  a_.addStiffness(j, j - 1, k_ma);
  a_.addStiffness(j - 1, j, k_ma.transpose());
  a_.addStiffness(j - 1, j - 1, dq * ga_.gradient * ga_.gradient.transpose() - qha);
  a_.addStiffness(j + 1, j - 1, k_ba);
  a_.addStiffness(j - 1, j + 1, k_ba.transpose());
}

void SpatialSink::addJointMoment(int j, double lambda, const Eigen::Vector3d& m,
                                 const Eigen::Vector3d& dm) {
  // f_j = 2 G(q_j+1)^T m and f_j+1 = -2 G(q_j)^T m, with m(Omega).
  const quat::Vec4 qa = s_.q.col(j), qb = s_.q.col(j + 1);
  a_.addQForce(j, 2.0 * quat::gTransposeApply(qb, m));
  a_.addQForce(j + 1, -2.0 * quat::gTransposeApply(qa, m));
  if (!a_.wantsJacobianAt(j)) return;
  const quat::Mat34 ga = quat::G(qa), gb = quat::G(qb);
  const Eigen::Matrix4d gm = quat::gTransposeTimes(m);
  const Eigen::Matrix<double, 4, 3> gad = ga.transpose() * dm.asDiagonal();
  const Eigen::Matrix<double, 4, 3> gbd = gb.transpose() * dm.asDiagonal();
  const double s2 = 4.0 / lambda;
  a_.addStiffnessQQ(j, j, -s2 * gbd * gb);
  a_.addStiffnessQQ(j, j + 1, 2.0 * gm + s2 * gbd * ga);
  a_.addStiffnessQQ(j + 1, j, -2.0 * gm + s2 * gad * gb);
  a_.addStiffnessQQ(j + 1, j + 1, -s2 * gad * ga);
}

}  // namespace cws
