// A sweep's plan (wire_sim sweep): its cases, each a list of scene-key
// overrides applied to one base scene after the sweep's own --set
// overrides. The cases come from a grid (the cartesian product of --grid
// axes) or from a cases file (CSV, one column per key), and the plan is
// kept as a text file in the sweep's directory, so that each case can be
// run by its index alone (a local process or a Slurm array task).
#pragma once

#include <cstddef>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace cws_tools {

// A malformed grid, cases file or plan; the message names what is wrong.
class SweepError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One key's values: "key=a:b:n" (n values from a to b, evenly spaced),
// "key=v1,v2,..." (a list) or "key=v" (one value).
struct GridAxis {
  std::string key;
  std::vector<std::string> values;
};
GridAxis parseGridAxis(const std::string& arg);

struct SweepPlan {
  // What the cases are and what the table adds: "sweep" (plain runs) or a
  // registered kind (PlanKind: "study", the paper's 2 x 2 study, whose
  // tables gather adds; "stability", the stability matrix).
  std::string kind = "sweep";
  std::string scene;                            // base scene file ("": built-in defaults)
  std::vector<std::string> overrides;           // the sweep's --set, before each case's keys
  std::vector<std::string> keys;                // the swept keys
  std::vector<std::vector<std::string>> cases;  // per case, one value per key
  std::vector<std::string> names;               // per case, its folder (empty: case_NNNN)
  // Settings of the kind (stability: the budget and checkpoint interval).
  std::vector<std::pair<std::string, std::string>> options;

  // The overrides of case i: the sweep's, then "key=value" per swept key.
  std::vector<std::string> caseOverrides(std::size_t i) const;
  // "key=value, key=value" for messages.
  std::string caseLabel(std::size_t i) const;
  // The case's folder in the sweep's directory: its name, or case_0000,
  // case_0001, ...
  std::string caseDir(std::size_t i) const;
  // An option's value, or `fallback`.
  std::string option(const std::string& key, const std::string& fallback) const;
};

// What a kind of plan does in place of a plain sweep's way; an empty hook
// keeps the plain way. A kind registers itself (registerPlanKind) where it
// is defined (study.cpp, stability.cpp): the sweep knows none of them.
struct PlanKind {
  // A case's identity (a run is kept while it stays the same).
  std::function<std::string(const SweepPlan&, std::size_t)> case_identity;
  // Runs case i in `dir`; its exit code.
  std::function<int(const SweepPlan&, const std::string&, std::size_t,
                    const std::function<bool()>&)>
      run_case;
  // Writes the table in place of the plain one; its exit code.
  std::function<int(const SweepPlan&, const std::string&)> gather;
  // Adds to the plain table; its exit code.
  std::function<int(const SweepPlan&, const std::string&)> add_to_table;
  // Whether checkPlan loads every case's scene (false: a refused scene is
  // one of the kind's results).
  bool check_scenes = true;
  // The kind reports its own progress: runSweepLocal prints none.
  bool quiet = false;
};
// Registers a kind under `name`; returns true (for a static initializer).
bool registerPlanKind(const std::string& name, PlanKind kind);
// The kind registered under `name`; null for "sweep" or an unknown name.
const PlanKind* findPlanKind(const std::string& name);

// The cartesian product of the axes, the first axis varying slowest.
SweepPlan gridPlan(const std::string& scene, const std::vector<std::string>& overrides,
                   const std::vector<GridAxis>& axes);
// A cases file: a header of keys, then one row of values per case ("..."
// quotes a value holding commas); `file` names it in messages.
SweepPlan casesPlan(const std::string& scene, const std::vector<std::string>& overrides,
                    const std::string& csv_text, const std::string& file);

// Every case's scene loads and passes validation; otherwise throws
// cws::SceneError naming the case and the key. Throws SweepError for a
// plan without cases.
void checkPlan(const SweepPlan& plan);

// The plan as text (tab-separated lines) and back; `file` names it in
// messages.
std::string planText(const SweepPlan& plan);
SweepPlan parsePlanText(const std::string& text, const std::string& file);

}  // namespace cws_tools
