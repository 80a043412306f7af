// The stability study's results and their report: one run's outcome and
// measures, and the table written from them as CSV and Markdown
// (docs/STABILITY.md), apart from running the cases (stability.cpp).
#pragma once

#include <string>
#include <vector>

#include "coil_winding_sim/core/run/run_checks.hpp"
#include "coil_winding_sim/core/scene/stability_cases.hpp"

namespace cws_tools {

// How a run ended.
enum class Outcome { kStable, kViolated, kStopped, kRefused, kBudget, kPending };

const char* outcomeName(Outcome o);

struct StabilityRun {
  const cws::StabilityCase* c = nullptr;
  std::string method;
  Outcome outcome = Outcome::kStopped;
  std::string message;  // why it stopped, was refused, or which criteria it broke
  cws::RunMeasures m;
  bool measured = false;
  double wall_s = 0.0, sim_s = 0.0, end_s = 0.0, step_s = 0.0;
  bool kept = false;         // taken from an earlier study's result file
  bool interrupted = false;  // stopped by a signal: checkpointed, no result
};

// What the report says about the study as a whole.
struct ReportInfo {
  double budget_s = 0.0;     // wall-time budget per run [s]
  int jobs = 1;              // runs in parallel
  double study_min = 0.0;    // the study's wall time [min]
  bool report_only = false;  // written from kept results while in progress
};

// Writes DIR/stability.csv and DIR/STABILITY.md and returns the CSV text;
// `bad` counts the runs that broke the criteria or the budget, or are
// pending.
std::string writeStabilityReport(const std::string& dir, const std::vector<StabilityRun>& runs,
                                 const ReportInfo& info, int& bad);

}  // namespace cws_tools
