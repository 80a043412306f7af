// Implicit steps over a NewtonFormulation (the planar wire's reduced
// coordinates, or the 3-D wire with its frame constraints): backward Euler
// (implicit_euler), first order and L-stable, and the variable-step BDF2
// (bdf2), second order and L-stable. Both solve
//   v = alpha (x - x_hat),   alpha M (v - v_hat) = F(x, v)
// with Newton's method at every step of solver.implicit_step, or of one
// revolution of the core over solver.steps_per_revolution where that is
// shorter (limitStep: the step follows the process); a step whose
// Newton iterations do not converge is retried at a quarter of its size and
// the step grows back by doubling. BDF2 starts, and restarts after a
// retried step or a step more than twice the last, with one backward Euler
// step. A run starts with small steps (kStartFraction), and so does the
// step after a kink of the core's motion (kink()). With solver.strike_step,
// a step in which the core strikes the free span (a point of it lands well
// beyond the wound wire, fast) is redone in steps of an eighth until one of
// strike_step takes the landing, and the steps stay there for
// kStrikeWindow (docs/MODEL.md, "Steps through a struck span").
// Progress is guaranteed: where the retried step would fall below
// solver.min_step, a stretch of kFallbackStretch of symplectic Euler steps
// at the explicit safe step (solver.fixed_step as resolved) carries the run
// on, and Newton steps resume after it (counted in NewtonCounts; the
// node's /diagnostics warns).
#pragma once

#include <Eigen/Core>
#include <memory>

#include "coil_winding_sim/core/implicit/newton_formulation.hpp"
#include "coil_winding_sim/core/time_steppers/time_stepper.hpp"

namespace cws {

class ImplicitStepper : public TimeStepper {
 public:
  enum class Scheme { kBackwardEuler, kBdf2 };
  // A limit this close to t (relative to max(1 s, |t|)) counts as reached.
  static constexpr double kLandRounding = 1e-12;
  // A step may be this much longer to land on the limit.
  static constexpr double kLandStretch = 0.01;
  // A run, and the step after a kink of the core's motion, start with this
  // fraction of solver.implicit_step, doubled each step: full steps
  // through the jerk of the clamped wire booked energy it did not get
  // (docs/MODEL.md, "Implicit integration of planar scenes").
  static constexpr double kStartFraction = 1.0 / 64.0;
  // A span counts as struck where a point at least this many points beyond
  // the wound wire lands (solver.strike_step).
  static constexpr int kStrikeGap = 3;
  // ... and lands at this speed relative to the core or faster [m/s]
  // (docs/MODEL.md, "Steps through a struck span"; the scene key
  // solver.strike_speed until issue 61).
  static constexpr double kStrikeSpeed = 1.0;
  // ... and the steps stay at solver.strike_step for this long after it
  // [s]: the wave the strike sends along the span needs them (1e-4 s left
  // 0.0107 d at 1200 rpm; the scene key solver.strike_window until issue
  // 61).
  static constexpr double kStrikeWindow = 1.5e-4;
  // A step whose solution lies farther than this from the predictor x0 + h
  // v0 + h^2 / 2 a0 [m] is retried at a quarter (the scene key
  // solver.predictor_tol until issue 61).
  static constexpr double kPredictorTol = 1.0e-4;
  // The explicit fallback's stretch of simulated time [s].
  static constexpr double kFallbackStretch = 1e-3;
  ImplicitStepper(const SolverParams& p, OdeSystem& sys, Scheme scheme);

  const char* name() const override { return scheme_ == Scheme::kBdf2 ? "bdf2" : "implicit_euler"; }
  double collapseRatio() const override { return 0.0; }
  void step(OdeSystem& sys, double& t, Eigen::VectorXd& y, double t_limit) override;
  double nextStep() const override { return h_; }
  double lastStep() const override { return h_last_; }
  const StepCounts& counts() const override { return counts_; }
  void restore(double next_step, double last_step, const StepCounts& counts) override;
  const NewtonCounts* newtonCounts() const override { return &newton_; }
  void kink() override;
  void limitStep(double longest) override;

 private:
  // The explicit fallback: a stretch begins at t after Newton failed at a
  // step of h [s] (converged: the solution left the predictor); one
  // explicit step of it.
  void beginFallback(double t, double h, bool converged);
  void explicitStep(OdeSystem& sys, double& t, Eigen::VectorXd& y, double t_limit);
  SolverParams p_;
  Scheme scheme_;
  // The formulation it solves, built from the system's view of its model.
  std::unique_ptr<NewtonFormulation> formulation_;
  NewtonModelView* model_ = nullptr;  // the system's view for the formulation
  double h_, h_last_ = 0.0;
  // The longest step at present [s]: solver.implicit_step, or less where
  // the core turns fast (limitStep); whether a kink awaits the next limit.
  double longest_;
  bool kinked_ = false;
  StepCounts counts_;
  NewtonCounts newton_;
  // The step before the present one (BDF2): configuration and rates of
  // every point (the formulation's rows), its size, and whether it can be
  // used; the present step's scheme data.
  Eigen::MatrixXd x_prev_, v_prev_, x_hat_, v_hat_, guess_;
  double h_prev_ = 0.0;
  double t_prev_ = 0.0;  // the last accepted step's start [s]
  int n_prev_ = 0;
  int first_prev_ = 0;  // the first integrated point of the last step
  bool have_prev_ = false;
  // The model's retired points (OdeSystem::pointsRetired) the past above is
  // numbered after; -1: not known (a restore).
  long retired_seen_ = -1;
  // Moves the past of the last step to the live arrays' numbering after k
  // points retired from their front.
  void retirePast(int k);
  // Steps through a struck span: they stay at solver.strike_step until this
  // time [s].
  double strike_until_ = -1.0;
  std::unique_ptr<TimeStepper> explicit_;  // the fallback's stepper (none: no safe step)
  double fallback_until_ = -1.0;           // the stretch's end [s]
};

}  // namespace cws
