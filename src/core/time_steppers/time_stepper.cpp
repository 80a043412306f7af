#include "coil_winding_sim/core/time_steppers/time_stepper.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "coil_winding_sim/core/time_steppers/implicit_stepper.hpp"
#include "coil_winding_sim/core/time_steppers/rkf45.hpp"
#include "coil_winding_sim/core/time_steppers/symplectic_euler.hpp"

namespace cws {

double scaledErrorNorm(const OdeSystem& sys, double rtol, const Eigen::VectorXd& y,
                       const Eigen::VectorXd& y_new, const Eigen::VectorXd& err, Eigen::Index n) {
  const Eigen::VectorXd& atol = sys.absoluteTolerance();
  const Eigen::VectorXd& rweight = sys.relativeToleranceWeight();
  double norm = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double scale = atol[i] + rweight[i] * rtol * std::max(std::abs(y[i]), std::abs(y_new[i]));
    const double e = std::abs(err[i]) / scale;
    if (!(e <= norm)) norm = e;  // NaN propagates as a failure
  }
  return norm;
}

void throwStepFloor(const char* method, double min_step, double t, double e, double h) {
  std::ostringstream msg;
  msg << "step size fell below solver.min_step = " << min_step << " s at t = " << t
      << " s (error norm " << e << " at step " << h
      << " s): the scene is too stiff or unstable for " << method
      << "; lower solver.min_step, loosen solver.rtol/atol, or check the scene";
  throw IntegrationError(msg.str());
}

std::unique_ptr<TimeStepper> makeTimeStepper(const SolverParams& p, OdeSystem& sys) {
  // The stepper of each integrator of the scene's catalogue
  // (scene/integrators.hpp), by its name there.
  const std::string& name = p.integrator;
  if (name == "rkf45") return std::make_unique<Rkf45>(p, sys.capacity());
  if (name == "symplectic_euler") return std::make_unique<SymplecticEuler>(p, sys.capacity());
  using Scheme = ImplicitStepper::Scheme;
  if (name == "implicit_euler")
    return std::make_unique<ImplicitStepper>(p, sys, Scheme::kBackwardEuler);
  if (name == "bdf2") return std::make_unique<ImplicitStepper>(p, sys, Scheme::kBdf2);
  throw std::invalid_argument("unknown integrator '" + name + "'");
}

}  // namespace cws
