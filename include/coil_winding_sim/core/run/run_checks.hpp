// What makes a finished run numerically trustworthy: the criteria of the
// stability study (docs/STABILITY.md), measured on a Simulation and checked
// in one place for the study tool and the tests.
#pragma once

#include <string>
#include <vector>

#include "coil_winding_sim/core/run/simulation.hpp"

namespace cws {

// Bounds a run must stay within to count as stable. The defaults are the
// stated criteria of docs/STABILITY.md; the reasons are given there.
struct StabilityCriteria {
  // |KE + U + D - W| / max(|W|, KE + U + D): the energy balance [-].
  double energy_rel = 1.0e-2;
  // Largest frame constraint residual over the run (segment off its frame's
  // tangent, quaternion off unit length) [-], i.e. [rad].
  double residual = 1.0e-3;
  // Deepest contact penetration over the run / wire radius [-].
  double penetration_ratio = 0.5;
};

// Figures of a run against those criteria.
struct RunMeasures {
  bool finite = true;              // state and energy terms all finite
  double energy_rel = 0.0;         // relative energy imbalance |KE + U + D - W| / scale [-]
  double energy_signed_rel = 0.0;  // the same with its sign: < 0 energy lost, > 0 created
  // The method is numerically dissipative (IntegratorInfo): its lost energy
  // is numerical dissipation, reported, not a broken balance.
  bool dissipative_method = false;
  double energy_scale_J = 0.0;     // max(|W|, KE + U + D) [J]
  double residual = 0.0;           // largest constraint residual [-]
  double penetration_ratio = 0.0;  // deepest penetration / radius [-] (0 without contact)
  long steps = 0;                  // accepted steps
  long rejected = 0;
  double mean_step_s = 0.0;  // simulated time / accepted steps [s]
};

RunMeasures measureRun(const Simulation& sim);

// The criteria `m` breaks, one line each naming the figure and its bound;
// empty when the run counts as stable.
std::vector<std::string> stabilityViolations(const RunMeasures& m, const StabilityCriteria& c = {});

// What a failed step says (Simulation::step throws IntegrationError with
// it): what failed, where, and what to change. `method` is the stepper's
// name.
namespace remedy {
// A segment `residual` [rad] off its frame's tangent at t [s], with steps
// of step_s [s].
std::string diverged(const Scene& s, double t, double residual, const std::string& method,
                     double step_s);
// Point `point` `depth_radii` wire radii deep in segment `segment` of
// `what` ("wound wire", "free wire") at t [s].
std::string wireThroughWire(const Scene& s, double t, const char* what, int point,
                            double depth_radii, int segment, const std::string& method);
// Point `point` lies outside_m [m] beyond flange `flange` (0: the first),
// from_axis_m [m] from the core axis against the flanges' reach_m, at t [s].
std::string overFlange(const Scene& s, double t, int point, int flange, double outside_m,
                       double from_axis_m, double reach_m);
// `steps` accepted steps in a row below `below_s` [s] (`ratio` times the
// explicit limit l / c) from since_s to t [s], the last h [s].
std::string collapsed(const Scene& s, const std::string& method, long steps, double below_s,
                      double ratio, double since_s, double t, double h);
// `what` with the cause named when the failure began (t_fail_s [s]) within
// a core speed ramp (ending at ramp_end_s [s], of ramp_acceleration
// [rad/s^2]) shorter than a wave's crossing of a segment; else `what`.
std::string withinRamp(const Scene& s, const std::string& what, const std::string& method,
                       double t_fail_s, double ramp_end_s, double ramp_acceleration);
}  // namespace remedy

}  // namespace cws
