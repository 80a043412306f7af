// An effect whose law acts on each free mass point by the point's own
// position and velocity (gravity, air drag): the law is written once, in
// pointLaw(), on local quantities, and reaches every integrator through the
// force sink (assembly/force_sink.hpp).
#pragma once

#include <Eigen/Core>

#include "coil_winding_sim/core/assembly/force_effect.hpp"

namespace cws {

// The law's answer for one point: its force and the force's derivatives.
struct PointForce {
  Eigen::Vector3d f_world = Eigen::Vector3d::Zero();  // [N]
  Eigen::Matrix3d df_dp = Eigen::Matrix3d::Zero();    // d f / d p_world [N/m]
  Eigen::Matrix3d df_dv = Eigen::Matrix3d::Zero();    // d f / d v_world [N s/m]
};

class PointForceEffect : public SinkEffect<PointForceEffect> {
 public:
  // Whether the force does work on the wire (an applied load, booked in
  // the work done) or dissipates (booked as dissipated energy).
  using Power = ForcePower;
  // `constant`: the force depends on neither position nor velocity (no
  // Jacobian blocks are added).
  PointForceEffect(const WireConstants& c, Power power, bool constant = false)
      : SinkEffect(c), power_(power), constant_(constant) {}

  // The law at time t [s] for a point at p_world [m] moving at v_world
  // [m/s]: its force, and with `jacobian` its derivatives (else they may
  // be left as they are). Must not allocate or change state.
  virtual void pointLaw(double t, const Eigen::Vector3d& p_world, const Eigen::Vector3d& v_world,
                        bool jacobian, PointForce& out) const = 0;

  // Point 0 (and the wire the core carries) is held: its load goes to the
  // support, not the wire, so the law runs over the integrated points only.
  template <class Sink>
  void law(Sink& s) const {
    PointForce pf;
    for (int i = s.first(); i < s.n(); ++i) {
      const bool jac = !constant_ && s.jacobian(i);
      pointLaw(s.t(), s.p(i), s.v(i), jac, pf);
      s.addPointForce(i, pf.f_world, power_);
      if (!jac) continue;
      s.addPointStiffness(i, pf.df_dp);
      s.addPointDamping(i, pf.df_dv);
    }
  }

 private:
  Power power_;
  bool constant_;
};

}  // namespace cws
