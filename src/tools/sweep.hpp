// Parameter sweeps (wire_sim sweep): one mechanism that runs a plan's cases
// as separate processes, locally N at once, each case into a folder of its
// own, and gathers their summaries into one table. A case is always run by
// `wire_sim sweep-run DIR INDEX`, whoever starts it (this machine, or a
// Slurm array task), and leaves DIR/case_NNNN/status.txt: the case's
// identity (the core build and the resolved scene), ok or failed, and the
// error. A later sweep in the same DIR reuses a case whose status is ok and
// whose identity is unchanged.
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "sweep_plan.hpp"

namespace cws_tools {

// File names in a sweep's directory.
extern const char* const kSweepPlanFile;    // the plan (sweep_plan.tsv)
extern const char* const kSweepStatusFile;  // per case: status.txt
extern const char* const kSweepResultsCsv;  // results.csv
extern const char* const kSweepResultsMd;   // results.md

// A case's status.txt: present once its run has ended (status "ok",
// "failed" with the error, or "budget": stopped at the plan's wall-time
// budget, with the figures of the part it ran).
struct SweepCaseStatus {
  bool present = false;
  std::string identity, status, error;
  double wall_s = 0.0;
  double budget_s = 0.0;  // the wall-time budget it ran with [s] (0: none)
};
SweepCaseStatus readCaseStatus(const SweepPlan& plan, const std::string& dir, std::size_t i);
void writeCaseStatus(const SweepPlan& plan, const std::string& dir, std::size_t i,
                     const SweepCaseStatus& s);

// The numbers of a summary.json: top-level scalars, and those of its
// objects as "object.key"; throws when the file cannot be read.
std::map<std::string, double> readSummaryNumbers(const std::string& path);

// The plan of a cases file (casesPlan); throws SweepError naming the file
// when it cannot be read.
SweepPlan readCasesFile(const std::string& scene, const std::vector<std::string>& overrides,
                        const std::string& path);

// Writes the plan to DIR (created if need be); throws naming the file.
void writePlan(const SweepPlan& plan, const std::string& dir);
SweepPlan readPlan(const std::string& dir);

// The identity a case's results are kept under: the core build and the
// case's resolved scene (hex).
std::string caseIdentity(const SweepPlan& plan, std::size_t index);

// The cases of the plan whose results DIR does not keep (status ok under
// the same identity), in order; `kept` counts the others.
std::vector<std::size_t> casesToRun(const SweepPlan& plan, const std::string& dir,
                                    std::size_t& kept);
// Forgets case i's status, so that it reads as pending until it has run.
void clearCaseStatus(const SweepPlan& plan, const std::string& dir, std::size_t i);

// Runs case INDEX of the plan in DIR (wire_sim sweep-run): its outputs and
// status.txt in DIR/case_NNNN. Returns 0 when it ran, 1 when it failed (the
// status says why), 2 for a bad DIR or INDEX, -1 when `stop` turned true
// (no status: the case is pending).
int runSweepCase(const std::string& dir, std::size_t index, const std::function<bool()>& stop);

// Runs the plan's cases in DIR as `exe sweep-run DIR i`, `jobs` at once,
// each one's console output in its folder (log.txt), reusing kept results;
// progress on stderr; then gathers. Returns gatherSweep's code, or -1 when
// `stop` turned true: the running cases are then sent SIGINT and waited
// for, and nothing is gathered.
int runSweepLocal(const SweepPlan& plan, const std::string& dir, int jobs, const std::string& exe,
                  const std::function<bool()>& stop = {});

// The results table: DIR/results.csv (one row per case: its keys, its
// status and error, and every number of its summary.json) and
// DIR/results.md. Cases without a status are pending, named on stderr.
// Returns 0 when every case ran, 1 when one failed or is pending.
int gatherSweep(const std::string& dir);

}  // namespace cws_tools
