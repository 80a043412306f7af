// Where a run spent its wall time: the run is cut into stretches of
// kStretch of simulated time, and the one that ran slowest against real
// time is kept with the integrator's work inside it (steps, retried steps,
// Newton iterations and factorizations). summary.json reports it as
// "slowest_stretch", and the robustness suite names it per coil
// (docs/ROBUSTNESS.md). Fixed-size state: recording allocates nothing.
#pragma once

#include <limits>

#include "coil_winding_sim/core/time_steppers/time_stepper.hpp"

namespace cws {

// The integrator's work counted up to a moment of the run.
struct WorkCount {
  double t_s = 0.0;     // simulated time [s]
  double wall_s = 0.0;  // wall time [s]
  long steps = 0, rejected = 0, iterations = 0, factorizations = 0;
};

// One stretch of a run and the work done in it.
struct PaceStretch {
  bool valid = false;
  double start_s = 0.0, end_s = 0.0;  // simulated [s]
  double wall_s = 0.0;                // [s]
  long steps = 0, rejected = 0, iterations = 0, factorizations = 0;
  double realTimeFactor() const { return wall_s > 0.0 ? (end_s - start_s) / wall_s : 0.0; }
};

class PaceProfile {
 public:
  // Simulated time per stretch [s]: long enough that the wall time of a
  // stretch run near real time (50 ms) is well above the clock's and the
  // scheduler's jitter.
  static constexpr double kStretch = 0.05;

  // The work counted now (after an accepted step, or where a run starts).
  static WorkCount count(double t_s, double wall_s, const TimeStepper& stepper) {
    WorkCount c;
    c.t_s = t_s;
    c.wall_s = wall_s;
    c.steps = stepper.counts().accepted;
    c.rejected = stepper.counts().rejected;
    if (const NewtonCounts* n = stepper.newtonCounts()) {
      c.iterations = n->iterations;
      c.factorizations = n->factorizations;
    }
    return c;
  }

  // A run (or a continued one) starts at `now`.
  void start(const WorkCount& now) {
    open_ = now;
    started_ = true;
  }
  // After each accepted step: closes the stretch once it is kStretch long.
  void record(const WorkCount& now) {
    if (!started_) start(now);
    if (now.t_s - open_.t_s >= kStretch) close(now);
  }
  // At the end of a run: the open stretch counts too when it is at least
  // a fifth of a stretch long, or when it is all there is.
  void finish(const WorkCount& now) {
    if (!started_) return;
    const double length = now.t_s - open_.t_s;
    if (length > 0.0 && (length >= 0.2 * kStretch || !slowest_.valid)) close(now);
  }
  // The slowest stretch so far (valid = false before one has closed).
  const PaceStretch& slowest() const { return slowest_; }

 private:
  void close(const WorkCount& now) {
    PaceStretch s;
    s.valid = true;
    s.start_s = open_.t_s;
    s.end_s = now.t_s;
    s.wall_s = now.wall_s - open_.wall_s;
    s.steps = now.steps - open_.steps;
    s.rejected = now.rejected - open_.rejected;
    s.iterations = now.iterations - open_.iterations;
    s.factorizations = now.factorizations - open_.factorizations;
    if (!slowest_.valid || s.realTimeFactor() < slowest_.realTimeFactor()) slowest_ = s;
    open_ = now;
  }

  bool started_ = false;
  WorkCount open_;
  PaceStretch slowest_;
};

}  // namespace cws
