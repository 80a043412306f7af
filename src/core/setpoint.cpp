#include "coil_winding_sim/core/setpoint.hpp"

#include "coil_winding_sim/core/simulation.hpp"

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
  }
}

const char* Setpoint::name() const {
  switch (kind) {
    case Kind::kCoreSpeed:
      return "core speed";
    case Kind::kSupplyTension:
      return "supply tension";
    case Kind::kPortPosition:
      return "port position";
    case Kind::kFriction:
      return "friction";
  }
  return "setpoint";
}

}  // namespace cws
