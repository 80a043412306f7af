// The inputs a run received while it ran (core speed and tension setpoints,
// port commands), each with the simulated time it was given at, so that the
// run can be repeated from its start with another solver setting: the ROS
// node's ~error_estimate runs a finished job again at a quarter of the step
// and compares the two.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <functional>
#include <vector>

namespace cws {

class Simulation;

class InputLog {
 public:
  // Inputs kept at most; beyond it the log is marked overflowed and a
  // replay is refused (one input is 48 bytes: 48 MB).
  static constexpr std::size_t kCapacity = 1000000;

  enum class Kind { kCoreSpeed, kSupplyTension, kPortCommand };
  struct Input {
    double t_s = 0.0;  // simulated time it was given at [s]
    Kind kind = Kind::kCoreSpeed;
    double value = 0.0;  // [rad/s] or [N]; for a port command its time [s]
    Eigen::Vector3d p_world = Eigen::Vector3d::Zero();  // port command [m]
  };

  // Forgets every input (a new run).
  void clear();
  // Records an input given to the run at simulated time t_s [s]. Record
  // after the run accepted it: an input it refused did not happen.
  void coreSpeed(double t_s, double omega_rad_s);
  void supplyTension(double t_s, double tension_N);
  void portCommand(double t_s, const Eigen::Vector3d& p_world, double at_s);

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
  void add(const Input& in);
  std::vector<Input> inputs_;
  bool overflowed_ = false;
};

}  // namespace cws
