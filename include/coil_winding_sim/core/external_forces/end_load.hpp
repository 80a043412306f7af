// Force and moment applied to the free end (the last mass point and its
// frame), following a piecewise-linear schedule in time.
#pragma once

#include <vector>

#include "coil_winding_sim/core/base/wire_types.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

class EndLoad : public ForceEffect {
 public:
  EndLoad(const WireConstants& c, const std::vector<LoadKeyframe>& schedule)
      : c_(c), schedule_(schedule) {}
  const char* name() const override { return "end_load"; }
  void addForces(double t, const WireKinematics& k, WireForces& f) const override;
  void addPlanarForces(const PlanarState& s, PlanarAssembly& a) const override;
  void addSpatialForces(const SpatialState& s, SpatialAssembly& a) const override;

  // Interpolated force [N] and moment [N m] in the world frame at time t [s].
  void loadAt(double t, Eigen::Vector3d& force_world, Eigen::Vector3d& moment_world) const;

 private:
  const WireConstants& c_;  // the model's: n grows with a supply
  std::vector<LoadKeyframe> schedule_;
};

}  // namespace cws
