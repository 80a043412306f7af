// The paper's 2 x 2 study (section V): core speed 600 / 1200 rpm x supply
// tension 30 / 70 N, the state after 1 3/4 turns. It is a sweep of kind
// "study": its four cases run on the sweep's mechanism (locally or on
// Slurm), and gathering the sweep adds the study's tables.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "sweep_plan.hpp"
#include "sweep_slurm.hpp"

namespace cws_tools {

// The study's plan on `scene_path` with `overrides` applied first; its case
// folders are named 600rpm_30N, ...; throws cws::SceneError for a scene
// that does not wind (no supply or no contact).
SweepPlan studyPlan(const std::string& scene_path, const std::vector<std::string>& overrides);

// Runs the study into DIR: locally on `jobs` processes, or submitted to
// Slurm when `slurm` is given. Returns the exit code (0 when every case ran,
// or when submitted; -1 when `stop` turned true).
int runStudy(const std::string& scene_path, const std::vector<std::string>& overrides,
             const std::string& dir, int jobs, const SlurmOptions* slurm, const std::string& exe,
             const std::function<bool()>& stop);

// The study's tables from its cases in DIR: DIR/study.csv (the cases that
// ran), DIR/study.md (every case, a failed or pending one with its status)
// and DIR/core_cylinders.csv; study.md also on stdout. Returns 0 when every
// case ran, 1 otherwise.
int writeStudyTables(const SweepPlan& plan, const std::string& dir);

}  // namespace cws_tools
