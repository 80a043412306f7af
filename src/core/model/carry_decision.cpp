// What the core carries (CarriedWire::decide): wound wire at rest on the
// core is taken on, up to the last stuck group of points but one; wound
// wire that slips is released back to the stuck group before it where that
// group cannot hold the tension difference across the boundary.
#include <algorithm>
#include <cmath>

#include "coil_winding_sim/core/external_forces/contact.hpp"
#include "coil_winding_sim/core/inner_forces/stretching.hpp"
#include "coil_winding_sim/core/machine/rotating_core.hpp"
#include "coil_winding_sim/core/model/carried_wire.hpp"

namespace cws {

namespace {

// Does the carried wire from point `from` to the boundary point (c.first -
// 1) hold, by static friction, the tension difference across the
// boundary: the live segment's axial force less that of the carried
// segment behind it (from its frozen length)? Its points' normal forces
// are those of the surfaces they touched when taken on (their poses on
// them have not changed since).
bool groupHolds(const CarriedWire& carried, const Contact& contact, const Stretching& stretching,
                const WireConstants& c, const WireKinematics& k, int from) {
  const int b = c.first - 1;
  if (b < 2 || from > b) return false;
  const double l = c.segment_length;
  const double strain = ((carried.positionCore(b) - carried.positionCore(b - 1)).norm() - l) / l;
  const double difference =
      stretching.axialForce(k, b) - stretching.axialForceAtStrain(strain, b - 1);
  double capacity = 0.0;
  for (int j = std::max(from, 1); j <= b; ++j) {
    double normal = 0.0;
    for (int s = 0; s < contact.slots(); ++s)
      if (contact.surface(j, s) >= 0)
        normal = std::max(normal, contact.stiffness() * contact.penetration(j, s));
    capacity += contact.staticFriction() * normal;
  }
  return std::abs(difference) <= capacity;
}

}  // namespace

CarriedWire::Decision CarriedWire::decide(const Contact& contact, const Stretching* stretching,
                                          const RotatingCore& core, const WireConstants& c,
                                          const WireKinematics& k, double t) const {
  // Stuck groups: runs of points held by static friction. The core carries
  // wound wire at most up to the start of the last group but one; that
  // group and the wire after it stay integrated.
  // (Found from the far end: a scan of the integrated wire, not the wound.)
  // (A group reaching into the carried wire starts, for this purpose, at
  // the first integrated point.)
  int last_start = -1, prev_start = -1, last_end = -1;
  for (int i = c.n - 1; i >= std::max(1, c.first) && prev_start < 0; --i) {
    if (last_end < 0 && contact.resting(i)) last_end = i;
    if (contact.resting(i) && !contact.resting(i - 1))
      (last_start < 0 ? last_start : prev_start) = i;
  }
  if (last_start < 0 && last_end >= 0) last_start = std::max(1, c.first);
  // Wire that lies on the core without a free span (a drum, or a layer
  // lying on the one below) forms one long group: the core carries it up
  // to half a turn (about the core axis) behind that group's end.
  if (last_start >= 0 && last_end - last_start > 2) {
    const int half_turn = halfTurnBehind(core, c, k, t, last_end, last_start);
    prev_start = std::max(prev_start, half_turn);
  }
  const int limit = std::min(prev_start, c.n - 2);
  // Release: wound wire before that limit slips on the core (in contact,
  // not stuck). The tension behind it changes, so the wire back to the
  // stuck group before the slipping point is integrated again. Carried
  // wire goes back only where that group's static friction cannot hold the
  // tension difference across the boundary (groupHolds), as in the full
  // model it would then slide too; the boundary point, which the core moves
  // rigidly, holds the rest. (Released for every slip, it went one stuck
  // group further back at every step after a strike, through turns of
  // wound wire that stayed stuck: docs/MODEL.md, "Carried wire".)
  for (int i = c.first; i < limit; ++i) {
    if (contact.inContact(i) && !contact.resting(i)) {
      int r = i;
      while (r > 1 && !(contact.resting(r) && !contact.resting(r - 1))) --r;
      // On a long group (a drum, a layer on a layer) no further back than
      // half a turn.
      r = std::max(r, halfTurnBehind(core, c, k, t, i, r));
      if (r < c.first && stretching &&
          groupHolds(*this, contact, *stretching, c, k, std::max(r, 1)))
        continue;
      return {std::min(c.first, r), true};
    }
  }
  // Take on wire that has come to rest on the core: every point within the
  // re-stick speed of the core material (as the accepted step's scheme
  // moved it, WireKinematics::coreVelocity), so that nothing still moving
  // is frozen.
  const double settled = contact.stickSpeed();
  auto relativeSpeed = [&](int i) {
    const Eigen::Vector3d p = k.p_world.col(i);
    const Eigen::Vector3d u = k.coreVelocity(p, core.velocityWorld(t, p), settled);
    return (k.v_world.col(i) - u).norm();
  };
  int target = c.first;
  while (target < limit && relativeSpeed(target) < settled) ++target;
  return {target, false};
}

int CarriedWire::halfTurnBehind(const RotatingCore& core, const WireConstants& c,
                                const WireKinematics& k, double t, int from, int down_to) const {
  constexpr double kPi = 3.14159265358979323846;
  // (Carried points by their poses in the core frame.)
  auto pointCore = [&](int i) -> Eigen::Vector3d {
    return i < c.first ? positionCore(i) : core.pointCore(t, k.p_world.col(i));
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

}  // namespace cws
