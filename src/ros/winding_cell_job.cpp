// The winding cell's job: when it ends (the core's actual turns, or
// process.duration), what the node says then, and the cell's state on
// cell_status and /diagnostics (winding_cell.hpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "coil_winding_sim/core/base/text_format.hpp"
#include "coil_winding_sim/core/run/coil_report.hpp"
#include "coil_winding_sim/core/run/quality_report.hpp"
#include "coil_winding_sim/ros/winding_cell.hpp"

namespace cws_ros {

// The job's end: process.duration when the scene sets it, else
// process.turns of the core's actual rotation (whatever speeds the
// setpoints gave it).
bool WindingCell::jobEnded() const {
  if (scene_.process.duration) return sim_->time() >= *scene_.process.duration;
  const cws::RotatingCore* core = sim_->model().core();
  if (!core) return sim_->time() >= sim_->endTime();
  // At the end time found for the present command, where the last step
  // ends, whatever the last bits of the angle there (as a wind goal's).
  if (core->command() == job_end_command_ && sim_->time() >= job_end_s_) return true;
  return std::abs(core->angle(sim_->time())) >= 2.0 * M_PI * scene_.process.turns * (1.0 - 1e-12);
}

// When the job ends if the core keeps its present command [s] (+inf:
// never).
double WindingCell::jobEndTime() const {
  if (scene_.process.duration) return *scene_.process.duration;
  if (!sim_->model().core()) return sim_->endTime();
  // (Found again only when the command changes: the core's motion under
  // one command is one closed form.)
  const double command = sim_->model().core()->command();
  if (command != job_end_command_) {
    job_end_command_ = command;
    job_end_s_ = timeAtTurns(0.0, scene_.process.turns);
  }
  return job_end_s_;
}

// The first time the core's angle lies `turns` turns from start_angle_rad
// [rad] if it keeps its present command [s] (+inf: never; now if it does
// already), found on its closed-form motion (ramp, then constant speed).
double WindingCell::timeAtTurns(double start_angle_rad, double turns) const {
  const cws::RotatingCore* core = sim_->model().core();
  const double target = 2.0 * M_PI * turns;
  const double t0 = sim_->time();
  auto reached = [&](double t) {
    return std::abs(core->angle(t) - start_angle_rad) >= target * (1.0 - 1e-12);
  };
  if (reached(t0)) return t0;
  double h = 1e-3;
  while (!reached(t0 + h)) {
    h *= 2.0;
    if (h > 1e6) return std::numeric_limits<double>::infinity();
  }
  double lo = t0, hi = t0 + h;
  for (int i = 0; i < 200 && hi - lo > 1e-13 * std::max(1.0, hi); ++i) {
    const double mid = 0.5 * (lo + hi);
    (reached(mid) ? hi : lo) = mid;
  }
  return hi;
}

// Running until stopped (neither ~stop_at_end nor ~follow_clock): a coil
// scene (process.layers planned) ends its job at process.turns with the
// spindle braked to rest, and the cell holds "job done"; a later wind goal
// or setpoint winds on (the traverse lays further layers:
// Scene::traverseLayers). A bobbin ends when it is full: the spindle stops
// and the cell holds until a reset or restore (lock held).
void WindingCell::checkPlan() {
  const cws::RotatingCore* core = sim_->model().core();
  if (!core || o_.stop_at_end || o_.follow_clock || failed_) return;
  // A later setpoint winds on from a plan's stop (not from a full bobbin).
  if (resume_.exchange(false) && plan_stop_ && !bobbin_full_) {
    plan_stop_ = false;
    job_done_ = false;
    job_note_.clear();
    restartPace();
  }
  if (job_done_) return;
  const double t = sim_->time();
  if (braking_) {
    if (std::abs(core->omega(t)) > 0.0) return;
    braking_ = false;
    plan_stop_ = true;
    if (wind_.active) {
      endWind("stopped (" + job_note_ + ")");
      return;
    }
    endJob();
    return;
  }
  const double turns = std::abs(core->angle(t)) / (2.0 * M_PI);
  const double holds = scene_.bobbinTurns();
  const bool full = turns >= holds * (1.0 - 1e-9);
  const bool planned = scene_.process.layers > 0 && !plan_ended_ && !wind_.active && jobEnded();
  if (!full && !planned) return;
  plan_ended_ = true;
  bobbin_full_ = full;
  job_note_ = full
                  ? "the bobbin is full at " + cws::formatNumber(holds, "%.4g") +
                        " turns: the spindle stopped; reset or restore to wind again"
                  : "the spindle stopped at the scene's plan of " +
                        cws::formatNumber(scene_.process.turns, "%.4g") + " turns in " +
                        std::to_string(scene_.plannedLayers()) +
                        " layers; a wind goal or a setpoint winds on" +
                        (std::isfinite(holds)
                             ? ", up to the bobbin's " + cws::formatNumber(holds, "%.4g") + " turns"
                             : std::string());
  speed_setpoint_ = 0.0;
  sim_->apply(cws::Setpoint::coreSpeed(0.0));
  braking_ = true;
}

// The job is done: one line on the console, cell_status and the metrics
// say so, and ~exit_at_end asks the loop to end.
void WindingCell::endJob() {
  job_done_ = true;
  job_wall_s_ = job_run_wall_s_;
  done_text_ = DoneText();
  exit_requested_ = o_.exit_at_end;
  std::string line;
  cellState(line);
  ROS_INFO("winding_cell: %s", line.c_str());
}

// The cell's state for cell_status and /diagnostics, and in words.
std::string WindingCell::cellState(std::string& message) const {
  using S = coil_winding_sim::CellStatus;
  if (failed_) {
    message = "stopped: " + failure_;
    return S::FAILED;
  }
  if (job_done_) {
    // (The held state does not change: its words are found once, not on
    // every pass of the loop, which asks for them to see if they changed;
    // the bulging of the coil kept a held cell at a quarter of a core.)
    if (done_text_.sim != sim_.get() || done_text_.time_s != sim_->time()) {
      const cws::BulgeReport b = cws::headlineBulging(sim_->model(), sim_->scene());
      char text[320];
      std::snprintf(text, sizeof text,
                    "job done: %.4g turns in %.6g s simulated and %.3g s of wall time winding "
                    "(real-time factor %.3g), bulging %s",
                    std::abs(sim_->coreTurns()), sim_->time() - job_start_sim_s_, job_wall_s_,
                    jobRealTimeFactor(),
                    b.valid ? (cws::formatNumber(1e3 * b.height_m, "%.4f") + " mm").c_str()
                            : "none (nothing wound)");
      // What the wire went through, where it matters (quality_report.hpp).
      const cws::CoilReport coil = cws::reportCoil(sim_->model(), sim_->scene());
      const cws::QualityReport q = cws::reportQuality(sim_->model(), sim_->scene(), coil);
      std::string quality;
      if (q.plastic_elongation > 0.0) {
        quality += "; the wire stretched for good by up to " +
                   cws::formatNumber(100.0 * q.plastic_elongation, "%.3g") +
                   " % (its cross-section " +
                   cws::formatNumber(100.0 * q.cross_section_lost, "%.3g") + " % smaller)";
      }
      if (!q.turns_past_limits.empty()) {
        quality += "; " + std::to_string(q.turns_past_limits.size()) +
                   " turns strained past the enamel's limits (the first: turn " +
                   std::to_string(q.turns_past_limits.front()) + ")";
      }
      if (!std::isnan(q.tension_peak_N)) {
        quality += "; tension at the load cell " + cws::formatNumber(q.tension_low_N, "%.3g") +
                   " to " + cws::formatNumber(q.tension_peak_N, "%.3g") + " N";
        if (!std::isnan(q.tension_ripple_mean_N)) {
          quality +=
              ", " + cws::formatNumber(q.tension_ripple_mean_N, "%.2g") + " N of ripple a turn";
        }
      }
      done_text_ = {sim_.get(), sim_->time(), std::string(text) + quality};
    }
    message = done_text_.text;
    if (plan_stop_) message += "; " + job_note_;
    return S::JOB_DONE;
  }
  if (storage_full_) {
    const cws::WireConstants& c = sim_->model().constants();
    message = "holding: the wire's storage is full (" + std::to_string(c.n) + " of " +
              std::to_string(c.capacity) + " live points, ~max_points: the last " +
              cws::formatNumber(sim_->model().keepTurns(), "%.3g") +
              " turns of wound wire stay live, older wire retires) after " +
              cws::formatNumber(std::abs(sim_->coreTurns()), "%.4g") +
              " turns; reset or restore to wind again, or start the cell with a larger "
              "~max_points (at most " +
              std::to_string(cws::kMaxScenePoints) + ")";
    return S::FULL;
  }
  if (paused_) {
    message = "paused";
    return S::PAUSED;
  }
  if (at_rest_) {
    message = "the core at rest until a speed setpoint (~start at_rest)";
    return S::AT_REST;
  }
  if (!keeping_pace_) {
    message =
        "not keeping pace: real-time factor " + cws::formatNumber(pace_window_.factor(), "%.3g") +
        " over the last second of wall time against the target " +
        cws::formatNumber(pace_.target(), "%.3g") + (slow_cause_.empty() ? "" : "; " + slow_cause_);
    return S::SLOW;
  }
  message = "winding";
  return S::RUNNING;
}

// cell_status (latched), whenever the state changes, and once a second
// while the cell winds.
void WindingCell::publishStatus() {
  std::lock_guard<std::mutex> lock(sim_mutex_);
  coil_winding_sim::CellStatus s;
  s.state = cellState(s.message);
  const JobErrorEstimator::Latest estimate =
      estimator_ ? estimator_->latest() : JobErrorEstimator::Latest{};
  // (A winding cell's figures are sent again once a second of wall time:
  // its real-time factor is the one of winding_metrics and /diagnostics,
  // not the one it had when its state last changed.)
  const double now = wallNow();
  const bool winding = s.state == coil_winding_sim::CellStatus::SLOW ||
                       s.state == coil_winding_sim::CellStatus::RUNNING;
  const bool again = winding && now - status_wall_s_ >= 1.0;
  if (s.state == last_status_ && refused_ == last_refused_ &&
      estimate.count == last_estimate_count_ && !again) {
    return;
  }
  status_wall_s_ = now;
  s.real_time_factor = realTimeFactor();
  last_status_ = s.state;
  last_refused_ = refused_;
  last_estimate_count_ = estimate.count;
  s.shape_error_estimate = estimate.shape;
  s.bulging_error_estimate = estimate.bulging;
  s.error_estimate_sim_time = estimate.sim_time;
  s.refused = refused_;
  s.header.stamp = stamp();
  s.header.frame_id = o_.frames.world;
  s.job_done = job_done_;
  s.sim_time = sim_->time();
  s.core_turns = std::abs(sim_->coreTurns());
  const cws::BulgeReport b = cws::headlineBulging(sim_->model(), sim_->scene());
  s.bulging_height = b.valid ? b.height_m : std::numeric_limits<double>::quiet_NaN();
  status_pub_.publish(s);
}

}  // namespace cws_ros
