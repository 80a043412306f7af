// Force and moment applied to the free end (the last mass point and its
// frame), following a piecewise-linear schedule in time; written once on
// the force sink (assembly/force_sink.hpp).
#pragma once

#include <vector>

#include "coil_winding_sim/core/assembly/force_effect.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

class EndLoad : public SinkEffect<EndLoad> {
 public:
  EndLoad(const WireConstants& c, const std::vector<LoadKeyframe>& schedule)
      : SinkEffect(c), schedule_(schedule) {}
  const char* name() const override { return "end_load"; }

  // Interpolated force [N] and moment [N m] in the world frame at time t [s].
  void loadAt(double t, Eigen::Vector3d& force_world, Eigen::Vector3d& moment_world) const;

  template <class Sink>
  void law(Sink& s) const {
    Eigen::Vector3d force_world, moment_world;
    loadAt(s.t(), force_world, moment_world);
    const int tip = s.n() - 1;
    s.addPointForce(tip, force_world, ForcePower::kApplied);
    // The moment turns the tip's frame; its power is m . omega_world.
    if (!moment_world.isZero()) s.addFrameMoment(tip, moment_world, ForcePower::kApplied);
  }

 private:
  std::vector<LoadKeyframe> schedule_;
};

}  // namespace cws
