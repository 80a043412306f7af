// The 3-D sink's joint moment (force_sink.hpp): a rotational spring's
// moment and tangent mapped to the quaternions' blocks.
#include "coil_winding_sim/core/assembly/force_sink.hpp"

namespace cws {

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
