#include "coil_winding_sim/core/machine/tensioner.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace cws {

double capstanRatio(double mu, double wrap_angle_rad, double u, double stick_speed) {
  const double s = u / std::max(std::abs(u), stick_speed);
  return std::exp(mu * wrap_angle_rad * s);
}

Tensioner::Tensioner(const TensionerParams& p, double span_rigidity, double setpoint_N)
    : p_(p),
      span_k_(span_rigidity / p.span_length),
      kp_(4.0 * p.bandwidth),
      ki_(2.0 * p.bandwidth * p.bandwidth),
      setpoint_(setpoint_N) {
  s_ << 0.0, 0.0, setpoint_N / span_k_, 0.0;
  // The arm's load stretched the span to the setpoint before the start.
  load_work_ = elastic();
  // A quarter of a period of the fastest mode (the arm on the span and its
  // spring), and of the loop: the trapezoidal rule's phase error stays
  // below half a percent there.
  const double omega = std::sqrt((p.stiffness + 4.0 * span_k_) / p.mass) + p.bandwidth;
  longest_substep_ = 0.25 / omega;
}

double Tensioner::tension() const { return span_k_ * std::max(s_[2], 0.0); }

double Tensioner::elastic() const {
  const double e = std::max(s_[2], 0.0);
  return 0.5 * p_.stiffness * s_[0] * s_[0] + 0.5 * span_k_ * e * e;
}

void Tensioner::advance(double t, double u) {
  const double h = t - t_;
  if (!(h > 0.0)) return;
  const int n = static_cast<int>(std::ceil(h / longest_substep_));
  for (int i = 0; i < n; ++i) subStep(h / n, u);
  t_ = t;
}

void Tensioner::subStep(double dt, double u) {
  // The span pulls on the arm only while taut (decided at the sub-step's
  // start).
  const double span_k = s_[2] > 0.0 ? span_k_ : 0.0;
  Eigen::Matrix4d a;
  a << 0.0, 1.0, 0.0, 0.0,                                                           // x' = v
      -p_.stiffness / p_.mass, -p_.damping / p_.mass, -2.0 * span_k / p_.mass, 0.0,  // v'
      kp_, 2.0, 0.0, ki_,  // e' = 2 v - u_pay + u
      1.0, 0.0, 0.0, 0.0;  // z' = x
  Vec4 b;
  b << 0.0, 2.0 * setpoint_ / p_.mass, u, 0.0;
  const Eigen::Matrix4d half = 0.5 * dt * a;
  const Vec4 next = (Eigen::Matrix4d::Identity() - half)
                        .partialPivLu()
                        .solve((Eigen::Matrix4d::Identity() + half) * s_ + dt * b);
  // The works at the sub-step's mean state: with the trapezoidal rule the
  // held energy changes by exactly their sum (taut span).
  const Vec4 mean = 0.5 * (s_ + next);
  const double tension = span_k * mean[2];
  load_work_ += dt * 2.0 * setpoint_ * mean[1];
  damped_ += dt * p_.damping * mean[1] * mean[1];
  payoff_work_ += dt * tension * (kp_ * mean[0] + ki_ * mean[3]);
  drawn_work_ += dt * tension * u;
  s_ = next;
}

void Tensioner::save(double* out) const {
  for (int i = 0; i < 4; ++i) out[i] = s_[i];
  out[4] = t_;
  out[5] = damped_;
  out[6] = load_work_;
  out[7] = payoff_work_;
  out[8] = drawn_work_;
}

void Tensioner::restore(const double* in) {
  for (int i = 0; i < kValues; ++i) {
    if (!std::isfinite(in[i])) throw std::runtime_error("snapshot tensioner state is not finite");
  }
  for (int i = 0; i < 4; ++i) s_[i] = in[i];
  t_ = in[4];
  damped_ = in[5];
  load_work_ = in[6];
  payoff_work_ = in[7];
  drawn_work_ = in[8];
}

}  // namespace cws
