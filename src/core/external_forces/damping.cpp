#include "coil_winding_sim/core/external_forces/damping.hpp"

#include "coil_winding_sim/core/quaternion.hpp"

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

}  // namespace cws
