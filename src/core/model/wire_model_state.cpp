// A model's snapshot (ModelState): written from the committed state, and
// read back with every field checked against the scene before anything
// changes.
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "coil_winding_sim/core/model/wire_model.hpp"

namespace cws {

ModelState WireModel::saveState(const Eigen::VectorXd& y) const {
  requirePlacedState();
  ModelState m;
  m.points = c_.n;
  m.y.assign(y.data(), y.data() + size());
  m.history = history();
  if (core_) core_->exportState(m.core);
  m.points_added = points_added_;
  m.committed_time_s = committed_time_;
  m.port_distance0_m = port_distance0_;
  m.carried = c_.first - 1;
  if (supply_) m.port_command = supply_->portCommand().exportState();
  for (int i = 1; i < c_.first; ++i) {
    const Eigen::Vector3d& p = carried_.positionCore(i);
    const Eigen::Vector4d& q = carried_.orientationCore(i);
    m.carried_pose.insert(m.carried_pose.end(), p.data(), p.data() + 3);
    m.carried_pose.insert(m.carried_pose.end(), q.data(), q.data() + 4);
  }
  m.retired = c_.retired;
  if (c_.retired > 0) {
    retired_.exportPoints(m.retired_points);
    m.retired_energy[0] = retired_.elastic_J;
    m.retired_energy[1] = retired_.plastic_J;
    m.retired_energy[2] = carried_.retiredInertia();
    m.retired_energy[3] = contact_ ? contact_->retiredMaxPenetration() : 0.0;
    std::copy(p0_.data(), p0_.data() + 3, m.clamp_core);
    std::copy(q0_.data(), q0_.data() + 4, m.clamp_core + 3);
    m.clamp_core[7] = clamp_axial_force_;
  }
  return m;
}

void WireModel::restoreState(const ModelState& m, Eigen::VectorXd& y) {
  carried_.forgetSums();
  if (m.points < 2 || m.points > c_.capacity) {
    throw std::runtime_error("snapshot has " + std::to_string(m.points) +
                             " points; this scene holds 2 to " + std::to_string(c_.capacity));
  }
  if (!supply_ && m.points != c_.n) {
    throw std::runtime_error("snapshot has " + std::to_string(m.points) +
                             " points, the scene's wire " + std::to_string(c_.n));
  }
  if (m.y.size() != static_cast<std::size_t>(stateOffset(m.points))) {
    throw std::runtime_error("snapshot state vector has the wrong length");
  }
  for (double v : m.y) {
    if (!std::isfinite(v)) throw std::runtime_error("snapshot state is not finite");
  }
  if (m.carried < 0 || m.carried > m.points - 2 || (m.carried > 0 && !carry_)) {
    throw std::runtime_error("snapshot carries " + std::to_string(m.carried) +
                             " points; this scene carries " +
                             (carry_ ? "0 to " + std::to_string(m.points - 2) : "none"));
  }
  if (m.carried_pose.size() != static_cast<std::size_t>(7 * m.carried)) {
    throw std::runtime_error("snapshot has " + std::to_string(m.carried_pose.size()) +
                             " carried-pose values for " + std::to_string(m.carried) +
                             " carried points (7 each)");
  }
  for (double v : m.carried_pose) {
    if (!std::isfinite(v)) throw std::runtime_error("snapshot carried poses are not finite");
  }
  if (m.retired < 0 || (m.retired > 0 && !carry_)) {
    throw std::runtime_error("snapshot has " + std::to_string(m.retired) +
                             " retired points; this scene retires " +
                             (carry_ ? "0 or more" : "none (it carries no wound wire)"));
  }
  if (m.retired_points.size() != static_cast<std::size_t>(RetiredWire::kValuesPerPoint) *
                                     static_cast<std::size_t>(m.retired)) {
    throw std::runtime_error("snapshot has " + std::to_string(m.retired_points.size()) +
                             " retired-wire values for " + std::to_string(m.retired) +
                             " retired points (" + std::to_string(RetiredWire::kValuesPerPoint) +
                             " each)");
  }
  for (double v : m.retired_energy) {
    if (!std::isfinite(v)) throw std::runtime_error("snapshot retired-wire energy is not finite");
  }
  for (double v : m.clamp_core) {
    if (!std::isfinite(v)) throw std::runtime_error("snapshot clamp pose is not finite");
  }
  // (Reserved as at the start: a restored job retires without allocating.)
  RetiredWire retired;
  retired.reserve(retired_reserve_);
  retired.importPoints(m.retired_points);
  if (!supply_ && !m.port_command.empty()) {
    throw std::runtime_error("snapshot commands a supply port; this scene has no supply");
  }
  if (supply_) {
    try {
      supply_->portCommand().restoreState(m.port_command);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(e.what());
    }
  }
  c_.n = m.points;
  // Retired wire first: the laws' joint lengths count from the whole wire's
  // fixed end.
  c_.retired = m.retired;
  retired_ = std::move(retired);
  retired_.elastic_J = m.retired_energy[0];
  retired_.plastic_J = m.retired_energy[1];
  carried_.setRetiredInertia(m.retired_energy[2]);
  if (contact_) contact_->setRetiredMaxPenetration(m.retired_energy[3]);
  if (m.retired > 0) {
    p0_ = Eigen::Map<const Eigen::Vector3d>(m.clamp_core);
    q0_ = Eigen::Map<const Eigen::Vector4d>(m.clamp_core + 3);
    clamp_axial_force_ = m.clamp_core[7];
  } else {
    clamp_axial_force_ = 0.0;
    p0_ = p0_start_;
    q0_ = q0_start_;
  }
  y.head(size()) = Eigen::Map<const Eigen::VectorXd>(m.y.data(), size());
  HistoryReader in(m.history);
  for (EffectHistory* e : effects_.histories()) e->restoreHistory(in);
  if (!in.atEnd()) throw std::runtime_error("snapshot history is too long for this scene");
  if (core_) core_->restoreState(m.core);
  points_added_ = m.points_added;
  committed_time_ = m.committed_time_s;
  port_distance0_ = m.port_distance0_m;
  c_.first = m.carried + 1;
  carried_.forgetAll();  // the core moved; other points
  unpack(committed_time_, y, committed_);
  for (int i = 1; i < c_.first; ++i) {
    const double* pose = m.carried_pose.data() + 7 * (i - 1);
    carried_.setPose(i, Eigen::Map<const Eigen::Vector3d>(pose),
                     Eigen::Map<const Eigen::Vector4d>(pose + 3));
  }
  carried_kinematics_placed_ = carried_state_placed_ = true;  // a snapshot: the whole wire
}

}  // namespace cws
