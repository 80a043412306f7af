// A run's own error: the same scene run again with a refined setting and
// the two results compared, so that a user reads error against run time for
// their own scene (wire_sim run --error-estimate). The Newton-step methods
// run again at a quarter of the step, and the difference times 4/3 is the
// estimate: their error is first order in the step (contact, stick and slip
// are decided at a step's end; docs/PERFORMANCE.md, "An honest error
// estimate"), so e(h) = d / (1 - 1/4) for the difference d between h and
// h/4. The explicit fixed-step methods run again at half the step, the
// error-controlled ones at a tenth of the tolerances; the difference is
// their estimate.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "coil_winding_sim/core/run/simulation.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

struct ErrorEstimate {
  std::string refinement;  // what the second run changed, e.g. "solver.fixed_step / 2"
  // The distance of the two wound curves (core frame; the whole wire where
  // nothing is wound) over d, times `scale`: the shape error the accuracy
  // figures measure.
  double shape_error_rel_diameter = 0.0;
  // |difference| / refined bulging height, times `scale` (0 without one).
  double bulging_error_rel = 0.0;
  bool bulging_valid = false;
  double scale = 1.0;           // what the differences were multiplied by (refinementScale)
  double wall_s = 0.0;          // the run's own wall time [s]
  double refined_wall_s = 0.0;  // the refined run's [s]
};

// The scene of the refined run, and a description of the refinement.
Scene refinedScene(const Scene& scene, std::string& refinement);
// What the difference between a run of `scene` and its refined twin is
// multiplied by to estimate the run's error (4/3 for the Newton-step
// methods, 1 for the others).
double refinementScale(const Scene& scene);
// The largest distance [m] of a point of curve `a` from polyline `b` (both
// ways: the larger of the two), searching b's segments within
// kCurveWindow of the point's own index (curves of one wire whose points
// correspond; where they do not, the distance found is an upper bound).
double curveDistance(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b);
constexpr int kCurveWindow = 16;
// A run's start state with its scene refined likewise: the refined run
// continues from the same state (a restored snapshot, or a scene's start).
SimulationState refinedState(const SimulationState& start, std::string& refinement);
// How far a run's end lies from another's: the distance of their wound
// curves (the part both wound, core frame) over d, and the bulging heights'
// difference relative to the other's.
struct RunDifference {
  double shape_rel_diameter = 0.0;
  double bulging_rel = 0.0;
  bool bulging_valid = false;  // both wound wire with a bulging height
};
RunDifference differenceOf(const Simulation& run, const Simulation& other);
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
