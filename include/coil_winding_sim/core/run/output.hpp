// Run outputs: summary.json, wire.csv, shape_core.csv.
#pragma once

#include <ostream>
#include <string>

#include "coil_winding_sim/core/run/coil_report.hpp"
#include "coil_winding_sim/core/run/error_estimate.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"

namespace cws {

// Why a run ended before its end time: a signal (SIGINT, SIGTERM) or an
// error the integration could not go on from, and the message said then.
// Its outputs are those of the state it reached (summary.json "stopped").
struct RunStop {
  std::string cause;    // "SIGINT", "SIGTERM" or "error"
  std::string message;  // what the run said when it stopped
};

// With `estimate`, summary.json also reports the run's own error
// (error_estimate.hpp); with `stop`, why the run ended early ("stopped",
// absent from a run that reached its end).
void writeSummaryJson(const Simulation& sim, std::ostream& out,
                      const ErrorEstimate* estimate = nullptr, const RunStop* stop = nullptr);
void writeWireCsv(const Simulation& sim, std::ostream& out);
// The coil report as a JSON object (null when not valid).
void writeCoilJson(const CoilReport& r, std::ostream& out);

// The wire in the core frame with each point's stand-off from the winding
// surface (scenes with a core that has cylinders).
void writeShapeCsv(const Simulation& sim, std::ostream& out);

// Writes DIR/summary.json, DIR/wire.csv and, with a core, DIR/shape_core.csv
// (creating DIR). Each file is
// written to a temporary name and renamed, so a failed run never leaves a
// complete-looking file. Throws std::runtime_error naming the path.
void writeOutputs(const Simulation& sim, const std::string& dir,
                  const ErrorEstimate* estimate = nullptr, const RunStop* stop = nullptr);

// Refuses early (before a run) a directory that cannot be created or written.
void checkOutputDir(const std::string& dir);

// Removes DIR's results of an earlier run (the files writeOutputs writes and
// leftover temporaries), so that a run that then fails or is stopped leaves
// none that looks like its own. Throws std::runtime_error naming a file that
// cannot be removed.
void removeOutputs(const std::string& dir);

// Writes `text` to `path` through a temporary file renamed into place: the
// file is complete or absent. Throws std::runtime_error naming the path.
void writeFileAtomically(const std::string& path, const std::string& text);

}  // namespace cws
