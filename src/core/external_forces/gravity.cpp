#include "coil_winding_sim/core/external_forces/gravity.hpp"

namespace cws {

void Gravity::addForces(double, const WireKinematics&, WireForces& f) const {
  // Point 0 is held by the clamp: its load goes to the support, not the wire.
  const Eigen::Vector3d w_world = c_.point_mass * g_world_;
  for (int i = c_.first; i < c_.n; ++i) {
    f.f_world.col(i) += w_world;
    f.f_work_world.col(i) += w_world;
  }
}

}  // namespace cws
