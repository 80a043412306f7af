#include "coil_winding_sim/core/implicit/planar_formulation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "coil_winding_sim/core/assembly/force_effect.hpp"
#include "coil_winding_sim/core/base/quaternion.hpp"
#include "coil_winding_sim/core/implicit/newton_iteration.hpp"

namespace cws {

namespace {
// Quaternion (scalar first) of a turn by angle [rad] about the unit world
// axis n, applied on the left (a world rotation).
quat::Vec4 turnAbout(const Eigen::Vector3d& n, double angle, const quat::Vec4& q) {
  const Eigen::Quaterniond r(Eigen::AngleAxisd(angle, n));
  const Eigen::Quaterniond out = r * Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
  return {out.w(), out.x(), out.y(), out.z()};
}
// The same turn, by the angle from plane direction a to plane direction b,
// from their dot and cross products: cos(angle / 2) = sqrt((1 + c) / 2).
// (A step turns a frame by far less than a half turn; near one, the angle
// is taken by atan2.)
quat::Vec4 turnOnto(const Eigen::Vector3d& n, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                    const quat::Vec4& q) {
  const double norms = std::sqrt(a.squaredNorm() * b.squaredNorm());
  const double c = a.dot(b) / norms, sn = planar::cross(a, b) / norms;
  if (c < -0.5) return turnAbout(n, planar::turn(a, b), q);
  const double cos_half = std::sqrt(0.5 * (1.0 + c)), sin_half = 0.5 * sn / cos_half;
  const Eigen::Quaterniond r(cos_half, sin_half * n.x(), sin_half * n.y(), sin_half * n.z());
  const Eigen::Quaterniond out = r * Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
  return {out.w(), out.x(), out.y(), out.z()};
}
}  // namespace

PlanarFormulation::PlanarFormulation(NewtonModelView& model, const SolverParams& solver)
    : model_(model),
      multiplier_(model.newtonSetup().port),
      port_scale_(model.newtonSetup().elastic_rigidity / model.constants().segment_length),
      point_mass_(model.constants().point_mass),
      point_inertia_(model.constants().point_inertia),
      newton_(NewtonSettings::of(solver)),
      carried_(model.core()) {
  const int cap = model.constants().capacity;
  for (ForceEffect* e : model.effectList()) effects_.push_back(e);
  for (EffectHistory* h : model.historyList()) histories_.push_back(h);
  const WireKinematics& k = model.integratedKinematics();
  state_.plane = PlaneBasis::through(k.p_world.col(0), model.newtonSetup().core_axis_world);
  // The plane normal in the material axes: the same in every frame.
  const quat::Vec4 q0 = k.q.col(0);
  const Eigen::Vector3d n = state_.plane.n_world;
  state_.n_material = {quat::xi(q0).dot(n), quat::eta(q0).dot(n), quat::zeta(q0).dot(n)};
  state_.x.setZero(2, cap);
  state_.v.setZero(2, cap);
  assembly_.resize(cap);
  x0_.setZero(2, cap);
  v0_.setZero(2, cap);
  x_hat_.setZero(2, cap);
  v_hat_.setZero(2, cap);
  x_try_.setZero(2, cap);
  omega0_.setZero(cap);
  omega_hat_.setZero(cap);
  x0_steps_.setZero(2, cap);
  v0_steps_.setZero(3, cap);
  frame_gradient_.setZero(2, cap);
  r_.setZero(2 * cap + 1);
  dx_.setZero(2 * cap + 1);
}

void PlanarFormulation::load(double t0) {
  const WireKinematics& k = model_.integratedKinematics();
  const WireConstants& c = model_.constants();
  state_.first = c.first;
  state_.n = c.n;
  state_.t = t0;
  // The integrated points and the boundary one before them; carried wire
  // is not read (WireModel::setCarriedDeferred).
  const int b = c.first - 1, m = c.n - b;
  for (int i = b; i < c.n; ++i) {
    x0_.col(i) = state_.plane.toPlane(k.p_world.col(i));
    v0_.col(i) = state_.plane.vectorToPlane(k.v_world.col(i));
  }
  // Frame i turns with segment i-1.
  for (int i = c.first; i < c.n; ++i) {
    const Eigen::Vector2d d = x0_.col(i) - x0_.col(i - 1);
    frame_gradient_.col(i) = planar::angleGradient(d);
    omega0_[i] = frame_gradient_.col(i).dot(v0_.col(i) - v0_.col(i - 1));
  }
  state_.x.middleCols(b, m) = x0_.middleCols(b, m);
  state_.v.middleCols(b, m) = v0_.middleCols(b, m);
  x0_steps_.middleCols(b, m) = x0_.middleCols(b, m);
  v0_steps_.block(0, b, 2, m) = v0_.middleCols(b, m);
  v0_steps_.block(2, b, 1, m) = omega0_.segment(b, m).transpose();
  // Newton starts from the last accepted step's port multiplier, also when
  // a failed solve is retried (its multiplier may be far off).
  state_.lambda_port = lambda_accepted_;
  state_.carried = carried_.load(t0);
  placeBoundary(t0);
  for (EffectHistory* h : histories_) h->beginStep(NewtonView(state_));
}

void PlanarFormulation::placeBoundary(double t) {
  Eigen::Vector4d q, qd;
  model_.prescribedPose(t, p_boundary_world_, v_boundary_world_, q, qd);
  const int b = state_.first - 1;
  // On the core it moves as the scheme moves the core's material; its exact
  // velocity is kept for the work booked.
  const Eigen::Vector3d v_world =
      model_.prescribedOnCore() ? state_.carried.velocity(p_boundary_world_) : v_boundary_world_;
  state_.x.col(b) = state_.plane.toPlane(p_boundary_world_);
  state_.v.col(b) = state_.plane.vectorToPlane(v_world);
  state_.boundary_tangent = state_.plane.vectorToPlane(quat::zeta(q)).normalized();
  // omega_world = 2 E(q) qdot, about n.
  state_.boundary_omega = 2.0 * (quat::E(q) * qd).dot(state_.plane.n_world);
}

void PlanarFormulation::updateVelocities() {
  const int f = state_.first, m = state_.n - f;
  state_.v.middleCols(f, m) = alpha_ * (state_.x.middleCols(f, m) - x_hat_.middleCols(f, m));
}

const PlanarAssembly& PlanarFormulation::assemble(bool jacobian) {
  if (jacobian) have_factor_ = false;  // the matrix is overwritten
  assembly_.begin(state_.first, state_.n, multiplier_, jacobian, state_.alpha);
  PlanarSink sink(state_, assembly_);
  for (const ForceEffect* e : effects_) e->addForces(sink);
  if (multiplier_) {
    addPlanarPortConstraint(state_, model_.portMotion(state_.t), port_scale_, assembly_);
  }
  return assembly_;
}

double PlanarFormulation::residual(bool jacobian, int /*top_point*/) {
  assemble(jacobian);
  const int f = state_.first, n = state_.n;
  const double a = alpha_;
  const Eigen::VectorXd& force = assembly_.forces();
  const int unknowns = assembly_.unknowns();
  // Point inertia M a = alpha M (v - v_hat), minus the forces.
  for (int i = f; i < n; ++i) {
    const int o = assembly_.dof(i);
    r_.segment<2>(o) = a * point_mass_ * (state_.v.col(i) - v_hat_.col(i)) - force.segment<2>(o);
  }
  if (multiplier_) r_[unknowns - 1] = force[unknowns - 1];
  // Frame inertia: I alpha (omega - omega_hat) g on both points of the
  // segment, omega = g . (v_i - v_{i-1}) with g from the step's start.
  for (int i = f; i < n; ++i) {
    const Eigen::Vector2d g = frame_gradient_.col(i);
    const double omega = g.dot(state_.v.col(i) - state_.v.col(i - 1));
    const Eigen::Vector2d fi = point_inertia_ * a * (omega - omega_hat_[i]) * g;
    r_.segment<2>(assembly_.dof(i)) += fi;
    if (i - 1 >= f) r_.segment<2>(assembly_.dof(i - 1)) -= fi;
  }
  if (jacobian) {
    PlanarAssembly::Matrix& m = assembly_.matrix();
    const double mass = a * alpha_ * point_mass_;
    for (int r = 0; r < 2 * (n - f); ++r) m.at(r, r) += mass;
    for (int i = f; i < n; ++i) {
      const Eigen::Vector2d g = frame_gradient_.col(i);
      const Eigen::Matrix2d b = point_inertia_ * a * alpha_ * g * g.transpose();
      const int oi = assembly_.dof(i);
      for (int p = 0; p < 2; ++p) {
        for (int q = 0; q < 2; ++q) {
          m.at(oi + p, oi + q) += b(p, q);
          if (i - 1 < f) continue;
          const int oj = assembly_.dof(i - 1);
          m.at(oj + p, oj + q) += b(p, q);
          m.at(oi + p, oj + q) -= b(p, q);
          m.at(oj + p, oi + q) -= b(p, q);
        }
      }
    }
  }
  return r_.head(unknowns).lpNorm<Eigen::Infinity>();
}

NewtonStats PlanarFormulation::solve(const OneLegStep& step, const Eigen::MatrixXd& x_hat,
                                     const Eigen::MatrixXd& v_hat, const Eigen::MatrixXd& x_guess) {
  const int f = state_.first, n = state_.n, m = n - f;
  const double t1 = step.t1, alpha = step.alpha;
  state_.carried = carried_.trial(step);
  alpha_ = alpha;
  state_.alpha = alpha;
  state_.t = t1;
  state_.dt = t1 - step.t_past[0];
  // The steppers' rates: the plane velocities, then the frames' angular ones.
  x_hat_.middleCols(f, m) = x_hat.middleCols(f, m);
  v_hat_.middleCols(f, m) = v_hat.block(0, f, 2, m);
  omega_hat_.segment(f, m) = v_hat.block(2, f, 1, m).transpose();
  placeBoundary(t1);
  state_.x.middleCols(f, m) = x_guess.middleCols(f, m);
  updateVelocities();
  if (!(factored_ == FactorKey{alpha, f, n})) have_factor_ = false;
  return newtonSolve(*this, newton_, have_factor_);
}

// (The planar system is factored whole after a flag change.)
int PlanarFormulation::changedTop() const { return -1; }

bool PlanarFormulation::factor() {
  if (!assembly_.matrix().factor()) return false;
  factored_ = {alpha_, state_.first, state_.n};
  return true;
}

double PlanarFormulation::direction() {
  const int unknowns = assembly_.unknowns();
  dx_.head(unknowns) = -r_.head(unknowns);
  assembly_.matrix().solve(dx_.head(unknowns));
  return dx_.head(2 * (state_.n - state_.first)).lpNorm<Eigen::Infinity>();
}

void PlanarFormulation::keepStart() {
  const int f = state_.first, m = state_.n - f;
  x_try_.middleCols(f, m) = state_.x.middleCols(f, m);
  lambda_try_ = state_.lambda_port;
}

void PlanarFormulation::moveAlong(double s) {
  for (int i = state_.first; i < state_.n; ++i) {
    state_.x.col(i) = x_try_.col(i) + s * dx_.segment<2>(assembly_.dof(i));
  }
  if (multiplier_) state_.lambda_port = lambda_try_ + s * dx_[assembly_.unknowns() - 1];
  updateVelocities();
}

bool PlanarFormulation::recheckFlags() {
  bool changed = false;
  for (EffectHistory* h : histories_) changed = h->recheck(NewtonView(state_)) || changed;
  return changed;
}

void PlanarFormulation::store(double h, Eigen::VectorXd& y) {
  const WireKinematics& k = model_.integratedKinematics();
  const PlaneBasis& pl = state_.plane;
  const int f = state_.first, n = state_.n;
  // Bookkeeping with a converged solve's last evaluation: within newton_tol
  // of the end state (a last step below it is not evaluated again), with
  // the flags it kept, so its forces and powers are at hand.
  double work = assembly_.power_external, dissipated = assembly_.power_dissipated;
  for (int i = f; i < n; ++i) {
    work += assembly_.f_work.col(i).dot(state_.v.col(i));
    dissipated -= assembly_.f_dissipative.col(i).dot(state_.v.col(i));
  }
  // The clamp (or the carried wire) works on the integrated wire.
  work -= assembly_.boundary_force.dot(state_.plane.vectorToPlane(v_boundary_world_)) +
          assembly_.boundary_torque * state_.boundary_omega;
  // The step's work and dissipation [J]: h times its end powers.
  y[0] += h * work;
  y[1] += h * dissipated;
  for (int i = f; i < n; ++i) {
    const int o = model_.stateOffsetOf(i);
    y.segment<3>(o) = pl.toWorld(state_.x.col(i));
    y.segment<3>(o + 7) = pl.vectorToWorld(state_.v.col(i));
    // Frame i: the committed frame turned about n onto segment i-1.
    const Eigen::Vector2d d = state_.segment(i - 1);
    const quat::Vec4 q_old = k.q.col(i);
    const Eigen::Vector2d zeta_old = pl.vectorToPlane(quat::zeta(q_old));
    const quat::Vec4 q = turnOnto(pl.n_world, zeta_old, d, q_old);
    const double omega = planar::cross(d, state_.v.col(i) - state_.v.col(i - 1)) / d.squaredNorm();
    y.segment<4>(o + 3) = q;
    y.segment<4>(o + 10) = 0.5 * quat::E(q).transpose() * (omega * pl.n_world);
  }
  lambda_accepted_ = state_.lambda_port;
  carried_.accept();
  model_.acceptNewtonFlags();
}

}  // namespace cws
