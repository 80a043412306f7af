#include "coil_winding_sim/core/run/command_schedule.hpp"

#include "coil_winding_sim/core/external_forces/port_trajectory.hpp"

namespace cws {

double CommandSchedule::tolerance(double t) { return PortTrajectory::timeTolerance(t); }

}  // namespace cws
