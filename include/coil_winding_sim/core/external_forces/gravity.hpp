// Uniform gravity on the free mass points.
#pragma once

#include "coil_winding_sim/core/wire_types.hpp"

namespace cws {

class Gravity : public ForceEffect {
 public:
  Gravity(const WireConstants& c, const Eigen::Vector3d& g_world) : c_(c), g_world_(g_world) {}
  const char* name() const override { return "gravity"; }
  void addForces(double t, const WireKinematics& k, WireForces& f) const override;
  void addPlanarForces(const PlanarState& s, PlanarAssembly& a) const override;
  void addSpatialForces(const SpatialState& s, SpatialAssembly& a) const override;

 private:
  const WireConstants& c_;   // the model's: n grows with a supply
  Eigen::Vector3d g_world_;  // [m/s^2]
};

}  // namespace cws
