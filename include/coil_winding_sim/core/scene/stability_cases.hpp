// The cases of the stability matrix (docs/STABILITY.md): stiff and extreme
// scenes as overrides of the study's base scene (the paper's case at 2 mm
// segments and 1200 rpm). One table, read by `wire_sim stability` and by the
// unit tests that run shortened versions of the same cases.
#pragma once

#include <string>
#include <vector>

namespace cws {

// A change of the core's commanded speed during a run.
struct SpeedEvent {
  double time_s;
  double speed_rad_s;
};

struct StabilityCase {
  std::string name, what;              // e.g. "rigidity_x100", and in words
  std::vector<std::string> overrides;  // key=value on the base scene, in order
  std::vector<SpeedEvent> events;      // speed commands at simulated times
};

// Every case, in the report's order.
const std::vector<StabilityCase>& stabilityCases();
// The case of that name; throws std::out_of_range naming it.
const StabilityCase& stabilityCase(const std::string& name);

}  // namespace cws
