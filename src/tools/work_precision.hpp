// Error against run time for every integrator (a work-precision diagram).
#pragma once

#include <string>
#include <vector>

namespace cws_tools {

// Runs `scene_path` (with `overrides`) once as a tight-tolerance RKF45
// reference, then with each method over a range of tolerances or steps, on
// `jobs` threads; writes DIR/work_precision.csv (error of the final shape
// relative to the wire diameter and of the bulging height, wall time) and
// DIR/<run>/ outputs. Returns the exit code.
int runWorkPrecision(const std::string& scene_path, const std::vector<std::string>& overrides,
                     const std::string& dir, int jobs);

}  // namespace cws_tools
