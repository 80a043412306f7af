// The node's ~error_estimate: every job's start state and the inputs it
// received (cws::InputLog); at the job's end, the job run again with the
// refined setting on a worker thread (cws::estimateFromInputs), the result
// published latched on `error_estimate` (coil_winding_sim/ErrorEstimate) and
// shown in /diagnostics. The node's own steps never wait for it.
#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>

#include <atomic>
#include <limits>
#include <mutex>
#include <string>
#include <thread>

#include "coil_winding_sim/core/run/input_log.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"

namespace cws_ros {

class JobErrorEstimator {
 public:
  explicit JobErrorEstimator(ros::NodeHandle nh);
  // Stops a refined run under way and waits for it.
  ~JobErrorEstimator();
  JobErrorEstimator(const JobErrorEstimator&) = delete;
  JobErrorEstimator& operator=(const JobErrorEstimator&) = delete;

  // A new job from the present state of `sim` (the scene's start, a reset,
  // a restored snapshot): its inputs are those `sim` logs from here on.
  void startJob(const cws::Simulation& sim);
  // The job ended at finished.time() after compute_s [s] of wall time in its
  // steps: its refined twin runs on the worker (a refined run of an earlier
  // job still under way is stopped first). Once per job.
  void finishJob(const cws::Simulation& finished, double compute_s, const ros::Time& stamp);
  // True once the present job's estimate is published (or never will be:
  // the job has not ended).
  bool settled() const { return !busy_; }
  // The last published estimate (cell_status): NaN fields while there is
  // none; count grows by one with each.
  struct Latest {
    double shape = std::numeric_limits<double>::quiet_NaN();     // [d]
    double bulging = std::numeric_limits<double>::quiet_NaN();   // relative [-]
    double sim_time = std::numeric_limits<double>::quiet_NaN();  // the job's end [s]
    int count = 0;
  };
  Latest latest() const;
  // Adds the estimate's state to the node's diagnostics.
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) const;

 private:
  void stopWorker();
  void setStatus(const std::string& status);

  ros::Publisher pub_;
  cws::SimulationState start_;
  std::size_t first_input_ = 0;  // the job's first in the simulation's log
  bool finished_ = false;        // finishJob called for the present job
  std::thread worker_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> busy_{false};  // a refined run under way
  mutable std::mutex status_mutex_;
  std::string status_ = "the job has not ended yet";
  Latest latest_;  // under status_mutex_
};

}  // namespace cws_ros
