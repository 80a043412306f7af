#include "coil_winding_sim/ros/cell_timing.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "coil_winding_sim/core/external_forces/port_trajectory.hpp"

namespace cws_ros {

double ReplayClock::target(const ros::Time& now, double wall_s) {
  if (now.isZero()) return -1.0;  // no /clock yet
  if (!have_origin_) setOrigin(now);
  if (now != last_clock_) {
    last_clock_ = now;
    last_clock_wall_s_ = wall_s;
  }
  const double clock_s = (now - origin_).toSec();
  double target = clock_s - lag_s_;
  if (end_s_) {
    const double end = *end_s_;
    const bool at_end = clock_s >= end - 1e-9;
    const bool stalled = clock_s >= end - lag_s_ - 1e-9 && wall_s - last_clock_wall_s_ > 5.0;
    if ((at_end || stalled) && !end_seen_) {
      end_seen_ = true;
      end_seen_wall_s_ = wall_s;
    }
    if (end_seen_ && wall_s - end_seen_wall_s_ >= 0.5) target = end;
    target = std::min(target, end);
  }
  return target;
}

std::string slowCause(const cws::WorkCount& from, const cws::WorkCount& to,
                      long fallbacks_in_stretch, const std::string& fallback_cause) {
  const long steps = to.steps - from.steps;
  if (steps <= 0) return "";
  char text[320];
  int k = std::snprintf(text, sizeof text, "steps of %.2g s on average, %ld of %ld retried",
                        (to.t_s - from.t_s) / static_cast<double>(steps),
                        to.rejected - from.rejected, steps + (to.rejected - from.rejected));
  const long iterations = to.iterations - from.iterations;
  if (iterations > 0 && k > 0 && k < static_cast<int>(sizeof text)) {
    k += std::snprintf(
        text + k, sizeof text - k, ", %.1f Newton iterations and %.1f factorizations a step",
        static_cast<double>(iterations) / static_cast<double>(steps),
        static_cast<double>(to.factorizations - from.factorizations) / static_cast<double>(steps));
  }
  std::string cause = text;
  if (fallbacks_in_stretch > 0) {
    cause += "; explicit steps where Newton could not go on (" + fallback_cause + ")";
  }
  return cause;
}

void PaceWindow::add(double wall_s, double sim_s) {
  // Samples at least 20 ms apart: a second spans up to 50 of them.
  if (n_ > 0 && wall_s - wall_[(head_ + kSize - 1) % kSize] < 0.02) return;
  wall_[head_] = wall_s;
  sim_[head_] = sim_s;
  head_ = (head_ + 1) % kSize;
  if (n_ < kSize) ++n_;
}

void PaceWindow::update(double wall_s, double sim_s, double target, bool near_pace) {
  add(wall_s, sim_s);
  // The oldest sample within the last second, or the oldest of all.
  int oldest = (head_ + kSize - n_) % kSize;
  for (int k = n_; k > 1; --k) {
    const int i = (head_ + kSize - k) % kSize;
    if (wall_s - wall_[i] <= 1.0) break;
    oldest = i;
  }
  const double dw = wall_s - wall_[oldest];
  if (dw > 0.0) factor_ = (sim_s - sim_[oldest]) / dw;
  // Once the window spans a second, its factor alone decides: the pace
  // restarts whenever the cell falls a quarter second behind, so "near the
  // pace" holds again after every restart, even for a cell that never
  // keeps up (it hid a factor of 0.52 at a target of 1, issue 58).
  const bool keeping = target <= 0.0 || (dw >= 1.0 ? factor_ >= 0.95 * target : near_pace);
  if (keeping) {
    behind_since_s_ = -1.0;
  } else if (behind_since_s_ < 0.0) {
    behind_since_s_ = wall_s;
  }
  slow_ = !keeping && wall_s - behind_since_s_ >= 1.0;
}

void PublishGrid::restart(double t) {
  for (int c = 0; c < kChannels; ++c) {
    index_[c] = static_cast<long>(std::ceil(t * hz_[c]));
    next_s_[c] = static_cast<double>(index_[c]) / hz_[c];
  }
}

double PublishGrid::next() const {
  return std::min({next_s_[kFast], next_s_[kFrames], next_s_[kProfile]});
}

PublishGrid::Due PublishGrid::take(double t) {
  const double tol = cws::PortTrajectory::timeTolerance(t);
  bool due[kChannels];
  for (int c = 0; c < kChannels; ++c) {
    due[c] = t >= next_s_[c] - tol;
    if (!due[c]) continue;
    // A long step passes several grid times: one sample, the grid moves past.
    while (next_s_[c] <= t + tol) next_s_[c] = static_cast<double>(++index_[c]) / hz_[c];
  }
  return {due[kFast], due[kFrames], due[kProfile]};
}

bool WallThrottle::due(double wall_s, int& skipped, const std::string& text) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (warned_ && wall_s - last_s_ < period_s_) {
    ++skipped_;
    held_ = text;
    return false;
  }
  warned_ = true;
  last_s_ = wall_s;
  skipped = skipped_;
  skipped_ = 0;
  return true;
}

bool WallThrottle::overdue(double wall_s, std::string& text, int& skipped) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (skipped_ == 0 || wall_s - last_s_ < period_s_) return false;
  last_s_ = wall_s;
  text = held_;
  skipped = skipped_;
  skipped_ = 0;
  return true;
}

}  // namespace cws_ros
