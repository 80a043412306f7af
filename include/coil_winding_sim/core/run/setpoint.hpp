// One input to a running simulation: what a machine or a user sets while
// it runs. Each kind knows how it is applied to a Simulation (applyTo) and
// how it is named in logs; Simulation::apply applies one and logs it
// (InputLog), so that a run can be repeated with the inputs it accepted
// (the error estimate, snapshots). Adding a setpoint: its Kind, its
// factory, its case in applyTo and in name() (src/core/run/setpoint.cpp), and
// where the node receives it.
#pragma once

#include <Eigen/Core>

namespace cws {

class Simulation;

struct Setpoint {
  enum class Kind {
    kCoreSpeed,      // value [rad/s]
    kSupplyTension,  // value [N]
    kPortPosition,   // p_world [m] reached at the time `value` [s]
    kFriction,       // value static, value2 kinetic coefficient [-]
    kDamping,        // value translational [N s/m^2], value2 rotational [N m s/m]
  };
  Kind kind = Kind::kCoreSpeed;
  double value = 0.0;
  double value2 = 0.0;
  Eigen::Vector3d p_world = Eigen::Vector3d::Zero();

  static Setpoint coreSpeed(double omega_rad_s) { return {Kind::kCoreSpeed, omega_rad_s}; }
  static Setpoint supplyTension(double tension_N) { return {Kind::kSupplyTension, tension_N}; }
  static Setpoint portPosition(const Eigen::Vector3d& p_world, double at_s) {
    return {Kind::kPortPosition, at_s, 0.0, p_world};
  }
  static Setpoint friction(double mu_static, double mu_kinetic) {
    return {Kind::kFriction, mu_static, mu_kinetic};
  }
  static Setpoint damping(double translational, double rotational) {
    return {Kind::kDamping, translational, rotational};
  }

  // Applies it to `sim` now; throws what the simulation's setter throws
  // for a value it refuses (std::invalid_argument, SceneError).
  void applyTo(Simulation& sim) const;
  // Its name in messages and logs, e.g. "core speed".
  const char* name() const;
};

}  // namespace cws
