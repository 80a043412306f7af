// Setpoints scheduled by simulated time: each takes effect when the simulated time reaches its
// time. The node's replay queue (setpoints applied at their stamps) and the stability study's speed
// events both run on it; steps end at nextTime(), so a command takes effect at its time whatever
// the step. (A port position is a point of a path rather than a switch, and has its own queue:
// PortTrajectory.)
#pragma once

#include <iterator>
#include <limits>
#include <map>

#include "coil_winding_sim/core/run/setpoint.hpp"

namespace cws {

class CommandSchedule {
 public:
  // At simulated time t_s [s]; -infinity: at the next chance. Commands at
  // equal times keep the order they were added in.
  void add(double t_s, const Setpoint& c) { queue_.emplace(t_s, c); }
  // The earliest command's time [s]; +infinity when none is left.
  double nextTime() const {
    return queue_.empty() ? std::numeric_limits<double>::infinity() : queue_.begin()->first;
  }
  bool empty() const { return queue_.empty(); }
  std::size_t size() const { return queue_.size(); }
  void clear() { queue_.clear(); }
  // Removes the commands of `kind` at t_s [s] or later (a new trajectory
  // replaces what remains of the one before).
  void dropFrom(double t_s, Setpoint::Kind kind) {
    for (auto it = queue_.lower_bound(t_s); it != queue_.end();) {
      it = it->second.kind == kind ? queue_.erase(it) : std::next(it);
    }
  }
  // Hands every command due at time t [s] (within the time tolerance of
  // PortTrajectory::timeTolerance) to apply(t_s, command) in time order and
  // removes it. Returns the number applied.
  template <class Apply>
  int takeDue(double t, Apply apply) {
    int taken = 0;
    const double due = t + tolerance(t);
    while (!queue_.empty() && queue_.begin()->first <= due) {
      const auto first = queue_.begin();
      apply(first->first, first->second);
      queue_.erase(first);
      ++taken;
    }
    return taken;
  }

 private:
  static double tolerance(double t);
  std::multimap<double, Setpoint> queue_;
};

}  // namespace cws
