#include "coil_winding_sim/ros/job_error_estimate.hpp"

#include <cstdio>
#include <exception>
#include <limits>
#include <memory>
#include <optional>

#include "coil_winding_sim/ErrorEstimate.h"
#include "coil_winding_sim/core/run/error_estimate.hpp"
#include "coil_winding_sim/ros/bridge.hpp"

namespace cws_ros {

JobErrorEstimator::JobErrorEstimator(ros::NodeHandle nh) {
  pub_ = nh.advertise<coil_winding_sim::ErrorEstimate>("error_estimate", 1, true);
}

JobErrorEstimator::~JobErrorEstimator() { stopWorker(); }

void JobErrorEstimator::stopWorker() {
  if (!worker_.joinable()) return;
  stop_ = true;
  worker_.join();
  stop_ = false;
}

void JobErrorEstimator::setStatus(const std::string& status) {
  std::lock_guard<std::mutex> lock(status_mutex_);
  status_ = status;
}

void JobErrorEstimator::startJob(const cws::Simulation& sim) {
  start_ = sim.saveState();
  first_input_ = sim.inputs().size();
  finished_ = false;
}

void JobErrorEstimator::finishJob(const cws::Simulation& finished, double compute_s,
                                  const ros::Time& stamp) {
  if (finished_) return;
  finished_ = true;
  stopWorker();
  setStatus("running the job again refined");
  // The worker gets its own copies: the node goes on with its simulation.
  busy_ = true;
  worker_ = std::thread([this, start = start_, log = finished.inputs().since(first_input_),
                         end = finished.saveState(), compute_s, stamp] {
    // Settled when the worker ends, however it ends.
    struct Settle {
      std::atomic<bool>& busy;
      ~Settle() { busy = false; }
    } settle{busy_};
    const int inputs = static_cast<int>(log.size());
    cws::ErrorEstimate e;
    std::string failure;
    try {
      const std::unique_ptr<cws::Simulation> job = cws::Simulation::fromState(end);
      const std::optional<cws::ErrorEstimate> got =
          cws::estimateFromInputs(start, log, *job, [this] { return stop_.load(); });
      if (!got) {
        setStatus("stopped: a new job ended before the estimate of the last one");
        return;
      }
      e = *got;
      e.wall_s = compute_s;
    } catch (const std::exception& ex) {
      failure = ex.what();
    }
    pub_.publish(toErrorEstimateMsg(e, end.time_s, inputs, failure, stamp));
    char text[256];
    if (failure.empty()) {
      std::snprintf(
          text, sizeof text,
          "shape %.3g of the wire diameter, bulging %.3g, against the job with %s "
          "(%.3g s of steps against %.3g s)",
          e.shape_error_rel_diameter,
          e.bulging_valid ? e.bulging_error_rel : std::numeric_limits<double>::quiet_NaN(),
          e.refinement.c_str(), e.wall_s, e.refined_wall_s);
      ROS_INFO("winding_cell: error estimate of the job ended at t = %.6f s: %s", end.time_s, text);
      setStatus(text);
      std::lock_guard<std::mutex> lock(status_mutex_);
      latest_.shape = e.shape_error_rel_diameter;
      latest_.bulging =
          e.bulging_valid ? e.bulging_error_rel : std::numeric_limits<double>::quiet_NaN();
      latest_.sim_time = end.time_s;
      ++latest_.count;
    } else {
      ROS_WARN("winding_cell: no error estimate of the job ended at t = %.6f s: %s", end.time_s,
               failure.c_str());
      setStatus("failed: " + failure);
    }
  });
}

JobErrorEstimator::Latest JobErrorEstimator::latest() const {
  std::lock_guard<std::mutex> lock(status_mutex_);
  return latest_;
}

void JobErrorEstimator::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) const {
  std::lock_guard<std::mutex> lock(status_mutex_);
  stat.add("error estimate", status_);
}

}  // namespace cws_ros
