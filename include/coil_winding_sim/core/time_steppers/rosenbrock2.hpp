// ROS2, the two-stage L-stable Rosenbrock-W method of Verwer et al. (1999),
// for stiff systems: steps far above the explicit stability limit at two
// right-hand sides and two banded solves per step.
//
//   W = I - gamma h J,  gamma = 1 + 1/sqrt(2)
//   W k1 = F(t, y) + gamma h F_t
//   W k2 = F(t + h, y + h k1) - 2 k1 - gamma h F_t
//   y+ = y + 3/2 h k1 + 1/2 h k2,   error estimate W^-1 1/2 h (k1 + k2)
//
// Second order for any matrix J (a W-method), so J may be approximate and
// old: it is a finite-difference Jacobian over the system's chain structure
// (one right-hand side per colour and block component; blocks further apart
// than the chain radius are dropped), kept for up to kJacobianMaxAge
// accepted steps and rebuilt after a rejected step. W is refactored (banded
// LU, O(n)) only when the step size changes by more than a small band.
// The integrated quantities of the chain's lead (work done, dissipation) are
// treated explicitly (zero rows of J). F_t (the clamp and port move with the
// core) is a forward difference at every attempt: without it the error
// estimate of a stiff spring dragged by the clamp is h |v_clamp| and the
// step collapses. The error estimate is filtered by W^-1 (as in Radau5) so
// that stiff components the method damps do not limit the step. Nothing
// allocates after construction.
#pragma once

#include "coil_winding_sim/core/linear_algebra/banded_lu.hpp"
#include "coil_winding_sim/core/time_steppers/time_stepper.hpp"

namespace cws {

class Rosenbrock2 : public TimeStepper {
 public:
  static constexpr int kJacobianMaxAge = 25;

  // Throws std::invalid_argument if the system has no chain structure.
  Rosenbrock2(const SolverParams& p, const OdeSystem& sys);

  const char* name() const override { return "rosenbrock2"; }
  // Below the explicit limit an implicit step (two banded solves) buys
  // nothing: symplectic_euler takes such steps at a tenth of the cost.
  double collapseRatio() const override { return 1.0; }
  void step(OdeSystem& sys, double& t, Eigen::VectorXd& y, double t_limit) override;
  double nextStep() const override { return h_; }
  double lastStep() const override { return h_last_; }
  const StepCounts& counts() const override { return counts_; }
  void restore(double next_step, double last_step, const StepCounts& counts) override {
    h_ = next_step;
    h_last_ = last_step;
    counts_ = counts;
    jacobian_valid_ = false;
    f0_valid_ = false;  // F(t, y) belongs to the state before the restore
  }
  long jacobianEvaluations() const { return jacobians_; }
  long factorizations() const { return factorizations_; }

  // Builds the banded finite-difference Jacobian at (t, y) (F(t, y) is
  // left in f0). Public for tests.
  void buildJacobian(OdeSystem& sys, double t, const Eigen::VectorXd& y);
  // Entry (i, j) of the last Jacobian (0 outside the band).
  double jacobian(int i, int j) const;

 private:
  void factor(double h);
  // One attempt of size h; returns the scaled error norm (<= 1 passes).
  double attempt(OdeSystem& sys, double t, const Eigen::VectorXd& y, double h);

  SolverParams p_;
  ChainStructure chain_;
  int half_band_;  // scalar half-bandwidth kl = ku of J
  double h_;
  double h_last_ = 0.0;
  StepCounts counts_;
  long jacobians_ = 0, factorizations_ = 0;

  Eigen::MatrixXd jband_;  // J in band layout: J(i, j) at row half_band_ + i - j
  int jacobian_size_ = 0;  // system size when J was built
  bool jacobian_valid_ = false;
  bool f0_valid_ = false;  // f0_ holds F(t, y) of the step about to start
  int jacobian_age_ = 0;
  double factored_h_ = -1.0;
  BandedLu lu_;
  Eigen::VectorXd f0_, f1_, ft_, err_, k1_, k2_, y_stage_, y_new_, y_pert_, f_pert_, delta_;
};

}  // namespace cws
