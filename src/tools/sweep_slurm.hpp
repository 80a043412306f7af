// A sweep on a Slurm cluster (wire_sim sweep --slurm): the cases still to
// run become job arrays, one task per case running `wire_sim sweep-run DIR
// INDEX` on the shared file system, and a gather job that waits for them
// (afterany) writes the table. The scripts are kept in DIR/slurm/.
#pragma once

#include <string>
#include <vector>

#include "sweep_plan.hpp"

namespace cws_tools {

struct SlurmOptions {
  std::string partition;   // --partition (empty: the cluster's default)
  std::string time_limit;  // per task: minutes, MM:SS, HH:MM:SS or D-HH:MM:SS (empty: default)
  std::string memory;      // per task: e.g. 2G, 500M (empty: default)
  std::string account;     // --account (empty: the user's default)
  int max_running = 0;     // tasks of an array at once (%N); 0: no limit
  // The cluster's MaxArraySize: array indices stay below it, so a larger
  // sweep is submitted as several arrays.
  int max_array_size = 1001;
  bool dry_run = false;  // write the scripts, submit nothing
};

// Options of the command line: true when `opt` is one that takes a value
// (--partition, --time, --mem, --account, --max-running, --max-array-size);
// setSlurmOption stores it and returns "" or what is wrong with it.
bool isSlurmValueOption(const std::string& opt);
std::string setSlurmOption(SlurmOptions& o, const std::string& opt, const std::string& value);

// Throws SweepError naming the option that Slurm would not take.
void checkSlurmOptions(const SlurmOptions& o);

// The sbatch script of one job array: cases first + SLURM_ARRAY_TASK_ID for
// the indices in `array` (Slurm's --array syntax, without %N).
std::string slurmArrayScript(const SlurmOptions& o, const std::string& exe, const std::string& dir,
                             std::size_t first, const std::string& array);
// The sbatch script of the gather job.
std::string slurmGatherScript(const SlurmOptions& o, const std::string& exe,
                              const std::string& dir);
// Indices as Slurm's --array list: "0-4,7,9-12" (sorted input).
std::string arrayList(const std::vector<std::size_t>& indices);

// Writes the plan and the scripts to DIR (absolute paths in them) and,
// unless o.dry_run, submits them with sbatch; progress and the job ids on
// stderr. Cases kept from an earlier sweep are not submitted. Returns 0
// when submitted (or written, for a dry run), 1 when sbatch failed (its
// message shown).
int runSweepSlurm(const SweepPlan& plan, const std::string& dir, const SlurmOptions& o,
                  const std::string& exe);

}  // namespace cws_tools
