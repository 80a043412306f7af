// A run's own error: the same scene run again with a refined setting (half
// the step of a fixed-step or Newton-step method, a tenth of the tolerances
// of an error-controlled one) and the two results compared, so that a user
// reads error against run time for their own scene (wire_sim run
// --error-estimate).
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "coil_winding_sim/core/scene.hpp"
#include "coil_winding_sim/core/simulation.hpp"

namespace cws {

struct ErrorEstimate {
  std::string refinement;  // what the second run changed, e.g. "solver.fixed_step / 2"
  double shape_error_rel_diameter = 0.0;  // largest point distance (core frame) / d
  double bulging_error_rel = 0.0;         // |difference| / refined bulging height (0 without one)
  bool bulging_valid = false;
  double wall_s = 0.0;          // the run's own wall time [s]
  double refined_wall_s = 0.0;  // the refined run's [s]
};

// The scene of the refined run, and a description of the refinement.
Scene refinedScene(const Scene& scene, std::string& refinement);
// A run's start state with its scene refined likewise: the refined run
// continues from the same state (a restored snapshot, or a scene's start).
SimulationState refinedState(const SimulationState& start, std::string& refinement);
// Compares a finished run with its refined twin.
ErrorEstimate compareWithRefined(const Simulation& run, const Simulation& refined,
                                 const std::string& refinement);

class InputLog;
// The error of a run that received inputs while it ran (the ROS node's
// jobs): the run again from its start state with the refined setting, given
// the same inputs at the same simulated times up to the finished run's
// time, and compared with it. The refined run's wall time is measured here;
// the finished run's is the caller's to set. Returns nothing when `stop`
// (asked before every step) said stop; throws what the refined run throws
// (IntegrationError, an overflowed log's std::logic_error).
std::optional<ErrorEstimate> estimateFromInputs(const SimulationState& start,
                                                const InputLog& inputs, const Simulation& finished,
                                                const std::function<bool()>& stop = {});

}  // namespace cws
