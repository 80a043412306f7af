// The stability matrix: extreme cases x every integrator, each run checked
// against the stated criteria (core/run_checks.hpp).
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace cws_tools {

struct StabilityOptions {
  int jobs = 2;               // runs in parallel
  std::string only;           // only the cases whose name contains this
  std::string method;         // only this integrator (empty: every one)
  double budget_s = 18000.0;  // wall time per run [s]
  // Wall time between checkpoints of a run [s].
  double checkpoint_s = 300.0;
  bool fresh = false;          // discard the results and checkpoints of earlier studies
  bool report_only = false;    // write the tables from the kept results, run nothing
  std::function<bool()> stop;  // true: stop (a signal), keeping what is done
};

// Runs every case of the matrix (or those whose name contains `only`) on
// `scene_path` with `overrides`, with each integrator; writes
// DIR/stability.csv and DIR/STABILITY.md. A run longer than `budget_s` of
// wall time is stopped and reported as such. Each finished run's result and
// a checkpoint of each unfinished one (every `checkpoint_s`, at its budget
// and when `stop` turns true) are kept in DIR/runs/, tied to the core
// build and the run's inputs: a later study reuses the results and continues
// the unfinished runs (`report_only`: the tables from what is kept, with
// unfinished runs as PENDING, and nothing run). Returns the exit code: 0 when every run met the
// criteria or stopped with a message naming its cause, 1 otherwise, -1
// when stopped (no tables written).
int runStability(const std::string& scene_path, const std::vector<std::string>& overrides,
                 const std::string& dir, const StabilityOptions& options);

}  // namespace cws_tools
