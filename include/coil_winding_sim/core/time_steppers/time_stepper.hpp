// Interface of the time integrators (one file per method in this folder).
#pragma once

#include <memory>
#include <string>

#include "coil_winding_sim/core/base/ode_system.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

struct StepCounts {
  long accepted = 0;
  long rejected = 0;
  long derivative_evaluations = 0;
};

// Newton's work over a run (implicit steppers), for summary.json.
struct NewtonCounts {
  long iterations = 0;            // Newton iterations, all solves
  long factorizations = 0;        // Jacobians assembled and factored (modified Newton reuses them)
  long flag_rounds = 0;           // solves repeated after a contact, stick or slip flag changed
  long line_searches = 0;         // halved Newton steps
  long retried_steps = 0;         // steps retried smaller (not converged, or beyond predictor_tol)
  long predictor_retries = 0;     // of them: converged, but beyond the predictor's bound
  long return_mapped_solves = 0;  // solves that reached the return-mapping round
  long strike_windows = 0;  // stretches of strike steps after a struck span (solver.strike_step)
  long fallback_stretches = 0;    // stretches of explicit steps where Newton could not go on
  long fallback_steps = 0;        // explicit steps in them
  char fallback_cause[160] = "";  // why it began (empty: none; a step allocates nothing)
};

class TimeStepper {
 public:
  virtual ~TimeStepper() = default;
  virtual const char* name() const = 0;
  // Step-size collapse (Simulation::checkCollapse): the fraction of the
  // explicit stability limit l / c below which this method's step must not
  // stay; 0: not checked (a fixed-step method).
  virtual double collapseRatio() const = 0;
  // Advances (t, y) by one accepted step that does not pass t_limit [s];
  // rejected attempts are retried with smaller steps. Calls sys.acceptStep
  // once. Throws IntegrationError when the step falls below its floor.
  virtual void step(OdeSystem& sys, double& t, Eigen::VectorXd& y, double t_limit) = 0;
  // Step size the next attempt will use [s].
  virtual double nextStep() const = 0;
  // Size of the last accepted step [s].
  virtual double lastStep() const = 0;
  virtual const StepCounts& counts() const = 0;
  // Newton's counts; null for a method without Newton iterations.
  virtual const NewtonCounts* newtonCounts() const { return nullptr; }
  // Continues from a snapshot: next and last step sizes [s] and counts.
  virtual void restore(double next_step, double last_step, const StepCounts& counts) = 0;
  // The prescribed motion's acceleration jumps at the present time (a core
  // speed ramp begins or ends): a stepper may take small steps from here.
  virtual void kink() {}
  // The longest step the process allows from the present time [s]
  // (Simulation::step: solver.steps_per_revolution at the core's speed):
  // a stepper of fixed steps may take shorter ones; the others ignore it.
  virtual void limitStep(double /*longest*/) {}
};

// Max norm of an error estimate `err` over the first n components, each
// scaled by atol + rtol max(|y|, |y_new|) (rtol where the system's weight is
// 1); NaN comes out as NaN, which fails every "<= 1" test.
double scaledErrorNorm(const OdeSystem& sys, double rtol, const Eigen::VectorXd& y,
                       const Eigen::VectorXd& y_new, const Eigen::VectorXd& err, Eigen::Index n);

// Stops an error-controlled run whose step fell below solver.min_step [s] at
// time t [s], after an attempt of step h [s] with error norm e.
[[noreturn]] void throwStepFloor(const char* method, double min_step, double t, double e, double h);

// The integrator named by solver.integrator, sized for `sys`.
std::unique_ptr<TimeStepper> makeTimeStepper(const SolverParams& p, OdeSystem& sys);

}  // namespace cws
