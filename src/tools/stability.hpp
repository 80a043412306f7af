// The stability matrix: extreme cases x every integrator, each run checked
// against the stated criteria (core/run_checks.hpp).
#pragma once

#include <string>
#include <vector>

namespace cws_tools {

// Runs every case of the matrix (or those whose name contains `only`) on
// `scene_path` with `overrides`, with each integrator, on `jobs` threads;
// writes DIR/stability.csv and DIR/STABILITY.md. A run longer than
// `budget_s` of wall time is stopped and reported as such. Returns the exit
// code: 0 when every run met the criteria or stopped with a message naming
// its cause, 1 otherwise.
int runStability(const std::string& scene_path, const std::vector<std::string>& overrides,
                 const std::string& dir, int jobs, const std::string& only, double budget_s);

}  // namespace cws_tools
