// The one registry of time integrators: each one's name (solver.integrator),
// a line of description, the solver keys it reads, the scenes it takes and
// how it is built. Scene validation, the stepper factory, the simulation's
// messages and the tools read it; adding an integrator adds one entry here
// and its file in this folder.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

class OdeSystem;
class TimeStepper;

struct IntegratorInfo {
  const char* name;
  const char* description;
  std::vector<const char*> keys;  // the solver keys it reads
  std::unique_ptr<TimeStepper> (*make)(const SolverParams& p, OdeSystem& sys) = nullptr;
  // Its traits, each set by name in its row (integrators.cpp).
  // Fixed step solver.fixed_step, explicit: refused above the stability
  // limit l / c.
  bool explicit_fixed_step = false;
  // Error-controlled (solver.rtol, solver.atol).
  bool error_controlled = false;
  // Newton steps of solver.implicit_step over a NewtonFormulation (planar
  // scenes in reduced coordinates, 3-D scenes with the frame constraints).
  bool newton_steps = false;
  // Numerically dissipative (L-stable, or damping the highest frequencies):
  // it removes energy of motion its step does not resolve. That numerical
  // dissipation is reported as its own term; the energy balance then
  // bounds only energy the method creates.
  bool numerically_dissipative = false;
  // What --error-estimate's refinement is known to get wrong with this
  // method, said beside the estimate (null: within a factor of 2 of the
  // true error where measured).
  const char* estimate_caveat = nullptr;
};

// All integrators, in the order messages list them.
const std::vector<IntegratorInfo>& integrators();
// The entry named `name`, or null.
const IntegratorInfo* findIntegrator(const std::string& name);
std::vector<std::string> integratorNames();

}  // namespace cws
