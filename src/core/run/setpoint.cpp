#include "coil_winding_sim/core/run/setpoint.hpp"

#include "coil_winding_sim/core/base/text_format.hpp"
#include "coil_winding_sim/core/external_forces/supply.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"

namespace cws {

const std::vector<SetpointRow>& setpointTable() {
  // (The targets are the simulation's private setters: this function is
  // its friend, and so are the lambdas within it.)
  static const std::vector<SetpointRow> rows = {
      {Setpoint::Kind::kCoreSpeed, "core speed", "rad/s", "process.max_core_speed_rpm",
       [](const SetpointLimits& l, const Setpoint& sp) { return coreSpeedRefusal(l, sp.value); },
       [](Simulation& sim, const Setpoint& sp) { sim.setCoreSpeed(sp.value); }, nullptr,
       "core_speed_setpoint", "angular_velocity", "machine/spindle/command", false},
      {Setpoint::Kind::kSupplyTension, "tension", "N", "process.max_tension",
       [](const SetpointLimits& l, const Setpoint& sp) { return tensionRefusal(l, sp.value); },
       [](Simulation& sim, const Setpoint& sp) { sim.setSupplyTension(sp.value); },
       [](const Simulation& sim, Setpoint& out) {
         if (!sim.model().supply()) return false;
         out = Setpoint::supplyTension(sim.model().supply()->tensionSetpoint());
         return true;
       },
       "tension_setpoint", "tension", "machine/tension/command", false},
      {Setpoint::Kind::kPortPosition, "port position", "s", "", nullptr,
       [](Simulation& sim, const Setpoint& sp) { sim.setPortCommand(sp.p_world, sp.value); },
       nullptr, "port_position_setpoint", "point", "machine/port/command", true},
      {Setpoint::Kind::kFriction, "friction", "",
       "contact.static_friction, contact.kinetic_friction", nullptr,
       [](Simulation& sim, const Setpoint& sp) { sim.setFriction(sp.value, sp.value2); },
       [](const Simulation& sim, Setpoint& out) {
         const Scene& scene = sim.scene();
         if (!scene.physics.friction) return false;
         out = Setpoint::friction(scene.contact.static_friction, scene.contact.kinetic_friction);
         return true;
       },
       "", "", "", false},
      {Setpoint::Kind::kDamping, "damping", "N s/m^2", "damping.translational, damping.rotational",
       nullptr,
       [](Simulation& sim, const Setpoint& sp) {
         sim.setDamping(DampingParams{sp.value, sp.value2});
       },
       [](const Simulation& sim, Setpoint& out) {
         const Scene& scene = sim.scene();
         if (!scene.physics.damping) return false;
         out = Setpoint::damping(scene.damping.translational, scene.damping.rotational);
         return true;
       },
       "", "", "", false},
  };
  return rows;
}

const SetpointRow& setpointRow(Setpoint::Kind kind) {
  return setpointTable().at(static_cast<std::size_t>(kind));
}

const SetpointRow* setpointRowNamed(const std::string& name) {
  for (const SetpointRow& row : setpointTable()) {
    if (name == row.name) return &row;
  }
  return nullptr;
}

const char* Setpoint::name() const { return setpointRow(kind).name; }

std::string setpointRefusal(const SetpointLimits& limits, const Setpoint& sp) {
  const SetpointRow& row = setpointRow(sp.kind);
  const std::string why = row.refusal ? row.refusal(limits, sp) : "";
  if (why.empty()) return why;
  return std::string(row.name) + " " + formatNumber(sp.value) + " " + row.unit + " " + why;
}

}  // namespace cws
