// The setpoint limits of a scene (process.max_core_speed_rpm,
// process.max_tension): one check of a core speed or a supply tension for
// every way a setpoint comes in (the scene's own, a command during a run,
// the node's setpoint topics, a restored snapshot), so that each refuses the
// same values with the same message.
#pragma once

#include <string>

#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

struct SetpointLimits {
  double max_core_speed_rad_s = 0.0;  // |omega| up to this [rad/s]
  double max_tension_N = 0.0;         // 0 .. this [N]
  static SetpointLimits of(const ProcessParams& p) {
    return {rpmToRadPerSec(p.max_core_speed_rpm), p.max_tension};
  }
};

// Empty when the setpoint is allowed; else what is wrong with it, naming the
// limit's key, as a predicate: "is above process.max_tension = 300 N".
std::string coreSpeedRefusal(const SetpointLimits& limits, double omega_rad_s);
std::string tensionRefusal(const SetpointLimits& limits, double tension_N);
// The subject of such a message: "core speed 700 rad/s", "tension 400 N".
std::string coreSpeedText(double omega_rad_s);
std::string tensionText(double tension_N);

}  // namespace cws
