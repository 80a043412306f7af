// The wound wire of WireModel: when wire the core carries rigidly
// (solver.carry_stuck_wire, kept by CarriedWire) is taken on and released,
// its deferred placement for the Newton-step methods, and the stand-off and
// bulging reports of the wound wire.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "coil_winding_sim/core/base/quaternion.hpp"
#include "coil_winding_sim/core/external_forces/contact.hpp"
#include "coil_winding_sim/core/machine/rotating_core.hpp"
#include "coil_winding_sim/core/model/wire_model.hpp"
#include "coil_winding_sim/core/scene/core_geometry.hpp"

namespace cws {

void WireModel::placeCarried(double t, int i) { carried_.place(*core_, t, i, committed_); }

void WireModel::writeCommitted(int i, Eigen::VectorXd& y) const {
  const int o = stateOffset(i);
  y.segment<3>(o) = committed_.p_world.col(i);
  y.segment<4>(o + 3) = committed_.q.col(i);
  y.segment<3>(o + 7) = committed_.v_world.col(i);
  y.segment<4>(o + 10) = committed_.qd.col(i);
}

void WireModel::placeCarried(double t, int i, Eigen::VectorXd& y) {
  placeCarried(t, i);
  writeCommitted(i, y);
}

void WireModel::updateCarried(double t, Eigen::VectorXd& y) {
  // Stuck groups: runs of points held by static friction. The core carries
  // wound wire at most up to the start of the last group but one; that
  // group and the wire after it stay integrated.
  // (Found from the far end: a scan of the integrated wire, not the wound.)
  // (A group reaching into the carried wire starts, for this purpose, at
  // the first integrated point.)
  int last_start = -1, prev_start = -1, last_end = -1;
  for (int i = c_.n - 1; i >= std::max(1, c_.first) && prev_start < 0; --i) {
    if (last_end < 0 && contact_->resting(i)) last_end = i;
    if (contact_->resting(i) && !contact_->resting(i - 1))
      (last_start < 0 ? last_start : prev_start) = i;
  }
  if (last_start < 0 && last_end >= 0) last_start = std::max(1, c_.first);
  // Wire that lies on the core without a free span (a drum, or a layer
  // lying on the one below) forms one long group: the core carries it up
  // to half a turn (about the core axis) behind that group's end.
  if (last_start >= 0 && last_end - last_start > 2) {
    const int half_turn = halfTurnBehind(t, last_end, last_start);
    prev_start = std::max(prev_start, half_turn);
  }
  const int limit = std::min(prev_start, c_.n - 2);
  // Release: wound wire before that limit slips on the core (in contact,
  // not stuck). The tension behind it changes, so the wire back to the
  // stuck group before the slipping point is integrated again.
  for (int i = c_.first; i < limit; ++i) {
    if (contact_->inContact(i) && !contact_->resting(i)) {
      int r = i;
      while (r > 1 && !(contact_->resting(r) && !contact_->resting(r - 1))) --r;
      // On a long group (a drum, a layer on a layer) no further back than
      // half a turn.
      r = std::max(r, halfTurnBehind(t, i, r));
      // Released points are integrated again from their rigid poses now.
      if (r < c_.first) placeCarriedWire(y);
      c_.first = std::min(c_.first, r);
      carried_.forgetSums();  // (summed anew: carriedEnergyChange)
      return;
    }
  }
  // Take on wire that has come to rest on the core: every point within the
  // re-stick speed of the core material, so that nothing still moving is
  // frozen. (Setting the velocity to the rigid one is a jump of at most that
  // speed v; the boundary frame's constraint absorbs it with a residual of
  // about v / (e nu l), 7e-5 at 1 mm/s, nu = 5000 1/s, l = 1 mm.)
  const double settled = contact_->stickSpeed();
  int target = c_.first;
  while (target < limit && relativeSpeed(t, target) < settled) ++target;
  if (target > c_.first) {
    for (int i = c_.first; i < target; ++i) {
      carried_.takeOn(*core_, t, i, committed_.p_world.col(i), committed_.q.col(i));
      // The kinetic energy of the remaining relative motion (below the
      // re-stick speed) is given up: counted as dissipated.
      const int o = stateOffset(i);
      const double before = 0.5 * c_.point_mass * y.segment<3>(o + 7).squaredNorm() +
                            2.0 * c_.point_inertia * y.segment<4>(o + 10).squaredNorm();
      placeCarried(t, i, y);
      y[1] += before - (0.5 * c_.point_mass * y.segment<3>(o + 7).squaredNorm() +
                        2.0 * c_.point_inertia * y.segment<4>(o + 10).squaredNorm());
    }
  }
  c_.first = target;
}

double WireModel::carriedEnergyChange(double t0, double t1) const {
  if (!carry_ || !core_ || c_.first <= 1) return 0.0;
  return carried_.energyChange(*core_, c_, t0, t1);
}

double WireModel::relativeSpeed(double t, int i) const {
  const Eigen::Vector3d p = committed_.p_world.col(i);
  const Eigen::Vector3d u =
      committed_.coreVelocity(p, core_->velocityWorld(t, p), contact_->stickSpeed());
  return (committed_.v_world.col(i) - u).norm();
}

int WireModel::halfTurnBehind(double t, int from, int down_to) const {
  constexpr double kPi = 3.14159265358979323846;
  // (Carried points by their poses in the core frame.)
  auto pointCore = [&](int i) -> Eigen::Vector3d {
    return i < c_.first ? carried_.positionCore(i) : core_->pointCore(t, committed_.p_world.col(i));
  };
  Eigen::Vector3d a = pointCore(from);
  double turned = 0.0;
  for (int i = from - 1; i >= down_to; --i) {
    const Eigen::Vector3d b = pointCore(i);
    turned += std::abs(std::atan2(a.x() * b.y() - a.y() * b.x(), a.x() * b.x() + a.y() * b.y()));
    if (turned >= kPi) return i;
    a = b;
  }
  return -1;
}

void WireModel::placeCarriedWire() const {
  if (carried_kinematics_placed_) return;
  // Only the carried poses of the committed kinematics (a cache) change.
  WireModel& self = const_cast<WireModel&>(*this);
  for (int i = 1; i < c_.first - 1; ++i) self.placeCarried(committed_time_, i);
  self.carried_kinematics_placed_ = true;
}

void WireModel::requirePlacedState() const {
  if (!carried_state_placed_) {
    throw std::logic_error(
        "WireModel: the state vector's carried wire is not placed (call "
        "placeCarriedWire(y) first)");
  }
}

void WireModel::placeCarriedWire(Eigen::VectorXd& y) const {
  if (carried_state_placed_) return;
  placeCarriedWire();
  for (int i = 1; i < c_.first - 1; ++i) writeCommitted(i, y);
  carried_state_placed_ = true;
}

double WireModel::standOff(int w) const {
  return w < c_.retired ? retired_[w].stand_off_m : liveStandOff(w - c_.retired);
}

double WireModel::liveStandOff(int i) const {
  // A carried point's stand-off is fixed while the core carries it: found
  // once (CoreSection::signedDistance is a search over directions), not at
  // every report of the whole wire.
  // (Point 0 is carried too where wire retired: the clamp on the core.)
  if (carry_ && (i >= 1 || c_.retired > 0) && i < c_.first) {
    return carried_.standOff(*section_, c_.radius, i);
  }
  placeCarriedWire();
  const Eigen::Vector3d p_core = core_->pointCore(committed_time_, committed_.p_world.col(i));
  return section_->signedDistance(p_core.head<2>()) - c_.radius;
}

int WireModel::lastInContact() const {
  int last = -1;
  if (!contact_) return last;
  for (int i = 1; i < c_.n; ++i) {
    if (contact_->inContact(i)) last = i;
  }
  if (last >= 0) return c_.retired + last;
  for (int w = c_.retired - 1; w >= 1; --w) {
    if (retired_[w].in_contact) return w;
  }
  return -1;
}

BulgeReport WireModel::bulging() const {
  placeCarriedWire();
  BulgeReport b;
  if (!contact_ || !section_) return b;
  const int last_contact = lastInContact();
  if (last_contact < 0) return b;
  b.valid = true;
  b.wound_points = last_contact + 1;
  b.height_m = 0.0;
  // Retired wire: its largest stand-off was found as it retired.
  int w = 0;
  if (c_.retired > 0 && last_contact >= c_.retired) {
    b.height_m = retired_.max_stand_off_m;
    b.index = retired_.max_stand_off_point;
    w = c_.retired;
  }
  for (; w <= last_contact; ++w) {
    const double h = standOff(w);
    if (h > b.height_m || b.index < 0) {
      b.height_m = std::max(0.0, h);
      b.index = w;
    }
  }
  b.build_up_m = b.height_m;
  b.arc_length_m = b.index * c_.segment_length;
  b.p_core = pointCore(b.index);
  return b;
}

}  // namespace cws
