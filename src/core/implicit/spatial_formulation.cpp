#include "coil_winding_sim/core/implicit/spatial_formulation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "coil_winding_sim/core/assembly/force_effect.hpp"
#include "coil_winding_sim/core/constraints/frame_constraints.hpp"
#include "coil_winding_sim/core/implicit/newton_iteration.hpp"

namespace cws {

SpatialFormulation::SpatialFormulation(NewtonModelView& model, const SolverParams& solver)
    : model_(model),
      port_(model.newtonSetup().port),
      point_mass_(model.constants().point_mass),
      quat_mass_(4.0 * model.constants().point_inertia),
      segment_length_(model.constants().segment_length),
      newton_(NewtonSettings::of(solver)),
      carried_(model.core()) {
  const int cap = model.constants().capacity;
  for (ForceEffect* e : model.effectList()) effects_.push_back(e);
  for (EffectHistory* h : model.historyList()) histories_.push_back(h);
  // Constraint rows in the force rows' unit: the axial stiffness EA / l
  // [N/m] for a direction (the frames' and the port's).
  scale_direction_ = model.newtonSetup().elastic_rigidity / segment_length_;
  state_.p.setZero(3, cap);
  state_.v.setZero(3, cap);
  state_.q.setZero(4, cap);
  state_.qd.setZero(4, cap);
  state_.mu.setZero(3, cap);
  assembly_.resize(cap);
  couplings_.resize(SpatialAssembly::kPerPoint * std::min(cap, SpatialAssembly::kReservedSpan) + 2);
  x0_.setZero(7, cap);
  v0_.setZero(7, cap);
  x_hat_.setZero(7, cap);
  v_hat_.setZero(7, cap);
  x_try_.setZero(7, cap);
  mu_try_.setZero(3, cap);
  mu_accepted_.setZero(3, cap);
  radial_r_.setZero(cap);
  r_.setZero(SpatialAssembly::kPerPoint * std::min(cap, SpatialAssembly::kReservedSpan) + 2);
  dx_.setZero(SpatialAssembly::kPerPoint * std::min(cap, SpatialAssembly::kReservedSpan) + 2);
  secant_.reserve(SpatialAssembly::kPerPoint * std::min(cap, SpatialAssembly::kReservedSpan) + 2);
  weight_.setZero(SpatialAssembly::kPerPoint * std::min(cap, SpatialAssembly::kReservedSpan) + 2);
}

void SpatialFormulation::load(double t0) {
  const WireKinematics& k = model_.integratedKinematics();
  const WireConstants& c = model_.constants();
  state_.first = c.first;
  state_.n = c.n;
  state_.t = t0;
  // The integrated points and the boundary one before them; carried wire
  // is not read (WireModel::setCarriedDeferred).
  const int b = c.first - 1, m = c.n - b;
  x0_.block(0, b, 3, m) = k.p_world.middleCols(b, m);
  x0_.block(3, b, 4, m) = k.q.middleCols(b, m);
  v0_.block(0, b, 3, m) = k.v_world.middleCols(b, m);
  v0_.block(3, b, 4, m) = k.qd.middleCols(b, m);
  state_.p.middleCols(b, m) = k.p_world.middleCols(b, m);
  state_.q.middleCols(b, m) = k.q.middleCols(b, m);
  state_.v.middleCols(b, m) = k.v_world.middleCols(b, m);
  state_.qd.middleCols(b, m) = k.qd.middleCols(b, m);
  // Newton starts from the last accepted step's multipliers, also when a
  // failed solve is retried.
  state_.mu.middleCols(c.first, c.n - c.first) = mu_accepted_.middleCols(c.first, c.n - c.first);
  state_.lambda_port = lambda_accepted_;
  state_.carried = carried_.load(t0);
  placeBoundary(t0);
  for (EffectHistory* h : histories_) h->beginStep(NewtonView(state_));
}

void SpatialFormulation::placeBoundary(double t) {
  Eigen::Vector3d p, v;
  Eigen::Vector4d q, qd;
  model_.prescribedPose(t, p, v, q, qd);
  const int b = state_.first - 1;
  // On the core it moves as the scheme moves the core's material; its exact
  // rates are kept for the work booked.
  v_boundary_exact_ = v;
  qd_boundary_exact_ = qd;
  if (model_.prescribedOnCore()) {
    v = state_.carried.velocity(p);
    qd = state_.carried.quaternionRate(q, qd);
  }
  state_.p.col(b) = p;
  state_.v.col(b) = v;
  state_.q.col(b) = q;
  state_.qd.col(b) = qd;
}

void SpatialFormulation::updateRates() {
  const int f = state_.first, m = state_.n - f;
  state_.v.middleCols(f, m) = alpha_ * (state_.p.middleCols(f, m) - x_hat_.block(0, f, 3, m));
  state_.qd.middleCols(f, m) = alpha_ * (state_.q.middleCols(f, m) - x_hat_.block(3, f, 4, m));
}

const SpatialAssembly& SpatialFormulation::assemble(bool jacobian, int jacobian_top) {
  if (jacobian) have_factor_ = false;  // the matrix is overwritten
  assembly_.setFrames(state_.q, state_.first, state_.n);
  assembly_.begin(state_.first, state_.n, port_, jacobian, state_.alpha, jacobian_top);
  SpatialSink sink(state_, assembly_);
  for (const ForceEffect* e : effects_) e->addForces(sink);
  if (port_)
    addSpatialPortConstraint(state_, model_.portMotion(state_.t), scale_direction_, assembly_);
  addSpatialFrameConstraints(state_, scale_direction_, assembly_);
  assembly_.finish();
  return assembly_;
}

double SpatialFormulation::residual(bool jacobian, int top_point) {
  // A flag round's factorization keeps the factors of the rows past its
  // highest changed point where the last one was of this system: those rows
  // are not assembled.
  const bool partial = jacobian && top_point >= state_.first &&
                       factored_ == FactorKey{alpha_, state_.first, state_.n} &&
                       assembly_.matrix().keepsFactorsFrom(
                           top_point - state_.first,
                           SpatialAssembly::unknownsFor(state_.first, state_.n, port_), port_);
  assemble(jacobian, partial ? top_point : -1);
  const int f = state_.first, n = state_.n;
  const Eigen::VectorXd& force = assembly_.forces();
  const int unknowns = assembly_.unknowns();
  double norm = 0.0;
  // Inertia alpha M (v - v_hat) minus the forces; the constraint rows as
  // assembled. The norm weighs a quaternion row [N m] by 1 / l.
  for (int i = f; i < n; ++i) {
    const int mu = assembly_.muRow(i), p = assembly_.pRow(i), q = assembly_.qRow(i);
    r_.segment<2>(mu) = force.segment<2>(mu);
    r_.segment<3>(p) =
        alpha_ * point_mass_ * (state_.v.col(i) - v_hat_.block<3, 1>(0, i)) - force.segment<3>(p);
    // The frame's rows: the quaternion's inertia, projected on its tangent
    // space as the forces are (their radial part kept for the Jacobian).
    const Eigen::Vector4d inertia_q =
        alpha_ * quat_mass_ * (state_.qd.col(i) - v_hat_.block<4, 1>(3, i));
    r_.segment<3>(q) = assembly_.frameBasis(i).transpose() * inertia_q - force.segment<3>(q);
    radial_r_[i] = state_.q.col(i).dot(inertia_q) - assembly_.radialForce(i);
    norm = std::max({norm, r_.segment<3>(p).lpNorm<Eigen::Infinity>(),
                     r_.segment<2>(mu).lpNorm<Eigen::Infinity>(),
                     r_.segment<3>(q).lpNorm<Eigen::Infinity>() / segment_length_});
  }
  if (port_) {
    r_.segment<2>(unknowns - 2) = force.segment<2>(unknowns - 2);
    norm = std::max(norm, r_.segment<2>(unknowns - 2).lpNorm<Eigen::Infinity>());
  }
  if (jacobian) {
    SpatialAssembly::Matrix& m = assembly_.matrix();
    // Inertia; on a frame's rows B^T M B = M / 4 with B = dq/dtheta, and the
    // curvature of q(theta) against the residual's radial part: d^2 q /
    // dtheta^2 = -q / 4 (what the unit norm's multiplier gave before).
    const double mp = alpha_ * alpha_ * point_mass_, mq = 0.25 * alpha_ * alpha_ * quat_mass_;
    for (int i = f; i < std::min(n, assembly_.jacobianTop() + 1); ++i) {
      for (int a = 0; a < 3; ++a) m.at(assembly_.pRow(i) + a, assembly_.pRow(i) + a) += mp;
      const double dq = mq - 0.25 * radial_r_[i];
      for (int a = 0; a < 3; ++a) m.at(assembly_.qRow(i) + a, assembly_.qRow(i) + a) += dq;
    }
  }
  return norm;
}

NewtonStats SpatialFormulation::solve(const OneLegStep& step, const Eigen::MatrixXd& x_hat,
                                      const Eigen::MatrixXd& v_hat,
                                      const Eigen::MatrixXd& x_guess) {
  const int f = state_.first, n = state_.n, m = n - f;
  const double t1 = step.t1, alpha = step.alpha;
  state_.carried = carried_.trial(step);
  alpha_ = alpha;
  state_.alpha = alpha;
  state_.t = t1;
  state_.dt = t1 - step.t_past[0];
  x_hat_.middleCols(f, m) = x_hat.middleCols(f, m);
  v_hat_.middleCols(f, m) = v_hat.middleCols(f, m);
  placeBoundary(t1);
  state_.p.middleCols(f, m) = x_guess.block(0, f, 3, m);
  // (Newton moves a frame by rotations: it starts on the unit sphere.)
  for (int i = f; i < n; ++i) state_.q.col(i) = x_guess.block<4, 1>(3, i).normalized();
  updateRates();
  // The system's vectors cover the integrated span (grown as the
  // assembly's are: SpatialAssembly::kReservedSpan).
  const Eigen::Index rows = SpatialAssembly::kPerPoint * m + 2;
  if (rows > r_.size()) {
    const Eigen::Index grown = std::max<Eigen::Index>(rows, 2 * r_.size());
    r_.setZero(grown);
    dx_.setZero(grown);
    weight_.setZero(grown);
  }
  // (The port's multipliers, last, weigh nothing.)
  const double w_rotation = 0.25 * segment_length_ * segment_length_;
  for (int i = f; i < n; ++i) {
    const int row = SpatialAssembly::kPerPoint * (i - f);
    weight_.segment<SpatialAssembly::kPerPoint>(row).setZero();
    weight_.segment<3>(row + SpatialAssembly::kQ).setConstant(w_rotation);
    weight_.segment<3>(row + SpatialAssembly::kP).setConstant(1.0);
  }
  weight_.segment<2>(SpatialAssembly::kPerPoint * m).setZero();
  if (!(factored_ == FactorKey{alpha, f, n})) have_factor_ = false;
  return newtonSolve(*this, newton_, have_factor_);
}

// A Jacobian assembled only up to a point (residual's top_point) is
// factored only there: the later blocks keep the factors of the last
// factorization of this system, made at an earlier iterate (modified
// Newton).
bool SpatialFormulation::factor() {
  SpatialAssembly::Matrix& m = assembly_.matrix();
  const int top = assembly_.jacobianTop();
  const bool ok = top < state_.n - 1 ? m.factorFrom(top - state_.first) : m.factor();
  if (!ok || !couplings_.factor(assembly_)) return false;
  factored_ = {alpha_, state_.first, state_.n};
  return true;
}

double SpatialFormulation::direction() {
  const int unknowns = assembly_.unknowns();
  dx_.head(unknowns) = -r_.head(unknowns);
  assembly_.matrix().solve(dx_.head(unknowns));
  couplings_.correct(assembly_, dx_.head(unknowns));
  // The steps taken since the factorization update it (secant_steps.hpp);
  // where they do not contract, no step: a new factorization.
  if (!secant_.correct(dx_.head(unknowns), weight_)) return std::numeric_limits<double>::infinity();
  // The step's size in metres: positions, and quaternions times l.
  double step = 0.0;
  for (int i = state_.first; i < state_.n; ++i) {
    // (A rotation dtheta moves the quaternion by |dtheta| / 2.)
    step = std::max(
        {step, dx_.segment<3>(assembly_.pRow(i)).lpNorm<Eigen::Infinity>(),
         0.5 * segment_length_ * dx_.segment<3>(assembly_.qRow(i)).lpNorm<Eigen::Infinity>()});
  }
  return step;
}

void SpatialFormulation::keepStart() {
  const int f = state_.first, m = state_.n - f;
  x_try_.block(0, f, 3, m) = state_.p.middleCols(f, m);
  x_try_.block(3, f, 4, m) = state_.q.middleCols(f, m);
  mu_try_.middleCols(f, m) = state_.mu.middleCols(f, m);
  lambda_try_ = state_.lambda_port;
}

void SpatialFormulation::moveAlong(double s) {
  for (int i = state_.first; i < state_.n; ++i) {
    state_.mu.block<2, 1>(1, i) =
        mu_try_.block<2, 1>(1, i) + s * dx_.segment<2>(assembly_.muRow(i));
    state_.p.col(i) = x_try_.block<3, 1>(0, i) + s * dx_.segment<3>(assembly_.pRow(i));
    // Along the frame's tangent dq/dtheta, back onto the unit sphere.
    const quat::Vec4 q0 = x_try_.block<4, 1>(3, i);
    state_.q.col(i) =
        (q0 + (0.5 * s) * quat::gTransposeApply(q0, dx_.segment<3>(assembly_.qRow(i))))
            .normalized();
  }
  if (port_) state_.lambda_port = lambda_try_ + s * dx_.segment<2>(assembly_.portRow());
  updateRates();
}

int SpatialFormulation::changedTop() const { return state_.changed_top; }

bool SpatialFormulation::recheckFlags() {
  // The highest point any effect changed; an effect that changes a flag
  // without naming its point has the whole system factored again.
  bool changed = false;
  int top = -1;
  for (EffectHistory* h : histories_) {
    state_.changed_top = -1;
    if (!h->recheck(NewtonView(state_))) continue;
    changed = true;
    top = std::max(top, state_.changed_top >= 0 ? state_.changed_top : state_.n - 1);
  }
  state_.changed_top = top;
  return changed;
}

void SpatialFormulation::store(double h, Eigen::VectorXd& y) {
  const int f = state_.first, n = state_.n;
  // Bookkeeping with the converged solve's last evaluation (within
  // newton_tol of the end state: a last step below it is not evaluated
  // again).
  double work = assembly_.power_external, dissipated = assembly_.power_dissipated;
  for (int i = f; i < n; ++i) {
    work += assembly_.f_work.col(i).dot(state_.v.col(i)) +
            assembly_.fq_work.col(i).dot(state_.qd.col(i));
    dissipated -= assembly_.f_dissipative.col(i).dot(state_.v.col(i)) +
                  assembly_.fq_dissipative.col(i).dot(state_.qd.col(i));
  }
  // The clamp (or the carried wire) works on the integrated wire.
  work -= assembly_.boundary_force.dot(v_boundary_exact_) +
          assembly_.boundary_fq.dot(qd_boundary_exact_);
  // The step's work and dissipation [J]: h times its end powers.
  y[0] += h * work;
  y[1] += h * dissipated;
  for (int i = f; i < n; ++i) {
    const int o = model_.stateOffsetOf(i);
    y.segment<3>(o) = state_.p.col(i);
    y.segment<4>(o + 3) = state_.q.col(i);
    y.segment<3>(o + 7) = state_.v.col(i);
    y.segment<4>(o + 10) = state_.qd.col(i);
  }
  mu_accepted_.middleCols(f, n - f) = state_.mu.middleCols(f, n - f);
  lambda_accepted_ = state_.lambda_port;
  carried_.accept();
  model_.acceptNewtonFlags();
}

void SpatialFormulation::retireFront(int k) {
  // The frame constraints' accepted multipliers start the next solve, also
  // a new point's (what its column held). (Column by column from the
  // front: the ranges overlap.)
  const int cols = static_cast<int>(mu_accepted_.cols());
  for (int i = k; i < cols; ++i) mu_accepted_.col(i - k) = mu_accepted_.col(i);
  mu_accepted_.rightCols(std::min(k, cols)).setZero();
}

}  // namespace cws
