// The one catalogue of time integrators a scene may name: each one's name
// (solver.integrator), a line of description, the solver keys it reads and
// its traits (the scenes it takes). Scene validation, the simulation's
// messages and the tools read it. The steppers themselves live above, in
// time_steppers/ (makeTimeStepper builds the one named here): adding an
// integrator adds its row here, its file there and its line in
// makeTimeStepper.
#pragma once

#include <string>
#include <vector>

#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

struct IntegratorInfo {
  const char* name;
  const char* description;
  std::vector<const char*> keys;  // the solver keys it reads
  // Its traits, each set by name in its row (integrators.cpp).
  // Fixed step solver.fixed_step, explicit: refused above the stability
  // limit l / c.
  bool explicit_fixed_step = false;
  // Error-controlled (solver.rtol, solver.atol).
  bool error_controlled = false;
  // Newton steps of solver.implicit_step over a NewtonFormulation (planar
  // scenes in reduced coordinates, 3-D scenes with the frame constraints).
  bool newton_steps = false;
  // Numerically dissipative (L-stable):
  // it removes energy of motion its step does not resolve. That numerical
  // dissipation is reported as its own term; the energy balance then
  // bounds only energy the method creates.
  bool numerically_dissipative = false;
};

// All integrators, in the order messages list them.
const std::vector<IntegratorInfo>& integrators();
// The entry named `name`, or null.
const IntegratorInfo* findIntegrator(const std::string& name);
std::vector<std::string> integratorNames();

}  // namespace cws
