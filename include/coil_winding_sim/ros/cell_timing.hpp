// The winding cell's timing logic, apart from ROS's node machinery so that
// it runs without a master: pacing to a target real-time factor, setpoint
// stamp admission, the replay's following of another node's clock, the
// sim/ topics' grid of simulated time, and warnings throttled by wall
// time. Every time is passed in (wall seconds from a steady clock, ROS
// times as values), so tests drive them with a fake clock
// (test/ros/test_cell_timing.cpp).
#pragma once

#include <ros/time.h>

#include <mutex>
#include <optional>
#include <string>

#include "coil_winding_sim/core/run/pace_profile.hpp"

namespace cws_ros {

// Simulated time against wall time at a target real-time factor.
class PaceKeeper {
 public:
  // target_rtf: simulated seconds per wall second; 0: as fast as possible.
  void setTarget(double target_rtf) { target_ = target_rtf; }
  double target() const { return target_; }
  // A new pace from wall time wall_s [s] and simulated time sim_s [s].
  void restart(double wall_s, double sim_s) {
    wall0_ = wall_s;
    sim0_ = sim_s;
  }
  // Simulated seconds ahead of the pace (negative: behind; -1 without a
  // target, so that a run as fast as possible never waits).
  double ahead(double wall_s, double sim_s) const {
    if (target_ <= 0.0) return -1.0;
    return sim_s - (sim0_ + target_ * (wall_s - wall0_));
  }
  // Behind the pace by no more than 50 ms of wall time.
  bool keeping(double wall_s, double sim_s) const {
    return target_ <= 0.0 || ahead(wall_s, sim_s) > -0.05 * target_;
  }

 private:
  double target_ = 1.0;
  double wall0_ = 0.0, sim0_ = 0.0;
};

// Whether a run keeps its pace, judged as Gazebo users read a real-time
// factor: over the last second of wall time, not against every deficit
// since the start. A run keeps pace while its factor over the last second
// is at least 95 % of the target (in its first second: while it is within
// 50 ms of the target pace); it is slow once it has not kept pace for a
// second.
class PaceWindow {
 public:
  void restart(double wall_s, double sim_s) {
    n_ = 0;
    behind_since_s_ = -1.0;
    add(wall_s, sim_s);
  }
  // A sample after a chunk of steps; `near_pace`: within 50 ms of the pace.
  void update(double wall_s, double sim_s, double target, bool near_pace);
  // Not keeping pace for a second or more.
  bool slow() const { return slow_; }
  // The factor over the window [-] (0 before it spans any wall time).
  double factor() const { return factor_; }

 private:
  void add(double wall_s, double sim_s);
  static constexpr int kSize = 64;
  double wall_[kSize] = {}, sim_[kSize] = {};
  int n_ = 0, head_ = 0;
  double factor_ = 0.0, behind_since_s_ = -1.0;
  bool slow_ = false;
};

// Why a cell runs slower than its target, from the integrator's work over
// a stretch of wall time (from, to: cws::PaceProfile::count): the mean
// step, the steps retried, and for Newton steps the iterations and
// factorizations per accepted step; with the explicit fallback's cause
// when one began in the stretch. Empty when no step was accepted.
std::string slowCause(const cws::WorkCount& from, const cws::WorkCount& to,
                      long fallbacks_in_stretch, const std::string& fallback_cause);

// The replay's target (~follow_clock): the simulated time may advance to
// the clock since the origin less the lag (setpoints stamped up to there
// have arrived), never beyond the bag's end; to the whole bag once its clock
// has reached the end, or stalled within the lag of it for 5 s of wall time,
// and 0.5 s of wall time has passed for the last messages.
class ReplayClock {
 public:
  ReplayClock(double lag_s, std::optional<double> bag_end_s) : lag_s_(lag_s), end_s_(bag_end_s) {}
  // The bag's start on the ROS clock (else the first clock seen).
  void setOrigin(const ros::Time& origin) {
    origin_ = origin;
    have_origin_ = true;
  }
  bool haveOrigin() const { return have_origin_; }
  const ros::Time& origin() const { return origin_; }
  const std::optional<double>& end() const { return end_s_; }
  // The target [s] at ROS time `now` and wall time wall_s [s]; negative
  // before the first clock.
  double target(const ros::Time& now, double wall_s);

 private:
  double lag_s_;
  std::optional<double> end_s_;
  bool have_origin_ = false, end_seen_ = false;
  ros::Time origin_, last_clock_;
  double last_clock_wall_s_ = 0.0, end_seen_wall_s_ = 0.0;
};

// The grid of simulated time the cell publishes its samples on: the fast
// sim/ topics (spindle, tension, port), the frames (TF and joint_states) and
// the profile, each at its own rate [Hz]. Steps end on the grid, so each
// sample shows the state at its stamp, and a replay's output is the same
// whatever the pace.
class PublishGrid {
 public:
  enum Channel { kFast, kFrames, kProfile, kChannels };
  PublishGrid(double fast_hz, double frames_hz, double profile_hz)
      : hz_{fast_hz, frames_hz, profile_hz} {}
  // A channel's rate [Hz]; restart() puts it into effect.
  void setRate(Channel c, double hz) { hz_[c] = hz; }
  // The grid from simulated time t [s] on (a new run).
  void restart(double t);
  // The next grid time of any channel [s].
  double next() const;
  struct Due {
    bool fast = false, frames = false, profile = false;
  };
  // What is due at t (within the simulation's time tolerance), moving the
  // grid past t.
  Due take(double t);

 private:
  double hz_[kChannels];
  long index_[kChannels] = {0, 0, 0};
  double next_s_[kChannels] = {0.0, 0.0, 0.0};
};

// Warnings at most once a second of wall time, counting those left out.
// (ROS_WARN_THROTTLE counts ROS time: with ~publish_clock that is the
// simulated time, and one second of it can take minutes.) Thread-safe.
class WallThrottle {
 public:
  // At most one warning per `period_s` of wall time (default 1 s).
  WallThrottle() = default;
  explicit WallThrottle(double period_s) : period_s_(period_s) {}

  // True when a warning is due at wall time wall_s [s]; `skipped` is the
  // number suppressed since the last one. The text of a suppressed warning
  // is kept for overdue().
  bool due(double wall_s, int& skipped, const std::string& text = std::string());

  // Warnings suppressed and not reported by a later one: once the period
  // has passed, true with the last suppressed text and their number (so a
  // burst inside one period is not lost when nothing follows it).
  bool overdue(double wall_s, std::string& text, int& skipped);

 private:
  double period_s_ = 1.0;
  std::mutex mutex_;
  bool warned_ = false;
  double last_s_ = 0.0;
  int skipped_ = 0;
  std::string held_;  // the last suppressed text
};

}  // namespace cws_ros
