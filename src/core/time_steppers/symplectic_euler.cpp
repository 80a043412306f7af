#include "coil_winding_sim/core/time_steppers/symplectic_euler.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace cws {

SymplecticEuler::SymplecticEuler(const SolverParams& p, int capacity)
    : h_(p.fixed_step.value_or(0.0)) {
  // Simulation resolves `auto` (fixedStep()) before it builds the stepper.
  if (!(h_ > 0.0)) throw std::invalid_argument("symplectic_euler needs a resolved fixed step");
  dydt_.setZero(capacity);
}

void SymplecticEuler::step(OdeSystem& sys, double& t, Eigen::VectorXd& y, double t_limit) {
  const Eigen::Index n = sys.size();
  const bool clipped = t + h_ >= t_limit;
  const double h = clipped ? t_limit - t : h_;
  sys.derivative(t, y.head(n), dydt_.head(n));
  ++counts_.derivative_evaluations;
  if (!sys.semiImplicitUpdate(h, dydt_.head(n), y.head(n))) {
    throw IntegrationError("symplectic_euler needs a second-order system");
  }
  if (!std::isfinite(y.head(n).sum())) {  // one pass; see Simulation::step
    std::ostringstream msg;
    msg << "the state became non-finite at t = " << t << " s with symplectic_euler at "
        << "solver.fixed_step = " << h_
        << " s: either the step is above the stability limit of this scene (validation checks "
        << "only l / c; lower solver.fixed_step) or the motion itself diverges (rkf45 on the "
        << "same scene tells them apart)";
    throw IntegrationError(msg.str());
  }
  t = clipped ? t_limit : t + h;
  h_last_ = h;
  ++counts_.accepted;
  sys.acceptStep(t, y);
}

}  // namespace cws
