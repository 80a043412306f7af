// What a running cell has received and not yet applied, without ROS: the
// node's callbacks put setpoints in (any thread), stamped in nanoseconds of
// their sender's clock; its loop takes them out between steps, gives each
// its simulated time and queues it, and applies the due ones
// (Simulation::apply). A stamp is admitted once per topic in order: none
// further ahead of the clock than a tolerance, none older than the topic's
// last; a refusal's text names the stamp and the rule.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "coil_winding_sim/core/run/command_schedule.hpp"
#include "coil_winding_sim/core/run/setpoint.hpp"

namespace cws {

class SetpointInbox {
 public:
  // A setpoint as received: its topic (for messages), its stamp [ns] on
  // the sender's clock (0: none, at once), the setpoint.
  struct Received {
    std::string topic;
    std::int64_t stamp_ns = 0;
    Setpoint setpoint;
  };
  // A schedule received at once (a trajectory): setpoints at offsets [s]
  // from its stamp. Each kind it holds replaces what remains queued of that
  // kind from its start on.
  struct Schedule {
    std::string topic;
    std::int64_t stamp_ns = 0;
    std::vector<std::pair<double, Setpoint>> points;
  };
  // A port sample waiting for room in the port's path.
  struct PortSample {
    double t_s;  // simulated time [s]; NaN: a move time after it is applied
    Eigen::Vector3d p_world;
    std::string topic;
  };
  enum class Verdict { kAdmitted, kAhead, kOutOfOrder };

  // Stamps further ahead of the clock than stamp_tolerance_s [s] are refused.
  explicit SetpointInbox(double stamp_tolerance_s) : tolerance_s_(stamp_tolerance_s) {}

  // --- The callbacks (any thread).
  // Admits a stamp [ns] of `topic` against the clock [ns]: `have_clock`
  // false: there is no clock to compare with yet (ROS time before the first
  // /clock). When the clock goes back (a looping bag) every topic forgets
  // its last stamp. `why` names a refusal.
  Verdict admit(const std::string& topic, std::int64_t stamp_ns, std::int64_t clock_ns,
                bool have_clock, std::string& why);
  void put(Received r);
  void put(Schedule s);

  // --- The loop (one thread).
  // Hands what was received since the last call to on_setpoint(Received&)
  // and on_schedule(Schedule&), each kind in arrival order.
  template <class OnSetpoint, class OnSchedule>
  void take(OnSetpoint on_setpoint, OnSchedule on_schedule) {
    std::vector<Received> r;
    std::vector<Schedule> s;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      r.swap(received_);
      s.swap(schedules_);
    }
    for (Received& x : r) on_setpoint(x);
    for (Schedule& x : s) on_schedule(x);
  }
  // Setpoints by simulated time (-infinity: at the next chance).
  CommandSchedule& due() { return due_; }
  // Port samples in arrival order.
  std::deque<PortSample>& ports() { return ports_; }
  // A new run (reset, restore): every topic's last stamp and the queued
  // port samples are forgotten.
  void clear();

 private:
  double tolerance_s_;
  std::mutex mutex_;  // guards the stamps and what was received
  std::map<std::string, std::int64_t> last_ns_;
  std::int64_t last_clock_ns_ = 0;
  std::vector<Received> received_;
  std::vector<Schedule> schedules_;
  CommandSchedule due_;
  std::deque<PortSample> ports_;
};

}  // namespace cws
