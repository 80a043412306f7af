// What a time stepper integrates: y' = F(t, y), with history state that is
// committed only on accepted steps.
//
// The state may grow between steps (a wire supply adds mass points): vectors
// are allocated once for capacity() components and the system uses the
// first size() of them. A stepper works on heads of its buffers and so
// allocates nothing when the system grows.
#pragma once

#include <Eigen/Core>
#include <stdexcept>

namespace cws {

class NewtonModelView;

// Sparsity of a chain: `lead` leading components that nothing depends on
// (integrated quantities such as work done), then blocks of `block`
// components, one per mass point; a block's rates depend on the blocks
// within `radius` of it (and, more weakly, on farther ones through a
// constraint solve). block == 0: no such structure.
struct ChainStructure {
  int lead = 0;
  int block = 0;
  int radius = 0;
};

class OdeSystem {
 public:
  using ConstRef = Eigen::Ref<const Eigen::VectorXd>;
  using Ref = Eigen::Ref<Eigen::VectorXd>;

  virtual ~OdeSystem() = default;
  // Components in use now, and the most there will ever be.
  virtual int size() const = 0;
  virtual int capacity() const = 0;
  // dydt = F(t, y) on the first size() components. Must not allocate and
  // must not change history state.
  virtual void derivative(double t, ConstRef y, Ref dydt) = 0;
  // Absolute tolerance per component (infinity: not error-controlled), and
  // 1 where rtol applies, 0 where it does not (a coordinate whose size
  // depends on the choice of origin, such as a position); capacity() long.
  virtual const Eigen::VectorXd& absoluteTolerance() const = 0;
  virtual const Eigen::VectorXd& relativeToleranceWeight() const = 0;
  // Semi-implicit (symplectic) Euler update for a second-order system:
  // velocities += h * their rates in dydt, then positions += h * the new
  // velocities, other components += h * rates. False if the system is not
  // second order (the default).
  virtual bool semiImplicitUpdate(double /*h*/, ConstRef /*dydt*/, Ref /*y*/) const {
    return false;
  }
  // What an implicit stepper's Newton formulation reads of the system
  // (model/newton_model_view.hpp); null when it offers none.
  virtual NewtonModelView* newtonModel() { return nullptr; }
  // Sparsity for integrators that build a banded Jacobian.
  virtual ChainStructure chainStructure() const { return {}; }
  // Called once per accepted step with the new time and state (capacity()
  // long). The system may grow here, writing its new components into y.
  virtual void acceptStep(double t, Eigen::VectorXd& y) = 0;
  // Points dropped from the front of the state since the start (a model
  // that retires buried wire, WireModel::retireBuriedWire): a stepper that
  // keeps a past per point moves it by the change.
  virtual long pointsRetired() const { return 0; }
};

// The step size fell below its floor, or the state stopped being finite.
class IntegrationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace cws
