#include "coil_winding_sim/core/external_forces/gravity.hpp"

#include "coil_winding_sim/core/implicit/planar_assembly.hpp"
#include "coil_winding_sim/core/implicit/spatial_assembly.hpp"

namespace cws {

void Gravity::addForces(double, const WireKinematics&, WireForces& f) const {
  // Point 0 is held by the clamp: its load goes to the support, not the wire.
  const Eigen::Vector3d w_world = c_.point_mass * g_world_;
  for (int i = c_.first; i < c_.n; ++i) {
    f.f_world.col(i) += w_world;
    f.f_work_world.col(i) += w_world;
  }
}

void Gravity::addPlanarForces(const PlanarState& s, PlanarAssembly& a) const {
  // A planar scene has no gravity along the normal: its in-plane part.
  const Eigen::Vector2d w = c_.point_mass * s.plane.vectorToPlane(g_world_);
  for (int i = s.first; i < s.n; ++i) {
    a.addForce(i, w);
    a.f_work.col(i) += w;
  }
}

void Gravity::addSpatialForces(const SpatialState& s, SpatialAssembly& a) const {
  const Eigen::Vector3d w_world = c_.point_mass * g_world_;
  for (int i = s.first; i < s.n; ++i) {
    a.addForce(i, w_world);
    a.f_work.col(i) += w_world;
  }
}

}  // namespace cws
