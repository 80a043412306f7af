// The inputs a run accepted while it ran (setpoints: core speed, tension,
// port commands, friction), each with the simulated time it was given at,
// so that the run can be repeated from its start with another solver
// setting: the ROS node's ~error_estimate runs a finished job again at a
// quarter of the step and compares the two. Simulation::apply keeps one.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "coil_winding_sim/core/run/setpoint.hpp"

namespace cws {

class Simulation;

class InputLog {
 public:
  // Inputs kept at most; beyond it the log is marked overflowed and a
  // replay is refused (one input is 64 bytes: 64 MB).
  static constexpr std::size_t kCapacity = 1000000;

  struct Input {
    double t_s = 0.0;  // simulated time it was given at [s]
    Setpoint setpoint;
  };

  // Forgets every input (a new run).
  void clear();
  // Records a setpoint given to the run at simulated time t_s [s]. Record
  // after the run accepted it: an input it refused did not happen.
  void record(double t_s, const Setpoint& setpoint);
  // The inputs from the first-th on (a job that began after them).
  InputLog since(std::size_t first) const;

  std::size_t size() const { return inputs_.size(); }
  bool overflowed() const { return overflowed_; }
  const std::vector<Input>& inputs() const { return inputs_; }

  // Steps `sim` from its present time to t_end_s [s], giving each input
  // when the simulated time reaches its time (steps end there). Returns
  // false when `stop` (asked before every step) said stop. Throws
  // std::logic_error for an overflowed log, and what Simulation::step and
  // the setters throw.
  bool replay(Simulation& sim, double t_end_s, const std::function<bool()>& stop = {}) const;

 private:
  std::vector<Input> inputs_;
  bool overflowed_ = false;
};

}  // namespace cws
