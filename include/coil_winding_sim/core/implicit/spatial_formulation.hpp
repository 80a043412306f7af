// The 3-D wire for implicit time steppers: the explicit model's coordinates
// (positions and frame quaternions of the integrated points) with the frame
// constraints (4), (5) and the port constraint (22) held exactly by Lagrange
// multipliers at the step's end. One step of a one-leg scheme is solved by
// Newton's method with a line search over the banded system of
// SpatialAssembly; the quaternions' inertia is the explicit model's, 4 I per
// component. Contact, stick, slip and hysteresis-line flags stay frozen
// within one Newton solve and are rechecked after it, as in the planar
// formulation.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <vector>

#include "coil_winding_sim/core/assembly/spatial_assembly.hpp"
#include "coil_winding_sim/core/implicit/newton_formulation.hpp"
#include "coil_winding_sim/core/implicit/newton_iteration.hpp"
#include "coil_winding_sim/core/implicit/pair_coupling_solve.hpp"
#include "coil_winding_sim/core/implicit/secant_steps.hpp"
#include "coil_winding_sim/core/model/newton_model_view.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

class ForceEffect;
class EffectHistory;

class SpatialFormulation : public NewtonFormulation {
 public:
  SpatialFormulation(NewtonModelView& model, const SolverParams& solver);

  // x: p (rows 0-2), q (rows 3-6); v: their rates.
  int configRows() const override { return 7; }
  int rateRows() const override { return 7; }
  void load(double t0) override;
  int first() const override { return state_.first; }
  int n() const override { return state_.n; }
  const Eigen::MatrixXd& committedX() const override { return x0_; }
  const Eigen::MatrixXd& committedV() const override { return v0_; }
  NewtonStats solve(const OneLegStep& step, const Eigen::MatrixXd& x_hat,
                    const Eigen::MatrixXd& v_hat, const Eigen::MatrixXd& x_guess) override;
  void store(double h, Eigen::VectorXd& y) override;
  void retireFront(int k) override;
  const CarriedRate& coreRate() const override { return state_.carried; }
  double largestMoveFrom(const Eigen::MatrixXd& x) const override {
    double most = 0.0;
    for (int i = state_.first; i < state_.n; ++i) {
      most = std::max(most, (state_.p.col(i) - x.block<3, 1>(0, i)).norm());
    }
    return most;
  }

  // The trial state and its assembly (tests: Jacobians against finite
  // differences).
  SpatialState& trialState() { return state_; }
  const SpatialAssembly& assemble(bool jacobian, int jacobian_top = -1);

 private:
  void placeBoundary(double t);
  // The trial velocities and rates from the configuration: alpha (x - x_hat).
  void updateRates();
  // Residual r = inertia - F (force rows), the scaled constraints; its
  // weighted max norm [N]. With jacobian, the Newton matrix too; top_point
  // >= 0 (a flag round's highest changed point): only the rows of points
  // up to it, where the factorization can keep the later rows' factors.
  double residual(bool jacobian, int top_point = -1);
  // The Problem of newtonSolve (newton_iteration.hpp).
  template <class Problem>
  friend NewtonStats newtonSolve(Problem& p, const NewtonSettings& c, bool& have_factor);
  bool factor();
  double direction();
  void keepStart();
  void moveAlong(double s);
  void forgetSteps() { secant_.clear(); }
  bool keepStep() { return secant_.push(dx_.head(assembly_.unknowns()), weight_); }
  bool recheckFlags();
  int changedTop() const;
  void returnMapping(bool on) { state_.return_mapping = on; }
  // From kCostlyPairs pairs of free segments outside the band, a
  // factorization costs from a few times the band's alone (40 pairs: 3.5
  // times) to a hundred (256 pairs; bench_block_lu's pairCouplings).
  static constexpr int kCostlyPairs = 32;
  bool costlyFactor() const { return couplings_.pairs() >= kCostlyPairs; }

  NewtonModelView& model_;
  std::vector<ForceEffect*> effects_;
  std::vector<EffectHistory*> histories_;
  bool port_;                      // a supply port constraint
  double point_mass_, quat_mass_;  // [kg], 4 I [kg m^2]
  double segment_length_;
  double scale_direction_;    // the frame constraints' row scale [N/m]
  Eigen::VectorXd radial_r_;  // q_i . the residual's rows of q_i, unprojected
  NewtonSettings newton_;
  SpatialState state_;
  SpatialAssembly assembly_;
  PairCouplingSolve couplings_;  // the couplings outside the band
  // Committed state and the present step's scheme data (capacity columns).
  Eigen::MatrixXd x0_, v0_, x_hat_, v_hat_, x_try_;
  Eigen::Matrix3Xd mu_try_, mu_accepted_;
  Eigen::Vector2d lambda_accepted_ = Eigen::Vector2d::Zero(), lambda_try_ = Eigen::Vector2d::Zero();
  Eigen::VectorXd r_, dx_;
  // The steps taken with the present factorization (secant updates), and
  // their inner product's weight per unknown: 1 for a position [m],
  // (l / 2)^2 for a rotation [rad] (the step's measure), 0 for a multiplier.
  SecantSteps secant_;
  Eigen::VectorXd weight_;
  double alpha_ = 0.0;
  // The scheme velocity of the core's material (the surface friction sees),
  // and the prescribed point's exact rates.
  CarriedMotion carried_;
  Eigen::Vector3d v_boundary_exact_ = Eigen::Vector3d::Zero();
  Eigen::Vector4d qd_boundary_exact_ = Eigen::Vector4d::Zero();
  // The factorization in the assembly's matrix, and what it was made for.
  bool have_factor_ = false;
  FactorKey factored_;
};

}  // namespace cws
