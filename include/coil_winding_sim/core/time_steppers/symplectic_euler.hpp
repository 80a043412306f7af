// Semi-implicit (symplectic) Euler with a fixed step: velocities from the
// accelerations at the start of the step, positions from the new velocities.
// One right-hand side per step, energy-stable for h below about 2 / omega_max
// (no error control: the step is solver.fixed_step). A state that stops
// being finite stops the run with a message naming the step.
#pragma once

#include "coil_winding_sim/core/time_steppers/time_stepper.hpp"

namespace cws {

class SymplecticEuler : public TimeStepper {
 public:
  SymplecticEuler(const SolverParams& p, int capacity);

  const char* name() const override { return "symplectic_euler"; }
  double collapseRatio() const override { return 0.0; }
  void step(OdeSystem& sys, double& t, Eigen::VectorXd& y, double t_limit) override;
  double nextStep() const override { return h_; }
  double lastStep() const override { return h_last_; }
  const StepCounts& counts() const override { return counts_; }
  void restore(double, double last_step, const StepCounts& counts) override {
    h_last_ = last_step;
    counts_ = counts;
  }

 private:
  double h_;
  double h_last_ = 0.0;
  StepCounts counts_;
  Eigen::VectorXd dydt_;
};

}  // namespace cws
