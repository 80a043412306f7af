#include "coil_winding_sim/core/time_steppers/rosenbrock2.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace cws {

namespace {
const double kGamma = 1.0 + 1.0 / std::sqrt(2.0);
// W is refactored only when the step changes by more than this band.
constexpr double kKeepBelow = 1.25, kKeepAbove = 0.9;
}  // namespace

Rosenbrock2::Rosenbrock2(const SolverParams& p, const OdeSystem& sys)
    : p_(p), chain_(sys.chainStructure()), h_(p.initial_step) {
  if (chain_.block <= 0) {
    throw std::invalid_argument("rosenbrock2 needs a system with chain structure");
  }
  const int cap = sys.capacity();
  half_band_ = chain_.block * (chain_.radius + 1) - 1;
  jband_.setZero(2 * half_band_ + 1, cap);
  lu_.resize(cap, half_band_, half_band_);
  for (Eigen::VectorXd* v :
       {&f0_, &f1_, &ft_, &err_, &k1_, &k2_, &y_stage_, &y_new_, &y_pert_, &f_pert_, &delta_}) {
    v->setZero(cap);
  }
}

double Rosenbrock2::jacobian(int i, int j) const {
  if (std::abs(i - j) > half_band_ || i >= jacobian_size_ || j >= jacobian_size_) return 0.0;
  return jband_(half_band_ + i - j, j);
}

void Rosenbrock2::buildJacobian(OdeSystem& sys, double t, const Eigen::VectorXd& y) {
  const int n = sys.size();
  const int lead = chain_.lead, bs = chain_.block, r = chain_.radius;
  const int blocks = (n - lead) / bs;
  const int period = 2 * r + 1;
  sys.derivative(t, y.head(n), f0_.head(n));
  ++counts_.derivative_evaluations;
  f0_valid_ = true;
  jband_.leftCols(n).setZero();
  // Perturbation per component: relative to its size, with a floor set by
  // its absolute tolerance (so that a component at zero is still moved).
  const Eigen::VectorXd& atol = sys.absoluteTolerance();
  const double root_eps = std::sqrt(std::numeric_limits<double>::epsilon());
  for (int j = lead; j < n; ++j) {
    const double floor = std::isfinite(atol[j]) ? 1.0e3 * atol[j] : 1.0;
    delta_[j] = root_eps * std::max(std::abs(y[j]), floor);
  }
  // Colouring: blocks `period` apart never share a row within the radius,
  // so one evaluation gives one column of each block of a colour.
  y_pert_.head(n) = y.head(n);
  for (int colour = 0; colour < period; ++colour) {
    for (int m = 0; m < bs; ++m) {
      for (int b = colour; b < blocks; b += period) {
        const int j = lead + b * bs + m;
        y_pert_[j] = y[j] + delta_[j];
      }
      sys.derivative(t, y_pert_.head(n), f_pert_.head(n));
      ++counts_.derivative_evaluations;
      for (int b = colour; b < blocks; b += period) {
        const int j = lead + b * bs + m;
        // Exact perturbation actually applied (rounding of y + delta).
        const double dj = y_pert_[j] - y[j];
        y_pert_[j] = y[j];
        const int row_lo = lead + std::max(0, b - r) * bs;
        const int row_hi = lead + std::min(blocks, b + r + 1) * bs;
        for (int i = row_lo; i < row_hi; ++i) {
          jband_(half_band_ + i - j, j) = (f_pert_[i] - f0_[i]) / dj;
        }
      }
    }
  }
  jacobian_size_ = n;
  jacobian_valid_ = true;
  jacobian_age_ = 0;
  factored_h_ = -1.0;
  ++jacobians_;
}

void Rosenbrock2::factor(double h) {
  const int n = jacobian_size_;
  lu_.setZero(n);
  const double g = kGamma * h;
  for (int j = 0; j < n; ++j) {
    const int i_lo = std::max(0, j - half_band_), i_hi = std::min(n - 1, j + half_band_);
    for (int i = i_lo; i <= i_hi; ++i) lu_.at(i, j) = -g * jband_(half_band_ + i - j, j);
    lu_.at(j, j) += 1.0;
  }
  if (!lu_.factor()) {
    std::ostringstream msg;
    msg << "rosenbrock2: the iteration matrix I - gamma h J is singular at h = " << h
        << " s (non-finite Jacobian?)";
    throw IntegrationError(msg.str());
  }
  factored_h_ = h;
  ++factorizations_;
}

