// An effect whose law acts on each free mass point by the point's own
// position and velocity (gravity, air drag): the law is written once, in
// pointLaw(), on local quantities; this base maps it to the explicit
// model's generalized forces and to each Newton formulation's coordinates
// (the plane's two, or the world's three) and their Jacobian blocks.
#pragma once

#include <Eigen/Core>

#include "coil_winding_sim/core/base/wire_types.hpp"

namespace cws {

// The law's answer for one point: its force and the force's derivatives.
struct PointForce {
  Eigen::Vector3d f_world = Eigen::Vector3d::Zero();  // [N]
  Eigen::Matrix3d df_dp = Eigen::Matrix3d::Zero();    // d f / d p_world [N/m]
  Eigen::Matrix3d df_dv = Eigen::Matrix3d::Zero();    // d f / d v_world [N s/m]
};

class PointForceEffect : public ForceEffect {
 public:
  // Whether the force does work on the wire (an applied load, booked in
  // the work done) or dissipates (booked as dissipated energy).
  enum class Power { kApplied, kDissipative };
  // `constant`: the force depends on neither position nor velocity (no
  // Jacobian blocks are added).
  PointForceEffect(const WireConstants& c, Power power, bool constant = false)
      : c_(c), power_(power), constant_(constant) {}

  // The law at time t [s] for a point at p_world [m] moving at v_world
  // [m/s]: its force, and with `jacobian` its derivatives (else they may
  // be left as they are). Must not allocate or change state.
  virtual void pointLaw(double t, const Eigen::Vector3d& p_world, const Eigen::Vector3d& v_world,
                        bool jacobian, PointForce& out) const = 0;

  void addForces(double t, const WireKinematics& k, WireForces& f) const final;
  void addPlanarForces(const PlanarState& s, PlanarAssembly& a) const final;
  void addSpatialForces(const SpatialState& s, SpatialAssembly& a) const final;

 protected:
  const WireConstants& c_;  // the model's: n grows with a supply

 private:
  Power power_;
  bool constant_;
};

}  // namespace cws
