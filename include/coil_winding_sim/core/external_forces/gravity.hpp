// Uniform gravity on the free mass points: the weight M g of each.
#pragma once

#include "coil_winding_sim/core/external_forces/point_force_effect.hpp"

namespace cws {

class Gravity : public PointForceEffect {
 public:
  Gravity(const WireConstants& c, const Eigen::Vector3d& g_world)
      : PointForceEffect(c, Power::kApplied, /*constant=*/true), g_world_(g_world) {}
  const char* name() const override { return "gravity"; }
  void pointLaw(double, const Eigen::Vector3d&, const Eigen::Vector3d&, bool,
                PointForce& out) const override {
    out.f_world = c_.point_mass * g_world_;
  }

 private:
  Eigen::Vector3d g_world_;  // [m/s^2]
};

}  // namespace cws
