#include "coil_winding_sim/core/run/input_log.hpp"

#include <algorithm>
#include <stdexcept>

#include "coil_winding_sim/core/external_forces/port_trajectory.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"

namespace cws {

void InputLog::clear() {
  inputs_.clear();
  overflowed_ = false;
}

void InputLog::record(double t_s, const Setpoint& setpoint) {
  if (inputs_.size() >= kCapacity) {
    overflowed_ = true;
    return;
  }
  inputs_.push_back({t_s, setpoint});
}

InputLog InputLog::since(std::size_t first) const {
  InputLog out;
  out.overflowed_ = overflowed_;
  if (first < inputs_.size()) out.inputs_.assign(inputs_.begin() + first, inputs_.end());
  return out;
}

bool InputLog::replay(Simulation& sim, double t_end_s, const std::function<bool()>& stop) const {
  if (overflowed_) {
    throw std::logic_error("the input log overflowed (more than " + std::to_string(kCapacity) +
                           " inputs): the run cannot be repeated");
  }
  std::size_t next = 0;
  // Gives every input whose time the run has reached (within rounding).
  auto giveDue = [&] {
    const double tol = PortTrajectory::timeTolerance(sim.time());
    while (next < inputs_.size() && inputs_[next].t_s <= sim.time() + tol) {
      sim.apply(inputs_[next++].setpoint);
    }
  };
  giveDue();
  while (sim.time() < t_end_s - PortTrajectory::timeTolerance(t_end_s)) {
    if (stop && stop()) return false;
    const double limit = next < inputs_.size() ? std::min(t_end_s, inputs_[next].t_s) : t_end_s;
    sim.step(limit);
    giveDue();
  }
  return true;
}

}  // namespace cws
