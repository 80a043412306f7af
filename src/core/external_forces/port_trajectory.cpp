#include "coil_winding_sim/core/external_forces/port_trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "coil_winding_sim/core/base/text_format.hpp"

namespace cws {

namespace {
// A commanded position this close to where the port is counts as the same [m].
constexpr double kSamePosition_m = 1.0e-12;

std::string text(double v) { return formatNumber(v, "%.12g"); }
}  // namespace

PortTrajectory::PortTrajectory() : ring_(kCapacity) {}

double PortTrajectory::timeTolerance(double t) { return 1e-12 * std::max(1.0, std::abs(t)); }

double PortTrajectory::lastTime() const {
  return size_ > 0 ? sample(size_ - 1).t_s : -std::numeric_limits<double>::infinity();
}

void PortTrajectory::push(double t_s, const Eigen::Vector3d& p_world) {
  Sample& s = ring_[(head_ + size_) % kCapacity];
  s.t_s = t_s;
  s.p_world = p_world;
  ++size_;
}

void PortTrajectory::append(double t_s, const Eigen::Vector3d& p_world, double t_now,
                            const Eigen::Vector3d& p_now_world) {
  if (!std::isfinite(t_s)) throw std::invalid_argument("port command stamp is not finite");
  if (!p_world.allFinite()) {
    throw std::invalid_argument("port command position at t = " + text(t_s) + " s is not finite");
  }
  const double tol = timeTolerance(t_now);
  if (t_s < t_now - tol) {
    throw std::invalid_argument("port command stamped " + text(t_s) +
                                " s lies before the simulated time " + text(t_now) +
                                " s (the port's motion up to then is integrated)");
  }
  if (size_ > 0 && t_s < lastTime() - tol) {
    throw std::invalid_argument("port command stamps go backwards: " + text(t_s) +
                                " s after a sample at " + text(lastTime()) + " s");
  }
  // The path from the present on: where the port is now, held up to now.
  const bool anchor = size_ == 0 || lastTime() < t_now - tol;
  const Eigen::Vector3d p_from = size_ == 0 ? p_now_world : sample(size_ - 1).p_world;
  const double t_from = anchor ? t_now : lastTime();
  if (t_s <= t_from + timeTolerance(t_from)) {
    // Same instant as the path's end: only the same position is no jump.
    if ((p_world - p_from).norm() > kSamePosition_m) {
      throw std::invalid_argument(
          "port command at t = " + text(t_s) + " s would make the port jump by " +
          text((p_world - p_from).norm()) + " m (a sample at the same time is at another place)");
    }
    if (!anchor) return;  // a repeat of the last sample
  }
  const int needed = (anchor ? 1 : 0) + (t_s > t_from + timeTolerance(t_from) ? 1 : 0);
  if (size_ + needed > kCapacity) {
    throw std::invalid_argument("port command at t = " + text(t_s) +
                                " s: " + std::to_string(kCapacity) +
                                " samples are queued ahead of the simulated time already");
  }
  if (anchor) push(t_now, p_from);
  if (t_s > t_from + timeTolerance(t_from)) push(t_s, p_world);
  commit(t_now);
}

PortMotion PortTrajectory::at(double t) const {
  PortMotion m;
  const Sample& a = sample(0);
  if (size_ < 2) {
    m.p_world = sample(size_ - 1).p_world;
    return m;
  }
  const Sample& b = sample(1);
  m.v_world = (b.p_world - a.p_world) / (b.t_s - a.t_s);
  m.p_world = a.p_world + (t - a.t_s) * m.v_world;
  return m;
}

double PortTrajectory::nextKink(double t) const {
  const double limit = t + timeTolerance(t);
  for (int k = 0; k < size_; ++k) {
    if (sample(k).t_s > limit) return sample(k).t_s;
  }
  return std::numeric_limits<double>::infinity();
}

void PortTrajectory::commit(double t) {
  const double limit = t + timeTolerance(t);
  while (size_ >= 2 && sample(1).t_s <= limit) {
    head_ = (head_ + 1) % kCapacity;
    --size_;
  }
}

std::vector<double> PortTrajectory::exportState() const {
  std::vector<double> out;
  out.reserve(4 * size_);
  for (int k = 0; k < size_; ++k) {
    const Sample& s = sample(k);
    out.insert(out.end(), {s.t_s, s.p_world.x(), s.p_world.y(), s.p_world.z()});
  }
  return out;
}

void PortTrajectory::restoreState(const std::vector<double>& flat) {
  if (flat.size() % 4 != 0 || flat.size() / 4 > static_cast<std::size_t>(kCapacity)) {
    throw std::invalid_argument("snapshot port command has " + std::to_string(flat.size()) +
                                " values; expected 4 per sample (t, x, y, z), at most " +
                                std::to_string(kCapacity) + " samples");
  }
  for (std::size_t i = 0; i < flat.size(); ++i) {
    if (!std::isfinite(flat[i])) throw std::invalid_argument("snapshot port command is not finite");
    if (i % 4 == 0 && i > 0 && !(flat[i] > flat[i - 4])) {
      throw std::invalid_argument("snapshot port command times do not increase");
    }
  }
  head_ = 0;
  size_ = 0;
  for (std::size_t i = 0; i < flat.size(); i += 4) {
    push(flat[i], Eigen::Vector3d(flat[i + 1], flat[i + 2], flat[i + 3]));
  }
}

}  // namespace cws
