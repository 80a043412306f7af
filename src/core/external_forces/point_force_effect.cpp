#include "coil_winding_sim/core/external_forces/point_force_effect.hpp"

#include "coil_winding_sim/core/assembly/planar_assembly.hpp"
#include "coil_winding_sim/core/assembly/spatial_assembly.hpp"

namespace cws {

// Point 0 (and the wire the core carries) is held: its load goes to the
// support, not the wire, so the law runs over the integrated points only.

void PointForceEffect::addForces(double t, const WireKinematics& k, WireForces& f) const {
  PointForce pf;
  Eigen::Matrix3Xd& booked = power_ == Power::kApplied ? f.f_work_world : f.f_dissipative_world;
  for (int i = c_.first; i < c_.n; ++i) {
    pointLaw(t, k.p_world.col(i), k.v_world.col(i), false, pf);
    f.f_world.col(i) += pf.f_world;
    booked.col(i) += pf.f_world;
  }
}

void PointForceEffect::addPlanarForces(const PlanarState& s, PlanarAssembly& a) const {
  // The plane's basis E = [e1 e2] maps world to plane: f = E^T f_world,
  // d f / d x = E^T (d f_world / d p) E (a planar scene's laws have
  // nothing along the normal that matters to its motion).
  Eigen::Matrix<double, 3, 2> e;
  e.col(0) = s.plane.e1_world;
  e.col(1) = s.plane.e2_world;
  Eigen::Matrix2Xd& booked = power_ == Power::kApplied ? a.f_work : a.f_dissipative;
  const bool jac = !constant_ && a.wantsJacobian();
  PointForce pf;
  for (int i = s.first; i < s.n; ++i) {
    pointLaw(s.t, s.plane.toWorld(s.x.col(i)), s.plane.vectorToWorld(s.v.col(i)), jac, pf);
    const Eigen::Vector2d f = s.plane.vectorToPlane(pf.f_world);
    a.addForce(i, f);
    booked.col(i) += f;
    if (!jac) continue;
    a.addStiffness(i, i, e.transpose() * pf.df_dp * e);
    a.addDamping(i, i, e.transpose() * pf.df_dv * e);
  }
}

void PointForceEffect::addSpatialForces(const SpatialState& s, SpatialAssembly& a) const {
  Eigen::Matrix3Xd& booked = power_ == Power::kApplied ? a.f_work : a.f_dissipative;
  PointForce pf;
  for (int i = s.first; i < s.n; ++i) {
    const bool jac = !constant_ && a.wantsJacobianAt(i);
    pointLaw(s.t, s.p.col(i), s.v.col(i), jac, pf);
    a.addForce(i, pf.f_world);
    booked.col(i) += pf.f_world;
    if (!jac) continue;
    a.addStiffnessPP(i, i, pf.df_dp);
    a.addDampingPP(i, i, pf.df_dv);
  }
}

}  // namespace cws
