// The stability matrix: extreme cases x every integrator, each run checked
// against the stated criteria (core/run/run_checks.hpp). It is a sweep of kind
// "stability": each run is a case of the sweep, in DIR/runs/<case>.<method>
// (its result, the checkpoint of an unfinished run, status.txt, log.txt),
// run locally or on Slurm; gathering writes DIR/stability.csv and
// DIR/STABILITY.md.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "sweep_plan.hpp"
#include "sweep_slurm.hpp"

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

// The matrix as a plan on `scene_path` with `overrides` (after the study's
// 2 mm segments and 1200 rpm): keys case and method, the last case first.
// Throws SweepError when no case name contains `only`, cws::SceneError for
// a bad base scene.
SweepPlan stabilityPlan(const std::string& scene_path, const std::vector<std::string>& overrides,
                        const StabilityOptions& opt);

// Run i's identity (hex): the core build, the scene, every override, the
// method and the speed events. A result or checkpoint under another
// identity is never reused.
std::string stabilityCaseIdentity(const SweepPlan& plan, std::size_t i);

// Runs run i of the plan (wire_sim sweep-run): a result kept from an
// earlier study is reused, a checkpoint continued; a run longer than its
// budget is stopped and checkpointed; when `stop` turns true it is
// checkpointed and -1 returned (no status: pending). Returns 0 when it has
// a result, 1 when out of its budget.
int runStabilityCase(const SweepPlan& plan, const std::string& dir, std::size_t i,
                     const std::function<bool()>& stop);

// DIR/stability.csv and DIR/STABILITY.md from the runs' results; a run
// without one is PENDING (with its checkpoint's time). The CSV also on
// stdout. Returns 0 when every run met the criteria or stopped with a
// message naming its cause, 1 otherwise.
int writeStabilityTables(const SweepPlan& plan, const std::string& dir, bool report_only);

// The study into DIR: locally (opt.jobs processes; -1 when stopped by
// opt.stop, what is done kept) or submitted to Slurm. opt.fresh discards
// earlier results and checkpoints; opt.report_only writes the tables from
// what is kept and runs nothing.
int runStability(const std::string& scene_path, const std::vector<std::string>& overrides,
                 const std::string& dir, const StabilityOptions& opt, const SlurmOptions* slurm,
                 const std::string& exe);

}  // namespace cws_tools
