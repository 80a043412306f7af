// Buried wound wire leaves the live arrays of WireModel (retireBuriedWire):
// which points may go, their compact record, and the renumbering of the
// state, the effects' histories and the carried wire behind them.
#include <algorithm>
#include <cmath>

#include "coil_winding_sim/core/external_forces/contact.hpp"
#include "coil_winding_sim/core/machine/rotating_core.hpp"
#include "coil_winding_sim/core/model/wire_model.hpp"

namespace cws {

int WireModel::retirablePoints() const {
  if (!carry_ || !core_ || c_.first < 3) return 0;
  constexpr double kTwoPi = 6.28318530717958647692;
  // Back from the last carried point, the angle the wire turns about the
  // core axis (carried points by their poses in the core frame): what lies
  // more than keep_turns_ turns behind may retire, up to the carried point
  // that stays as the new clamp.
  const double keep = keep_turns_ * kTwoPi;
  const int last_carried = c_.first - 1;
  Eigen::Vector3d a = carried_.positionCore(last_carried);
  double turned = 0.0;
  for (int i = last_carried - 1; i >= 1; --i) {
    const Eigen::Vector3d& b = carried_.positionCore(i);
    turned += std::abs(std::atan2(a.x() * b.y() - a.y() * b.x(), a.x() * b.x() + a.y() * b.y()));
    if (turned >= keep) return i;
    a = b;
  }
  return 0;
}

int WireModel::retireBuriedWire(Eigen::VectorXd& y) {
  const int k = retirablePoints();
  if (k < 1) return 0;
  // The whole wire as committed, in the kinematics and the state vector.
  placeCarriedWire(y);
  const EnergyReport before = energy(y);

  // The compact record of points 0..k-1 (whole-wire retired_ .. retired_+k-1),
  // with the running largest stand-off the bulging report reads.
  // (The store grows by doubling: a retirement is rare, between steps.)
  if (retired_.capacity() < retired_.size() + k) {
    retired_.reserve(std::max(2 * retired_.size(), retired_.size() + k));
  }
  for (int i = 0; i < k; ++i) {
    RetiredPoint q;
    static_cast<PointFigures&>(q) = livePoint(i);
    // (Wire is carried only where the clamp is on the core: p0_ is core frame.)
    q.p_core = i == 0 ? p0_ : carried_.positionCore(i);
    q.stand_off_m = section_ ? liveStandOff(i) : 0.0;
    q.segment_plastic_strain = stretching_->plasticStrain(i);
    static_assert(Contact::kMaxSlots <= RetiredPoint::kSlots, "a retired point keeps every slot");
    if (contact_) {
      for (int s = 0; s < contact_->slots(); ++s) q.surface[s] = contact_->surface(i, s);
    }
    const int w = c_.retired + i;
    if (section_ &&
        (q.stand_off_m > retired_.max_stand_off_m || retired_.max_stand_off_point < 0)) {
      retired_.max_stand_off_m = std::max(0.0, q.stand_off_m);
      retired_.max_stand_off_point = w;
    }
    retired_.append(q);
  }

  // Point k, carried, becomes the clamp on the core.
  clamp_axial_force_ = axialForce(k - 1);
  p0_ = carried_.positionCore(k);
  q0_ = carried_.orientationCore(k);
  clamp_in_core_ = true;

  // The effects' and the carried wire's per-point state, then the state
  // vector and the committed kinematics, move k points to the front.
  for (EffectHistory* e : effects_.histories()) e->retireFront(k);
  carried_.retireFront(k, c_.n, c_);
  const int from = stateOffset(k + 1), to = stateOffset(1), end = stateOffset(c_.n);
  std::copy(y.data() + from, y.data() + end, y.data() + to);
  for (int i = k; i < c_.n; ++i) {
    committed_.p_world.col(i - k) = committed_.p_world.col(i);
    committed_.v_world.col(i - k) = committed_.v_world.col(i);
    committed_.q.col(i - k) = committed_.q.col(i);
    committed_.qd.col(i - k) = committed_.qd.col(i);
  }
  c_.n -= k;
  c_.first -= k;
  c_.retired += k;

  // The retired wire's deformation energy stays in the balance as it was
  // (its kinetic energy follows the core through its moment of inertia).
  const EnergyReport after = energy(y);
  retired_.elastic_J += before.elastic - after.elastic;
  retired_.plastic_J += before.plastic - after.plastic;
  return k;
}

}  // namespace cws
