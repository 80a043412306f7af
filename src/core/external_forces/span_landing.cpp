#include <algorithm>

#include "coil_winding_sim/core/external_forces/contact.hpp"

namespace cws {

double Contact::spanLandingSpeed(const WireKinematics& k, double t, int gap) const {
  // A point touches at a slot other than a flange's (the free span may
  // slide along a flange anywhere).
  auto touches = [&](const std::vector<int>& surfaces, int i) {
    for (int s = 0; s < slots_; ++s) {
      if (s != flange_slot_ && surfaces[i * slots_ + s] >= 0) return true;
    }
    return false;
  };
  // The wound wire's front at the last commit: the last integrated point
  // that touched (the boundary point when none did).
  int front = c_.first - 1;
  for (int i = c_.n - 1; i >= c_.first; --i) {
    if (touches(surface_, i)) {
      front = i;
      break;
    }
  }
  // Points of the free span beyond it that touch in the trial state: their
  // speed relative to the core material at the last commit.
  double fastest = 0.0;
  for (int i = front + gap + 1; i < c_.n; ++i) {
    if (!touches(trial_surface_, i)) continue;
    const Eigen::Vector3d p = k.p_world.col(i);
    fastest = std::max(fastest, (k.v_world.col(i) - core_.velocityWorld(t, p)).norm());
  }
  return fastest;
}

}  // namespace cws
