#include "coil_winding_sim/core/run/setpoint.hpp"

#include <cstddef>

#include "coil_winding_sim/core/run/simulation.hpp"

namespace cws {

void Setpoint::applyTo(Simulation& sim) const {
  switch (kind) {
    case Kind::kCoreSpeed:
      sim.setCoreSpeed(value);
      return;
    case Kind::kSupplyTension:
      sim.setSupplyTension(value);
      return;
    case Kind::kPortPosition:
      sim.setPortCommand(p_world, value);
      return;
    case Kind::kFriction:
      sim.setFriction(value, value2);
      return;
    case Kind::kDamping:
      sim.setDamping(DampingParams{value, value2});
      return;
  }
}

const char* Setpoint::name() const {
  // In the order of Kind's values.
  static const char* const kNames[] = {"core speed", "supply tension", "port position", "friction",
                                       "damping"};
  const auto i = static_cast<std::size_t>(kind);
  return i < sizeof kNames / sizeof kNames[0] ? kNames[i] : "setpoint";
}

}  // namespace cws
