// What makes a finished run numerically trustworthy: the criteria of the
// stability study (docs/STABILITY.md), measured on a Simulation and checked
// in one place for the study tool and the tests.
#pragma once

#include <string>
#include <vector>

#include "coil_winding_sim/core/simulation.hpp"

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

}  // namespace cws
