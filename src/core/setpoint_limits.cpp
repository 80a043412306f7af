#include "coil_winding_sim/core/setpoint_limits.hpp"

#include <cmath>
#include <cstdio>

namespace cws {

namespace {
std::string number(double v) {
  char text[64];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}
}  // namespace

std::string coreSpeedRefusal(const SetpointLimits& limits, double omega_rad_s) {
  if (!std::isfinite(omega_rad_s)) return "is not a finite number";
  if (std::abs(omega_rad_s) > limits.max_core_speed_rad_s) {
    return "is beyond +-" + number(limits.max_core_speed_rad_s) +
           " rad/s (process.max_core_speed_rpm = " +
           number(limits.max_core_speed_rad_s / rpmToRadPerSec(1.0)) + " rpm)";
  }
  return "";
}

std::string tensionRefusal(const SetpointLimits& limits, double tension_N) {
  if (!std::isfinite(tension_N)) return "is not a finite number";
  if (tension_N < 0.0) return "is negative";
  if (tension_N > limits.max_tension_N) {
    return "is above process.max_tension = " + number(limits.max_tension_N) + " N";
  }
  return "";
}

std::string coreSpeedText(double omega_rad_s) {
  return "core speed " + number(omega_rad_s) + " rad/s";
}

std::string tensionText(double tension_N) { return "tension " + number(tension_N) + " N"; }

}  // namespace cws
