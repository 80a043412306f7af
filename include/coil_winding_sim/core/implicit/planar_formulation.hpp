// The planar wire in reduced coordinates, for implicit time steppers:
// positions alone (two per integrated point), frames tied to their segments,
// and, with a supply, the port constraint's multiplier. One step of any
// one-leg scheme
//   v = alpha (x - x_hat),   alpha M (v - v_hat) = F(x, v)
// (backward Euler: alpha = 1/h, x_hat = x_0, v_hat = v_0; BDF2 likewise with
// its own coefficients) is solved by Newton's method with a line search over
// a band system that every effect assembles (ForceEffect::addForces on a PlanarSink),
// factored in blocks of two points (PlanarAssembly::Matrix).
// The frames' rotational inertia enters with each frame's angle gradient
// taken at the step's start. Contact, stick and slip flags stay frozen
// within one Newton solve and are rechecked after it; the step is solved
// again with the new flags up to NewtonSettings::flag_rounds times.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <vector>

#include "coil_winding_sim/core/assembly/planar_assembly.hpp"
#include "coil_winding_sim/core/implicit/newton_formulation.hpp"
#include "coil_winding_sim/core/implicit/newton_iteration.hpp"
#include "coil_winding_sim/core/model/newton_model_view.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

class ForceEffect;
class EffectHistory;

class PlanarFormulation : public NewtonFormulation {
 public:
  PlanarFormulation(NewtonModelView& model, const SolverParams& solver);

  // x: plane coordinates (2 rows); v: their rates and the frame's angular
  // velocity (3 rows), for the steppers.
  int configRows() const override { return 2; }
  int rateRows() const override { return 3; }
  const Eigen::MatrixXd& committedX() const override { return x0_steps_; }
  const Eigen::MatrixXd& committedV() const override { return v0_steps_; }
  NewtonStats solve(const OneLegStep& step, const Eigen::MatrixXd& x_hat,
                    const Eigen::MatrixXd& v_hat, const Eigen::MatrixXd& x_guess) override;

  // Reads the committed state of the model at time t0 [s]: positions,
  // velocities and frame rates of the integrated points and the boundary.
  void load(double t0) override;
  int first() const override { return state_.first; }
  int n() const override { return state_.n; }
  const PlanarState& solution() const { return state_; }

  // Writes the solution into the model's state vector y (positions,
  // velocities, frames and their rates) and books the work and dissipation
  // of the step of h [s] from the converged solve's last evaluation (call
  // it right after solve()); the caller then accepts the step (acceptStep).
  void store(double h, Eigen::VectorXd& y) override;
  const CarriedRate& coreRate() const override { return state_.carried; }
  double largestMoveFrom(const Eigen::MatrixXd& x) const override {
    double most = 0.0;
    for (int i = state_.first; i < state_.n; ++i) {
      most = std::max(most, (state_.x.col(i) - x.block<2, 1>(0, i)).norm());
    }
    return most;
  }

  // The assembly at the present trial state (tests: Jacobians against
  // finite differences).
  PlanarState& trialState() { return state_; }
  const PlanarAssembly& assemble(bool jacobian);

 private:
  // Prescribed point first-1 and its frame at time t into state_.
  void placeBoundary(double t);
  // Residual r = inertia - F (force rows), the scaled constraint; its max
  // norm. With jacobian, the Newton matrix too (all of it: the plane's
  // system is factored whole, whatever point a flag round changed).
  double residual(bool jacobian, int top_point = -1);
  // Velocities of the integrated points from x: alpha (x - x_hat).
  void updateVelocities();
  // The Problem of newtonSolve (newton_iteration.hpp).
  template <class Problem>
  friend NewtonStats newtonSolve(Problem& p, const NewtonSettings& c, bool& have_factor);
  bool factor();
  double direction();
  void keepStart();
  void moveAlong(double s);
  // (No secant updates in the plane.)
  void forgetSteps() {}
  bool keepStep() { return true; }
  bool costlyFactor() const { return false; }
  bool recheckFlags();
  int changedTop() const;
  void returnMapping(bool on) { state_.return_mapping = on; }

  NewtonModelView& model_;
  std::vector<ForceEffect*> effects_;
  std::vector<EffectHistory*> histories_;
  bool multiplier_;    // a supply port constraint
  double port_scale_;  // its row's scale, EA / l [N/m]
  double point_mass_, point_inertia_;
  NewtonSettings newton_;
  Eigen::Vector3d p_boundary_world_, v_boundary_world_;
  PlanarState state_;
  PlanarAssembly assembly_;
  // Committed state and the present step's scheme data (capacity columns).
  Eigen::Matrix2Xd x0_, v0_, x_hat_, v_hat_, x_try_;
  Eigen::VectorXd omega0_, omega_hat_;
  // The same for the steppers: x0 (2 rows), v0 and omega0 (3 rows).
  Eigen::MatrixXd x0_steps_, v0_steps_;
  Eigen::Matrix2Xd frame_gradient_;  // d phi_i / d d_{i-1} at the step's start
  Eigen::VectorXd r_, dx_;
  double lambda_try_ = 0.0;
  double alpha_ = 0.0;
  // The scheme velocity of the core's material (the surface friction sees).
  CarriedMotion carried_;
  double lambda_accepted_ = 0.0;  // port multiplier of the last accepted step [N]
  // The factorization in the assembly's matrix, and what it was made for.
  bool have_factor_ = false;
  FactorKey factored_;
};

}  // namespace cws
