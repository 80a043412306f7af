#include "coil_winding_sim/core/scene/integrators.hpp"

namespace cws {

namespace {
// A row: name, description and the solver keys it reads; the caller sets
// its traits by name on the row returned.
IntegratorInfo& row(std::vector<IntegratorInfo>& r, const char* name, const char* description,
                    std::vector<const char*> keys) {
  r.push_back({name, description, std::move(keys)});
  return r.back();
}

std::vector<IntegratorInfo> registry() {
  std::vector<IntegratorInfo> r;
  const std::vector<const char*> adaptive = {"rtol",     "atol",         "min_step",
                                             "max_step", "initial_step", "baumgarte_nu"};
  row(r, "rkf45", "the paper's Runge-Kutta-Fehlberg 4(5), error-controlled; the reference",
      adaptive)
      .error_controlled = true;
  row(r, "symplectic_euler", "fixed-step semi-implicit Euler below the explicit limit l / c",
      {"fixed_step", "baumgarte_nu"})
      .explicit_fixed_step = true;
  // The Newton-step methods' keys.
  const std::vector<const char*> newton = {"implicit_step", "steps_per_revolution", "newton_tol",
                                           "newton_max_iterations", "min_step"};
  const std::size_t first_newton = r.size();
  row(r, "implicit_euler", "backward Euler with Newton steps (first order, L-stable)", newton);
  row(r, "bdf2", "variable-step BDF2 with Newton steps (second order, L-stable)", newton);
  for (std::size_t k = first_newton; k < r.size(); ++k) {
    r[k].newton_steps = true;
    r[k].numerically_dissipative = true;
  }
  return r;
}
}  // namespace

const std::vector<IntegratorInfo>& integrators() {
  static const std::vector<IntegratorInfo> r = registry();
  return r;
}

const IntegratorInfo* findIntegrator(const std::string& name) {
  for (const IntegratorInfo& i : integrators()) {
    if (name == i.name) return &i;
  }
  return nullptr;
}

std::vector<std::string> integratorNames() {
  std::vector<std::string> names;
  for (const IntegratorInfo& i : integrators()) names.emplace_back(i.name);
  return names;
}

}  // namespace cws
