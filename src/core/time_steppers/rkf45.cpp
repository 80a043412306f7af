#include "coil_winding_sim/core/time_steppers/rkf45.hpp"

#include <algorithm>
#include <cmath>

namespace cws {

namespace {
// Fehlberg's coefficients.
constexpr double kC[6] = {0.0, 1.0 / 4.0, 3.0 / 8.0, 12.0 / 13.0, 1.0, 1.0 / 2.0};
constexpr double kA[6][5] = {{0, 0, 0, 0, 0},
                             {1.0 / 4.0, 0, 0, 0, 0},
                             {3.0 / 32.0, 9.0 / 32.0, 0, 0, 0},
                             {1932.0 / 2197.0, -7200.0 / 2197.0, 7296.0 / 2197.0, 0, 0},
                             {439.0 / 216.0, -8.0, 3680.0 / 513.0, -845.0 / 4104.0, 0},
                             {-8.0 / 27.0, 2.0, -3544.0 / 2565.0, 1859.0 / 4104.0, -11.0 / 40.0}};
constexpr double kB5[6] = {16.0 / 135.0,      0.0,         6656.0 / 12825.0,
                           28561.0 / 56430.0, -9.0 / 50.0, 2.0 / 55.0};
constexpr double kB4[6] = {25.0 / 216.0, 0.0, 1408.0 / 2565.0, 2197.0 / 4104.0, -1.0 / 5.0, 0.0};
}  // namespace

Rkf45::Rkf45(const SolverParams& p, int capacity) : p_(p), h_(p.initial_step) {
  for (auto& k : k_) k.setZero(capacity);
  y_stage_.setZero(capacity);
  y_new_.setZero(capacity);
  err_.setZero(capacity);
}

double Rkf45::attempt(OdeSystem& sys, double t, const Eigen::VectorXd& y, double h) {
  // Work on the components in use (the buffers hold the capacity).
  const Eigen::Index n = sys.size();
  for (int s = 0; s < 6; ++s) {
    y_stage_.head(n) = y.head(n);
    for (int j = 0; j < s; ++j) {
      if (kA[s][j] != 0.0) y_stage_.head(n).noalias() += (h * kA[s][j]) * k_[j].head(n);
    }
    sys.derivative(t + kC[s] * h, y_stage_.head(n), k_[s].head(n));
    ++counts_.derivative_evaluations;
  }
  y_new_.head(n) = y.head(n);
  err_.head(n).setZero();
  for (int s = 0; s < 6; ++s) {
    y_new_.head(n).noalias() += (h * kB5[s]) * k_[s].head(n);
    err_.head(n).noalias() += (h * (kB5[s] - kB4[s])) * k_[s].head(n);
  }
  return scaledErrorNorm(sys, p_.rtol, y, y_new_, err_, n);
}

void Rkf45::step(OdeSystem& sys, double& t, Eigen::VectorXd& y, double t_limit) {
  for (;;) {
    double h = std::min(h_, p_.max_step);
    const bool clipped = t + h >= t_limit;
    if (clipped) h = t_limit - t;
    const double e = attempt(sys, t, y, h);
    if (e <= 1.0) {
      ++counts_.accepted;
      t = clipped ? t_limit : t + h;
      y.swap(y_new_);
      h_last_ = h;
      sys.acceptStep(t, y);
      // Grow by at most 5x; a clipped step does not shrink the next one.
      const double grow = (e > 0.0) ? 0.9 * std::pow(e, -0.2) : 5.0;
      const double h_next = h * std::min(5.0, std::max(0.2, grow));
      h_ = std::min(p_.max_step, clipped ? std::max(h_, h_next) : h_next);
      return;
    }
    ++counts_.rejected;
    const double shrink = std::isfinite(e) ? std::max(0.1, 0.9 * std::pow(e, -0.25)) : 0.25;
    h_ = h * shrink;
    if (h_ < p_.min_step) throwStepFloor(name(), p_.min_step, t, e, h);
  }
}

}  // namespace cws
