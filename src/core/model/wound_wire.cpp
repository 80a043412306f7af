// The wound wire of WireModel: wire the core carries rigidly
// (solver.carry_stuck_wire) taken on and released as CarriedWire decides,
// its deferred placement for the Newton-step methods, and a live point's
// stand-off (the whole wire's reports: run/wire_report.cpp).
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
  const CarriedWire::Decision d =
      carried_.decide(*contact_, stretching_, *core_, c_, committed_, t);
  if (d.release) {
    // Released points are integrated again from their rigid poses now.
    if (d.first < c_.first) placeCarriedWire(y);
    c_.first = d.first;
    carried_.forgetSums();  // (summed anew: carriedEnergyChange)
    return;
  }
  // Points taken on: set to their rigid motion with the core. (Setting the
  // velocity to the rigid one is a jump of at most the re-stick speed v;
  // the boundary frame's constraint absorbs it with a residual of about
  // v / (e nu l), 7e-5 at 1 mm/s, nu = 5000 1/s, l = 1 mm.)
  for (int i = c_.first; i < d.first; ++i) {
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
  c_.first = d.first;
}

double WireModel::carriedEnergyChange(double t0, double t1) const {
  if (!carry_ || !core_ || c_.first <= 1) return 0.0;
  return carried_.energyChange(*core_, c_, t0, t1);
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

}  // namespace cws
