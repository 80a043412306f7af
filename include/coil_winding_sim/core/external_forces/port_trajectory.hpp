// A commanded supply-port path: samples (t_s, p_world) joined by straight
// lines, the last sample held. The port moves continuously: the first
// command starts from where the port is, and a command that comes after the
// last sample has passed holds that sample until the present time first.
// Velocity is constant between samples (acceleration 0); a sample time is a
// velocity kink, and steps end there (Simulation::step, as at the end of a
// core speed ramp).
//
// Storage is a ring of kCapacity samples allocated once; samples behind the
// committed time are dropped at commit(), so the ring holds the path ahead
// of the simulated time. Nothing allocates during a step.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "coil_winding_sim/core/constraints/frame_constraints.hpp"

namespace cws {

class PortTrajectory {
 public:
  static constexpr int kCapacity = 4096;

  PortTrajectory();

  bool active() const { return size_ > 0; }
  int size() const { return size_; }
  int room() const { return kCapacity - size_; }
  // Time of the last sample [s] (-infinity when inactive).
  double lastTime() const;

  // Appends the sample (t_s, p_world). t_now is the committed time [s] and
  // p_now_world the port's position then (for the first sample, and to hold
  // the last one up to now). Throws std::invalid_argument naming what is
  // wrong (not finite, before t_now or the last sample, a jump, ring full);
  // nothing changes then.
  void append(double t_s, const Eigen::Vector3d& p_world, double t_now,
              const Eigen::Vector3d& p_now_world);

  // Port motion at time t within a step that starts at the committed time:
  // the straight line of the segment the committed time lies in (so every
  // stage of a step sees one segment, also at the step's end).
  PortMotion at(double t) const;
  // The first sample time after t [s] (beyond rounding), or infinity.
  double nextKink(double t) const;
  // Drops the samples the committed time t has passed.
  void commit(double t);

  // Flat copy for snapshots: t_s, x, y, z [m, world] per sample; restore
  // checks it (finite, times increasing, size) and throws
  // std::invalid_argument naming the problem, leaving the path unchanged.
  std::vector<double> exportState() const;
  void restoreState(const std::vector<double>& flat);

  // Rounding tolerance of sample times at time t [s].
  static double timeTolerance(double t);

 private:
  struct Sample {
    double t_s = 0.0;
    Eigen::Vector3d p_world = Eigen::Vector3d::Zero();
  };
  const Sample& sample(int k) const { return ring_[(head_ + k) % kCapacity]; }
  void push(double t_s, const Eigen::Vector3d& p_world);

  std::vector<Sample> ring_;
  int head_ = 0, size_ = 0;
};

}  // namespace cws
