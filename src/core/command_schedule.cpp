#include "coil_winding_sim/core/command_schedule.hpp"

#include "coil_winding_sim/core/external_forces/port_trajectory.hpp"
#include "coil_winding_sim/core/simulation.hpp"

namespace cws {

double CommandSchedule::tolerance(double t) { return PortTrajectory::timeTolerance(t); }

void applyCommand(Simulation& sim, const Command& c) {
  if (c.kind == Command::Kind::kCoreSpeed) {
    sim.setCoreSpeed(c.value);
  } else {
    sim.setSupplyTension(c.value);
  }
}

}  // namespace cws
