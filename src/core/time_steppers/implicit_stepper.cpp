#include "coil_winding_sim/core/time_steppers/implicit_stepper.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "coil_winding_sim/core/implicit/newton_formulations.hpp"
#include "coil_winding_sim/core/time_steppers/symplectic_euler.hpp"

namespace cws {

ImplicitStepper::ImplicitStepper(const SolverParams& p, OdeSystem& sys, Scheme scheme)
    : p_(p), scheme_(scheme), h_(kStartFraction * p.implicit_step), longest_(p.implicit_step) {
  // The explicit fallback steps at the resolved safe step (Simulation
  // resolves solver.fixed_step: auto).
  if (p.fixed_step && *p.fixed_step > 0.0)
    explicit_ = std::make_unique<SymplecticEuler>(p, sys.capacity());
  retired_seen_ = sys.pointsRetired();
  NewtonModelView* model = model_ = sys.newtonModel();
  if (!model)
    throw std::invalid_argument(std::string(name()) + ": the system has no Newton formulation");
  formulation_ = makeNewtonFormulation(*model, p);
  const NewtonFormulation* f = formulation_.get();
  const int cap = sys.capacity();  // more than enough columns
  const int points = (cap - 2) / 14 + 1;
  const int xr = f->configRows(), vr = f->rateRows();
  x_prev_.setZero(xr, points);
  v_prev_.setZero(vr, points);
  x_hat_.setZero(xr, points);
  v_hat_.setZero(vr, points);
  guess_.setZero(xr, points);
}

void ImplicitStepper::restore(double next_step, double last_step, const StepCounts& counts) {
  h_ = next_step;
  h_last_ = last_step;
  counts_ = counts;
  have_prev_ = false;  // a continued run restarts BDF2 with one Euler step
  retired_seen_ = -1;
  fallback_until_ = -1.0;
  strike_until_ = -1.0;
}

void ImplicitStepper::beginFallback(double t, double h, bool converged) {
  fallback_until_ = t + kFallbackStretch;
  ++newton_.fallback_stretches;
  // (Formatted into a fixed buffer: a step allocates nothing.)
  std::snprintf(newton_.fallback_cause, sizeof newton_.fallback_cause,
                converged
                    ? "the step's solution left its predictor at a step of %.3g s at t = %.6g s"
                    : "Newton did not converge at a step of %.3g s at t = %.6g s",
                h, t);
}

void ImplicitStepper::explicitStep(OdeSystem& sys, double& t, Eigen::VectorXd& y, double t_limit) {
  const long before = explicit_->counts().accepted;
  explicit_->step(sys, t, y, std::min(t_limit, fallback_until_));
  const long taken = explicit_->counts().accepted - before;
  counts_.accepted += taken;
  newton_.fallback_steps += taken;
  h_last_ = explicit_->lastStep();
  // The stretch is over: Newton steps again, from small ones and backward
  // Euler (the explicit steps leave BDF2 no past).
  if (t >= fallback_until_) {
    fallback_until_ = -1.0;
    have_prev_ = false;
    h_ = kStartFraction * longest_;
  }
}

void ImplicitStepper::retirePast(int k) {
  formulation_->retireFront(k);
  if (!have_prev_ || k <= 0 || k >= first_prev_) {
    have_prev_ = false;
    return;
  }
  // (Column by column from the front: the ranges overlap.)
  for (int i = first_prev_; i < n_prev_; ++i) {
    x_prev_.col(i - k) = x_prev_.col(i);
    v_prev_.col(i - k) = v_prev_.col(i);
  }
  first_prev_ -= k;
  n_prev_ -= k;
}

void ImplicitStepper::kink() {
  h_ = std::min(h_, kStartFraction * longest_);
  have_prev_ = false;
  kinked_ = true;
}

void ImplicitStepper::limitStep(double longest) {
  longest_ = std::min(p_.implicit_step, longest);
  // A run, and the step after a kink, start with a fraction of the step the
  // process asks for now (after a new speed setpoint: the new speed's).
  if (counts_.accepted == 0) h_ = kStartFraction * longest_;
  if (kinked_) h_ = std::min(h_, kStartFraction * longest_);
  kinked_ = false;
  h_ = std::min(h_, longest_);
}

void ImplicitStepper::step(OdeSystem& sys, double& t, Eigen::VectorXd& y, double t_limit) {
  // A limit within rounding of t is reached as it is. A step of that size
  // would turn Newton's position tolerance into velocities of tol / h
  // (docs/MODEL.md, "Steps that land on a time limit").
  if (t_limit - t <= kLandRounding * std::max(1.0, std::abs(t))) {
    t = t_limit;
    return;
  }
  // Buried wire retired at the last accepted step (WireModel::
  // retireBuriedWire): the past moves with the live arrays.
  const long retired = sys.pointsRetired();
  if (retired != retired_seen_) {
    if (retired_seen_ >= 0) retirePast(static_cast<int>(retired - retired_seen_));
    retired_seen_ = retired;
  }
  // A stretch of explicit steps under way (the fallback below).
  if (t < fallback_until_) {
    explicitStep(sys, t, y, t_limit);
    return;
  }
  NewtonFormulation& f = *formulation_;
  f.load(t);
  const int first = f.first(), n = f.n(), m = n - first;
  const int xr = f.configRows();
  // Points the core released since the last step have no past here (only
  // integrated points are loaded): restart with an Euler step.
  if (first < first_prev_) have_prev_ = false;
  const Eigen::MatrixXd& x0 = f.committedX();
  const Eigen::MatrixXd& v0 = f.committedV();
  for (;;) {
    // Within a struck span's window the steps stay short.
    if (t < strike_until_) h_ = std::min(h_, p_.strike_step);
    // No sliver before the limit: a remainder of at most kLandStretch more
    // than the step is one step onto the limit, one of less than two steps
    // is split into two equal ones.
    const double rest = t_limit - t;
    const bool clipped = rest <= (1.0 + kLandStretch) * h_;
    const double h = clipped ? rest : (rest < 2.0 * h_ ? 0.5 * rest : h_);
    // BDF2 over the last two steps (variable-step coefficients, ratio r =
    // h / h_prev); backward Euler for the first step, after a retry, and
    // where the step grows more than twofold (variable-step BDF2 is
    // zero-stable only for r < 1 + sqrt(2): after a step clipped at a ramp's
    // end, r can reach 1e5).
    const bool restart = !have_prev_;
    const bool bdf2 = scheme_ == Scheme::kBdf2 && have_prev_ && h <= 2.0 * h_prev_;
    // Points drawn in since the last step have no past: extrapolate back.
    if (have_prev_) {
      for (int i = n_prev_; i < n; ++i) {
        x_prev_.col(i) = x0.col(i) - h_prev_ * v0.col(i).head(xr);
        v_prev_.col(i) = v0.col(i);
      }
    }
    double alpha = 1.0 / h;
    OneLegStep step;
    step.t1 = t + h;
    step.t_past[0] = t;
    if (bdf2) {
      const double r = h / h_prev_;
      const double c0 = (1.0 + r) * (1.0 + r) / (1.0 + 2.0 * r), c1 = r * r / (1.0 + 2.0 * r);
      alpha = (1.0 + 2.0 * r) / ((1.0 + r) * h);
      step.past = 2;
      step.w_past[0] = c0;
      step.w_past[1] = -c1;
      step.t_past[1] = t_prev_;
      x_hat_.middleCols(first, m) =
          c0 * x0.middleCols(first, m) - c1 * x_prev_.middleCols(first, m);
      v_hat_.middleCols(first, m) =
          c0 * v0.middleCols(first, m) - c1 * v_prev_.middleCols(first, m);
    } else {
      x_hat_.middleCols(first, m) = x0.middleCols(first, m);
      v_hat_.middleCols(first, m) = v0.middleCols(first, m);
    }
    // Newton starts from the predictor x0 + h v0 + h^2 / 2 a0, with a0 the
    // last step's mean acceleration (where there is one): 11 % fewer
    // iterations on the 3-D spiral than from x0 + h v0
    // (docs/history/2026-11-24-3d-real-time-and-stick-spring-ringing.md).
    guess_.middleCols(first, m) = x0.middleCols(first, m) + h * v0.block(0, first, xr, m);
    if (have_prev_) {
      guess_.middleCols(first, m) +=
          (0.5 * h * h / h_prev_) * (v0.block(0, first, xr, m) - v_prev_.block(0, first, xr, m));
    }
    step.alpha = alpha;
    const NewtonStats st = f.solve(step, x_hat_, v_hat_, guess_);
    newton_.iterations += st.iterations;
    newton_.flag_rounds += st.flag_rounds;
    newton_.line_searches += st.line_searches;
    newton_.factorizations += st.factorizations;
    if (st.return_mapped) ++newton_.return_mapped_solves;
    // A solution farther from the predictor than kPredictorTol: the
    // step is too long for what happens within it (the distance estimates
    // its local error, as variable-step BDF codes take it). Frozen flags
    // that still change after the last round say the same.
    const bool accurate = st.converged && f.largestMoveFrom(guess_) <= kPredictorTol;
    if (st.converged && !accurate) ++newton_.predictor_retries;
    if (!accurate) {
      ++counts_.rejected;
      ++newton_.retried_steps;
      h_ = 0.25 * h;
      have_prev_ = false;
      // Below the smallest step: a stretch of explicit steps carries the
      // run past what Newton cannot follow. (Not sooner: on a violent
      // moment of a wound coil, Newton steps far below the explicit safe
      // step went on where the explicit steps diverged; docs/history.)
      if (explicit_ && h_ < p_.min_step) {
        beginFallback(t, h, st.converged);
        explicitStep(sys, t, y, t_limit);
        return;
      }
      if (h_ < p_.min_step) {
        std::ostringstream msg;
        if (st.converged) {
          msg << "the step's solution lay farther than " << kPredictorTol
              << " m from its predictor at t = " << t << " s even at a step of " << h << " s with "
              << name()
              << ": the scene is beyond what the implicit step can follow; use rkf45 or "
                 "symplectic_euler, or lower solver.min_step";
        } else {
          msg << "Newton's method did not converge at t = " << t << " s even at a step of " << h
              << " s with " << name()
              << ": the scene is beyond what the implicit step can follow; use rkf45 or "
                 "symplectic_euler, or raise solver.newton_max_iterations";
        }
        throw IntegrationError(msg.str());
      }
      // Back to the committed flags for the smaller step.
      f.load(t);
      continue;
    }
    // The core struck the free span within this step: it is redone in
    // steps of an eighth, down to strike_step, so that one of those takes
    // the landing; then the window of strike steps begins (a landing within
    // the window changes nothing). A landing that moves the span's points
    // at the core's speed is a wave along the wire faster than any longer
    // step follows (docs/MODEL.md, "Steps through a struck span").
    bool struck = false;
    if (p_.strike_step > 0.0 && t + h > strike_until_) {
      struck = model_->spanLandingSpeed(kStrikeGap) >= kStrikeSpeed;
      if (struck && h > (1.0 + kLandStretch) * p_.strike_step) {
        ++counts_.rejected;
        h_ = std::max(p_.strike_step, 0.125 * h);
        have_prev_ = false;
        f.load(t);
        continue;
      }
    }
    // Keep this step's start as the past of the next one (the integrated
    // points; a point the core releases restarts the method above).
    x_prev_.middleCols(first, m) = x0.middleCols(first, m);
    v_prev_.middleCols(first, m) = v0.middleCols(first, m);
    n_prev_ = n;
    first_prev_ = first;
    h_prev_ = h;
    t_prev_ = t;
    have_prev_ = true;
    f.store(h, y);
    // The core's work on the carried wire, which no Newton unknown sees.
    y[0] += model_->carriedEnergyChange(t, clipped ? t_limit : t + h);
    // The commit compares the wire's velocities with the core material's
    // by this step's scheme (CarriedWire::decide), except on a step
    // that restarts the method, whose start velocities are not the scheme's.
    if (!restart) model_->acceptCoreVelocity(f.coreRate().g_world, f.coreRate().origin_world);
    ++counts_.accepted;
    t = clipped ? t_limit : t + h;
    h_last_ = h;
    if (struck) {
      strike_until_ = t + kStrikeWindow;
      ++newton_.strike_windows;
    }
    sys.acceptStep(t, y);
    // Grow back towards the scene's step after a retry.
    if (!clipped) h_ = std::min(longest_, 2.0 * h_);
    return;
  }
}

}  // namespace cws
