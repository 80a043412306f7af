#include "coil_winding_sim/core/model/carried_wire.hpp"

#include <algorithm>

#include "coil_winding_sim/core/base/quaternion.hpp"
#include "coil_winding_sim/core/machine/rotating_core.hpp"
#include "coil_winding_sim/core/scene/core_geometry.hpp"

namespace cws {

CarriedWire::CarriedWire(int capacity, bool enabled)
    : enabled_(enabled),
      p_core_(enabled ? capacity : 0),
      q_core_(enabled ? capacity : 0),
      stand_off_(enabled ? capacity : 0),
      stand_off_known_(enabled ? capacity : 0, 0) {}

void CarriedWire::takeOn(const RotatingCore& core, double t, int i, const Eigen::Vector3d& p_world,
                         const Eigen::Vector4d& q) {
  const Eigen::Quaterniond q_core_world = core.quaternionWorldCore(t).conjugate();
  p_core_[i] = core.pointCore(t, p_world);
  stand_off_known_[i] = 0;
  const Eigen::Quaterniond qc = q_core_world * Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
  q_core_[i] = {qc.w(), qc.x(), qc.y(), qc.z()};
}

void CarriedWire::setPose(int i, const Eigen::Vector3d& p_core, const Eigen::Vector4d& q_core) {
  p_core_[i] = p_core;
  q_core_[i] = q_core;
}

void CarriedWire::place(const RotatingCore& core, double t, int i, WireKinematics& k) {
  // The core's pose at t, once per accepted step (a sine and cosine each).
  if (t != frame_time_) {
    frame_time_ = t;
    rot_ = core.rotationWorldCore(t);
    q_ = core.quaternionWorldCore(t);
    w_ = core.omega(t) * core.axisWorld();
  }
  const Eigen::Vector3d p = core.originWorld() + rot_ * p_core_[i];
  const Eigen::Quaterniond qc(q_core_[i][0], q_core_[i][1], q_core_[i][2], q_core_[i][3]);
  const Eigen::Quaterniond qw = q_ * qc;
  const quat::Vec4 q(qw.w(), qw.x(), qw.y(), qw.z());
  k.p_world.col(i) = p;
  k.q.col(i) = q;
  k.v_world.col(i) = w_.cross(p - core.originWorld());
  k.qd.col(i) = 0.5 * quat::E(q).transpose() * w_;
}

double CarriedWire::energyChange(const RotatingCore& core, const WireConstants& c, double t0,
                                 double t1) const {
  // Points taken on since the last sum are added; after a release or a
  // restored snapshot, all are summed again.
  if (inertia_first_ < 1) {
    inertia_first_ = 1;
    inertia_ = 0.0;
  }
  for (int i = inertia_first_; i < c.first; ++i) {
    inertia_ += c.point_mass * p_core_[i].head<2>().squaredNorm() + c.point_inertia;
  }
  inertia_first_ = c.first;
  // Rigid turning about the core axis: 1/2 (M r^2 + I) omega^2 a point.
  const double w0 = core.omega(t0), w1 = core.omega(t1);
  return 0.5 * (w1 * w1 - w0 * w0) * (inertia_ + retired_inertia_);
}

double CarriedWire::standOff(const CoreSection& section, double radius, int i) const {
  // (CoreSection::signedDistance is a search over directions: not at every
  // report of the whole wire.)
  if (!stand_off_known_[i]) {
    stand_off_[i] = section.signedDistance(p_core_[i].head<2>()) - radius;
    stand_off_known_[i] = 1;
  }
  return stand_off_[i];
}

void CarriedWire::retireFront(int k, int used, const WireConstants& c) {
  for (int i = 1; i <= k && i < used; ++i) {
    retired_inertia_ += c.point_mass * p_core_[i].head<2>().squaredNorm() + c.point_inertia;
  }
  const std::size_t drop = k, n = used;
  dropFront(p_core_, drop, n, Eigen::Vector3d::Zero().eval());
  dropFront(q_core_, drop, n, Eigen::Vector4d::Zero().eval());
  dropFront(stand_off_, drop, n, 0.0);
  dropFront(stand_off_known_, drop, n, static_cast<unsigned char>(0));
  inertia_first_ = -1;
}

void CarriedWire::forgetSums() { inertia_first_ = -1; }

void CarriedWire::forgetAll() {
  inertia_first_ = -1;
  frame_time_ = std::numeric_limits<double>::quiet_NaN();
  std::fill(stand_off_known_.begin(), stand_off_known_.end(), 0);
}

}  // namespace cws
