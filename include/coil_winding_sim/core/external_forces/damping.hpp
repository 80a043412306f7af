// Viscous damping of the wire against the surrounding air (world frame):
// translational and rotational, proportional to the length a point stands
// for. The law is written once, on the force sink (assembly/force_sink.hpp):
// -c v on each point, -c omega on each frame.
#pragma once

#include "coil_winding_sim/core/assembly/force_effect.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

class Damping : public SinkEffect<Damping> {
 public:
  Damping(const WireConstants& c, const DampingParams& p) : SinkEffect(c), p_(p) {}
  // New coefficients from the next evaluation on (Simulation::setDamping).
  void setParams(const DampingParams& p) { p_ = p; }
  const char* name() const override { return "damping"; }

  template <class Sink>
  void law(Sink& s) const {
    const double c_lin = p_.translational * c_.point_length;  // [N s/m]
    const double c_rot = p_.rotational * c_.point_length;     // [N m s]
    const Eigen::Matrix3d id = Eigen::Matrix3d::Identity();
    for (int i = s.first(); i < s.n(); ++i) {
      s.addPointForce(i, -c_lin * s.v(i), ForcePower::kDissipative);
      if (s.jacobian(i)) s.addPointDamping(i, -c_lin * id);
      if (c_rot > 0.0)
        s.addFrameMoment(i, -c_rot * s.omega(i), ForcePower::kDissipative, -c_rot * id);
    }
  }

 private:
  DampingParams p_;
};

}  // namespace cws
