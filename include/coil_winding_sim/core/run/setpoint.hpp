// One input to a running simulation: what a machine or a user sets while
// it runs, and the table of every kind (setpointTable): its name and unit,
// the scene key that limits it, the model target it drives, and where a
// snapshot and the node carry it. Simulation::apply is the one way a
// setpoint reaches the model: it checks the row's limit, drives its target
// and logs it (InputLog), so that a run can be repeated with the inputs it
// accepted (the error estimate, snapshots). Adding a setpoint: its Kind and
// factory here, its row in setpointTable (src/core/run/setpoint.cpp), the
// model's target, and its message if it needs a new one (the node
// subscribes to a row's topic and machine topic, a machine bag's replay
// reads the latter, and a snapshot keeps what its row holds:
// winding_cell_inputs.cpp, ros/bridge.hpp).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "coil_winding_sim/core/scene/setpoint_limits.hpp"

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

  // Its name in messages and logs, e.g. "core speed" (its row's).
  const char* name() const;
};

// One kind of setpoint.
struct SetpointRow {
  Setpoint::Kind kind;
  const char* name;  // in messages and logs: "core speed"
  const char* unit;  // of Setpoint::value: "rad/s"
  // The scene keys that bound it ("": none but the model's own checks).
  const char* limit_key;
  // Why `sp` is refused under `limits`, as a predicate ("is above
  // process.max_tension = 300 N"); empty: allowed. Null: no limit.
  std::string (*refusal)(const SetpointLimits& limits, const Setpoint& sp);
  // Drives the model's target (the simulation's private setter); throws
  // what the model refuses (std::invalid_argument, SceneError), with the
  // run unchanged.
  void (*target)(Simulation& sim, const Setpoint& sp);
  // What a snapshot keeps of it: the setpoint it holds now
  // (SimulationState::held; false: none, as friction in a scene without
  // friction), applied again on restore. Null: the model's state carries
  // it (the core's motion reference, the port's path ahead).
  bool (*held)(const Simulation& sim, Setpoint& out);
  // The node's topic that sets it and its message's field ("": none; the
  // node subscribes to every topic named here).
  const char* topic;
  const char* message_field;
  // The machine interface's command topic that carries it
  // (docs/MACHINE_INTERFACE.md; "": none): the node subscribes to it with
  // ~machine_inputs, and a machine bag's replay reads it.
  const char* machine_topic;
  // A sample of a path, fed to the model ahead of its time while the
  // path has room (the port), rather than applied when its time comes;
  // Setpoint::value is that time [s].
  bool path_sample;
};

// Every kind, in the order of Kind's values.
const std::vector<SetpointRow>& setpointTable();
const SetpointRow& setpointRow(Setpoint::Kind kind);
// The row of that name ("tension"), or null.
const SetpointRow* setpointRowNamed(const std::string& name);
// Empty when `sp` is allowed under `limits`; else what is wrong with it,
// with its subject: "core speed 700 rad/s is beyond +-628.3 rad/s (...)".
std::string setpointRefusal(const SetpointLimits& limits, const Setpoint& sp);

}  // namespace cws
