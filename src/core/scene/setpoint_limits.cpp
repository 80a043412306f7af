#include "coil_winding_sim/core/scene/setpoint_limits.hpp"

#include <cmath>

#include "coil_winding_sim/core/base/text_format.hpp"

namespace cws {

std::string coreSpeedRefusal(const SetpointLimits& limits, double omega_rad_s) {
  if (!std::isfinite(omega_rad_s)) return "is not a finite number";
  if (std::abs(omega_rad_s) > limits.max_core_speed_rad_s) {
    return "is beyond +-" + formatNumber(limits.max_core_speed_rad_s) +
           " rad/s (process.max_core_speed_rpm = " +
           formatNumber(limits.max_core_speed_rad_s / rpmToRadPerSec(1.0)) + " rpm)";
  }
  return "";
}

std::string tensionRefusal(const SetpointLimits& limits, double tension_N) {
  if (!std::isfinite(tension_N)) return "is not a finite number";
  if (tension_N < 0.0) return "is negative";
  if (tension_N > limits.max_tension_N) {
    return "is above process.max_tension = " + formatNumber(limits.max_tension_N) + " N";
  }
  return "";
}

std::string coreSpeedText(double omega_rad_s) {
  return "core speed " + formatNumber(omega_rad_s) + " rad/s";
}

std::string tensionText(double tension_N) { return "tension " + formatNumber(tension_N) + " N"; }

}  // namespace cws
