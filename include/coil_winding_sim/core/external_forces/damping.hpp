// Viscous damping of the wire against the surrounding air (world frame):
// translational and rotational, proportional to the length a point stands for.
#pragma once

#include "coil_winding_sim/core/base/wire_types.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

class Damping : public ForceEffect {
 public:
  Damping(const WireConstants& c, const DampingParams& p) : c_(c), p_(p) {}
  // New coefficients from the next evaluation on (Simulation::setDamping).
  void setParams(const DampingParams& p) { p_ = p; }
  const char* name() const override { return "damping"; }
  void addForces(double t, const WireKinematics& k, WireForces& f) const override;
  void addPlanarForces(const PlanarState& s, PlanarAssembly& a) const override;
  void addSpatialForces(const SpatialState& s, SpatialAssembly& a) const override;

 private:
  const WireConstants& c_;  // the model's: n grows with a supply
  DampingParams p_;
};

}  // namespace cws
