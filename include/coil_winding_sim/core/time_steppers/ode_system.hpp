// What a time stepper integrates: y' = F(t, y), with history state that is
// committed only on accepted steps.
#pragma once

#include <Eigen/Core>
#include <stdexcept>

namespace cws {

class OdeSystem {
 public:
  virtual ~OdeSystem() = default;
  virtual int size() const = 0;
  // dydt = F(t, y). Must not allocate and must not change history state.
  virtual void derivative(double t, const Eigen::VectorXd& y, Eigen::VectorXd& dydt) = 0;
  // Absolute tolerance per component (infinity: not error-controlled).
  virtual const Eigen::VectorXd& absoluteTolerance() const = 0;
  // Per component 1 where rtol applies, 0 where it does not (a coordinate
  // whose size depends on the choice of origin, such as a position).
  virtual const Eigen::VectorXd& relativeToleranceWeight() const = 0;
  // Called once per accepted step with the new time and state.
  virtual void acceptStep(double t, const Eigen::VectorXd& y) = 0;
};

// The step size fell below its floor, or the state stopped being finite.
class IntegrationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace cws
