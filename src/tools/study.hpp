// The paper's 2 x 2 study (section V): core speed 600 / 1200 rpm x supply
// tension 30 / 70 N, the state after 1 3/4 turns.
#pragma once

#include <string>
#include <vector>

namespace cws_tools {

// Runs the four cases of `scene_path` (with `overrides` applied first) on
// `jobs` threads, writing DIR/<case>/{summary.json, wire.csv, shape_core.csv},
// DIR/study.csv, DIR/study.md and DIR/core_cylinders.csv. Returns the exit
// code (0 when every case ran).
int runStudy(const std::string& scene_path, const std::vector<std::string>& overrides,
             const std::string& dir, int jobs);

}  // namespace cws_tools
