#include "coil_winding_sim/core/assembly/one_leg_step.hpp"

#include <algorithm>
#include <cmath>

#include "coil_winding_sim/core/machine/rotating_core.hpp"

namespace cws {

const CarriedRate& CarriedMotion::load(double t0) {
  if (!core_) return loaded_;
  angles_.record(t0, core_->angle(t0));
  // The accepted step's rate holds for the state it ended at; any other
  // committed state (the start, a restored snapshot) has exact velocities.
  if (have_accepted_ && std::abs(t0 - t_accepted_) <= 1e-12 * std::max(1.0, std::abs(t0))) {
    loaded_ = accepted_;
  } else {
    loaded_ = CarriedRate::tangent(core_->originWorld(), core_->axisWorld(), core_->omega(t0));
  }
  return loaded_;
}

const CarriedRate& CarriedMotion::trial(const OneLegStep& step) {
  if (!core_) return trial_;
  double theta_past[OneLegStep::kMaxPast];
  for (int j = 0; j < step.past; ++j) {
    theta_past[j] = angles_.at(step.t_past[j], core_->angle(step.t_past[j]));
  }
  trial_ = CarriedRate::scheme(step, core_->originWorld(), core_->axisWorld(),
                               core_->angle(step.t1), core_->omega(step.t1), theta_past);
  t_trial_ = step.t1;
  return trial_;
}

}  // namespace cws