double Rosenbrock2::attempt(OdeSystem& sys, double t, const Eigen::VectorXd& y, double h) {
  const Eigen::Index n = sys.size();
  if (!f0_valid_) {
    sys.derivative(t, y.head(n), f0_.head(n));
    ++counts_.derivative_evaluations;
    f0_valid_ = true;
  }
  // Explicit time dependence (the clamp and port move with the core):
  // F_t by a forward difference at every attempt, as the motion turns.
  const double dt = std::sqrt(std::numeric_limits<double>::epsilon()) * std::max(std::abs(t), h);
  sys.derivative(t + dt, y.head(n), ft_.head(n));
  ++counts_.derivative_evaluations;
  ft_.head(n) = (ft_.head(n) - f0_.head(n)) / dt;
  k1_.head(n) = f0_.head(n) + (kGamma * h) * ft_.head(n);
  lu_.solve(k1_.head(n));
  y_stage_.head(n) = y.head(n) + h * k1_.head(n);
  sys.derivative(t + h, y_stage_.head(n), f1_.head(n));
  ++counts_.derivative_evaluations;
  k2_.head(n) = f1_.head(n) - 2.0 * k1_.head(n) - (kGamma * h) * ft_.head(n);
  lu_.solve(k2_.head(n));
  y_new_.head(n) = y.head(n) + (1.5 * h) * k1_.head(n) + (0.5 * h) * k2_.head(n);
  // Error estimate 1/2 h (k1 + k2), filtered by W^-1 so that stiff
  // components, which the method damps, do not count (as in Radau5).
  err_.head(n) = (0.5 * h) * (k1_.head(n) + k2_.head(n));
  lu_.solve(err_.head(n));
  return scaledErrorNorm(sys, p_.rtol, y, y_new_, err_, n);
}

void Rosenbrock2::step(OdeSystem& sys, double& t, Eigen::VectorXd& y, double t_limit) {
  for (;;) {
    double h = std::min(h_, p_.max_step);
    const bool clipped = t + h >= t_limit;
    if (clipped) h = t_limit - t;
    if (!jacobian_valid_ || jacobian_size_ != sys.size() || jacobian_age_ >= kJacobianMaxAge) {
      buildJacobian(sys, t, y);
    }
    if (h != factored_h_) factor(h);
    const double e = attempt(sys, t, y, h);
    if (e <= 1.0) {
      ++counts_.accepted;
      ++jacobian_age_;
      t = clipped ? t_limit : t + h;
      y.head(sys.size()) = y_new_.head(sys.size());
      h_last_ = h;
      f0_valid_ = false;
      sys.acceptStep(t, y);
      // Second order: grow by at most 2x; keep the step (and W) when the
      // proposal is close to it; a clipped step does not shrink the next.
      const double grow = (e > 0.0) ? 0.9 / std::sqrt(e) : 2.0;
      const double factor_h = std::min(2.0, std::max(0.2, grow));
      double h_next = h;
      if (factor_h > kKeepBelow || factor_h < kKeepAbove) h_next = h * factor_h;
      h_ = std::min(p_.max_step, clipped ? std::max(h_, h_next) : h_next);
      return;
    }
    ++counts_.rejected;
    // An old Jacobian may be the cause: rebuild it before shrinking much.
    const bool stale = jacobian_age_ > 0;
    if (stale) jacobian_valid_ = false;
    const double shrink = std::isfinite(e) ? std::max(0.1, 0.9 / std::sqrt(e)) : 0.25;
    h_ = h * (stale ? std::max(shrink, 0.5) : shrink);
    if (h_ < p_.min_step) throwStepFloor(name(), p_.min_step, t, e, h);
  }
}

}  // namespace cws
