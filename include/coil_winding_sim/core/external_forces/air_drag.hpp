// Quadratic air drag on the free mass points: the pressure drag of a
// cylinder of the wire's diameter d moving through still air,
//   f = -1/2 rho_air C_d d l |v| v
// over the length l a point stands for. The drag coefficient is that of
// flow across the cylinder, taken for every direction (the flow along the
// wire, whose drag is far smaller, is not told apart). A wire falling
// through air reaches v_t = sqrt(2 rho_wire g / (rho_air C_d d)) (rho_wire
// [kg/m]); test/unit/test_air_drag.cpp checks it.
#pragma once

#include "coil_winding_sim/core/external_forces/point_force_effect.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

class AirDrag : public PointForceEffect {
 public:
  AirDrag(const WireConstants& c, const AirDragParams& p)
      : PointForceEffect(c, Power::kDissipative), p_(p) {}
  const char* name() const override { return "air_drag"; }
  void pointLaw(double, const Eigen::Vector3d&, const Eigen::Vector3d& v_world, bool jacobian,
                PointForce& out) const override {
    // c [kg/m]: f = -c |v| v, d f / d v = -c (|v| I + v v^T / |v|).
    const double c = 0.5 * p_.density * p_.drag_coefficient * 2.0 * c_.radius * c_.point_length;
    const double speed = v_world.norm();
    out.f_world = -c * speed * v_world;
    if (!jacobian) return;
    out.df_dv = -c * speed * Eigen::Matrix3d::Identity();
    if (speed > 0.0) out.df_dv -= (c / speed) * v_world * v_world.transpose();
  }

 private:
  AirDragParams p_;
};

}  // namespace cws
