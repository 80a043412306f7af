// Runge-Kutta-Fehlberg 4(5), the paper's integrator: six stages, the
// fifth-order solution is propagated (local extrapolation) and the
// difference to the fourth-order one estimates the local error.
#pragma once

#include "coil_winding_sim/core/time_steppers/time_stepper.hpp"

namespace cws {

class Rkf45 : public TimeStepper {
 public:
  // Buffers for up to `capacity` components (OdeSystem::capacity()).
  Rkf45(const SolverParams& p, int capacity);

  const char* name() const override { return "rkf45"; }
  // An explicit method steps near l / c; a hundred times below it, contact
  // or stick/slip switching holds it, and symplectic_euler is far faster.
  double collapseRatio() const override { return 1.0e-2; }
  void step(OdeSystem& sys, double& t, Eigen::VectorXd& y, double t_limit) override;
  double nextStep() const override { return h_; }
  double lastStep() const override { return h_last_; }
  const StepCounts& counts() const override { return counts_; }
  void restore(double next_step, double last_step, const StepCounts& counts) override {
    h_ = next_step;
    h_last_ = last_step;
    counts_ = counts;
  }

  // One attempt of size h from (t, y): fills the candidate state and returns
  // the scaled error norm (<= 1 passes). Changes nothing in `sys`.
  double attempt(OdeSystem& sys, double t, const Eigen::VectorXd& y, double h);
  const Eigen::VectorXd& candidate() const { return y_new_; }

 private:
  SolverParams p_;
  double h_;
  double h_last_ = 0.0;
  StepCounts counts_;
  Eigen::VectorXd k_[6];
  Eigen::VectorXd y_stage_, y_new_, err_;
};

}  // namespace cws
