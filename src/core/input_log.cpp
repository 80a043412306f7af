#include "coil_winding_sim/core/input_log.hpp"

#include <algorithm>
#include <stdexcept>

#include "coil_winding_sim/core/external_forces/port_trajectory.hpp"
#include "coil_winding_sim/core/simulation.hpp"

namespace cws {

void InputLog::clear() {
  inputs_.clear();
  overflowed_ = false;
}

void InputLog::add(const Input& in) {
  if (inputs_.size() >= kCapacity) {
    overflowed_ = true;
    return;
  }
  inputs_.push_back(in);
}

void InputLog::coreSpeed(double t_s, double omega_rad_s) {
  add({t_s, Kind::kCoreSpeed, omega_rad_s, Eigen::Vector3d::Zero()});
}

void InputLog::supplyTension(double t_s, double tension_N) {
  add({t_s, Kind::kSupplyTension, tension_N, Eigen::Vector3d::Zero()});
}

void InputLog::portCommand(double t_s, const Eigen::Vector3d& p_world, double at_s) {
  add({t_s, Kind::kPortCommand, at_s, p_world});
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
      const Input& in = inputs_[next++];
      switch (in.kind) {
        case Kind::kCoreSpeed:
          sim.setCoreSpeed(in.value);
          break;
        case Kind::kSupplyTension:
          sim.setSupplyTension(in.value);
          break;
        case Kind::kPortCommand:
          sim.setPortCommand(in.p_world, in.value);
          break;
      }
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
