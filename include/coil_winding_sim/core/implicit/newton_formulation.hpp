// What an implicit time stepper (ImplicitStepper) needs of a formulation of
// the wire: the committed configuration and velocities of the integrated
// points, one Newton solve of a one-leg scheme
//   v = alpha (x - x_hat),   alpha M (v - v_hat) = F(x, v)
// and the solution written back into the model's state. The planar
// formulation (positions in the plane) and the 3-D one (positions and
// quaternions with the frame constraints) implement it.
#pragma once

#include <Eigen/Core>

#include "coil_winding_sim/core/assembly/one_leg_step.hpp"

namespace cws {

struct NewtonStats {
  bool converged = false;
  int iterations = 0;   // Newton iterations, all flag rounds
  int flag_rounds = 0;  // solves repeated after a flag changed
  int line_searches = 0;
  int factorizations = 0;
  bool return_mapped = false;  // the solve reached solver.return_mapping_round
};

class NewtonFormulation {
 public:
  virtual ~NewtonFormulation() = default;
  // Rows per point of the configuration x and of the rates v; the first
  // configRows() rates are the configuration's time derivatives (the rest,
  // if any, are rates the scheme combines alike, e.g. a planar frame's
  // angular velocity).
  virtual int configRows() const = 0;
  virtual int rateRows() const = 0;
  // Reads the committed state of the model at time t0 [s].
  virtual void load(double t0) = 0;
  virtual int first() const = 0;  // integrated points first..n-1
  virtual int n() const = 0;
  // The committed configuration and rates (capacity columns).
  virtual const Eigen::MatrixXd& committedX() const = 0;
  virtual const Eigen::MatrixXd& committedV() const = 0;
  // Solves the step `step` with the scheme's x_hat, v_hat (columns
  // first..n-1), from x_guess.
  virtual NewtonStats solve(const OneLegStep& step, const Eigen::MatrixXd& x_hat,
                            const Eigen::MatrixXd& v_hat, const Eigen::MatrixXd& x_guess) = 0;
  // The largest distance of an integrated point's solution from its
  // position in x (columns first..n-1) [m], right after solve().
  virtual double largestMoveFrom(const Eigen::MatrixXd& x) const = 0;
  // Writes the solution into the model's state vector y and books the work
  // and dissipation of the step of h [s] (right after solve()).
  virtual void store(double h, Eigen::VectorXd& y) = 0;
  // The velocity of the core's material by the scheme of the last solve.
  virtual const CarriedRate& coreRate() const = 0;
  // Points 0..k-1 left the model's live arrays (WireModel::
  // retireBuriedWire): what the formulation keeps per point from one step
  // to the next moves k points to the front.
  virtual void retireFront(int /*k*/) {}
};

}  // namespace cws
