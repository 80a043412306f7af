#include "coil_winding_sim/core/time_steppers/integrators.hpp"

#include "coil_winding_sim/core/time_steppers/implicit_stepper.hpp"
#include "coil_winding_sim/core/time_steppers/rkf45.hpp"
#include "coil_winding_sim/core/time_steppers/rosenbrock2.hpp"
#include "coil_winding_sim/core/time_steppers/symplectic_euler.hpp"

namespace cws {

namespace {
std::unique_ptr<TimeStepper> makeRkf45(const SolverParams& p, OdeSystem& sys) {
  return std::make_unique<Rkf45>(p, sys.capacity());
}
std::unique_ptr<TimeStepper> makeSymplecticEuler(const SolverParams& p, OdeSystem& sys) {
  return std::make_unique<SymplecticEuler>(p, sys.capacity());
}
std::unique_ptr<TimeStepper> makeRosenbrock2(const SolverParams& p, OdeSystem& sys) {
  return std::make_unique<Rosenbrock2>(p, sys);
}
std::unique_ptr<TimeStepper> makeImplicitEuler(const SolverParams& p, OdeSystem& sys) {
  return std::make_unique<ImplicitStepper>(p, sys, ImplicitStepper::Scheme::kBackwardEuler);
}
std::unique_ptr<TimeStepper> makeBdf2(const SolverParams& p, OdeSystem& sys) {
  return std::make_unique<ImplicitStepper>(p, sys, ImplicitStepper::Scheme::kBdf2);
}

std::unique_ptr<TimeStepper> makeGeneralizedAlpha(const SolverParams& p, OdeSystem& sys) {
  return std::make_unique<ImplicitStepper>(p, sys, ImplicitStepper::Scheme::kGeneralizedAlpha);
}
std::vector<IntegratorInfo> registry() {
  std::vector<IntegratorInfo> r;
  r.push_back({"rkf45",
               "the paper's Runge-Kutta-Fehlberg 4(5), error-controlled; the reference",
               {"rtol", "atol", "min_step", "max_step", "initial_step", "baumgarte_nu"},
               false,
               true,
               false,
               false,
               makeRkf45});
  r.push_back({"symplectic_euler",
               "fixed-step semi-implicit Euler below the explicit limit l / c",
               {"fixed_step", "baumgarte_nu"},
               true,
               false,
               false,
               false,
               makeSymplecticEuler});
  r.push_back({"rosenbrock2",
               "linearly implicit Rosenbrock-W, banded Jacobian; stiff scenes without friction",
               {"rtol", "atol", "min_step", "max_step", "initial_step", "baumgarte_nu"},
               false,
               true,
               false,
               false,
               makeRosenbrock2});
  // The Newton-step methods' keys (generalized_alpha adds rho_infinity).
  const std::vector<const char*> newton = {
      "implicit_step",     "steps_per_revolution",  "newton_tol",
      "newton_energy_tol", "newton_max_iterations", "flag_rounds",
      "flag_check_tol",    "return_mapping_round",  "predictor_tol",
      "min_step"};
  std::vector<const char*> alpha = newton;
  alpha.insert(alpha.begin() + 2, "rho_infinity");
  r.push_back({"implicit_euler", "backward Euler with Newton steps (first order, L-stable)", newton,
               false, false, true, true, makeImplicitEuler});
  r.push_back({"bdf2", "variable-step BDF2 with Newton steps (second order, L-stable)", newton,
               false, false, true, true, makeBdf2});
  r.push_back({"generalized_alpha",
               "generalized-alpha with Newton steps (second order, high frequencies damped to "
               "rho_infinity)",
               alpha, false, false, true, true, makeGeneralizedAlpha,
               "not calibrated for generalized_alpha: 0.2 to 5 times its true error on the five "
               "accuracy cases (docs/PERFORMANCE.md)"});
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
