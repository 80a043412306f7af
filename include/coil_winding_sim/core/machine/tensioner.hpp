// The machine between the tension setpoint and the wire at the port
// (supply.tensioner, supply.nozzle_*; docs/MODEL.md, "A tensioner and a
// nozzle").
//
// A dancer: an arm of moving mass m on a spring (rate k, force 2 T_set at
// the centre) and a damper c carries a pulley the wire wraps, so the arm's
// travel x stores 2 x of wire. A servo pay-off feeds wire at
//   u_pay = -(K_p x + K_i integral(x)),  K_p = 4 w_c, K_i = 2 w_c^2,
// which puts the position loop's poles at -w_c (a double pole) for a stiff
// span. The span of wire from the pay-off over the pulley to the nozzle is a
// spring of rate k_w = EA / L_span on its stretch e; it carries the span's
// tension T = k_w e (0 when slack). With the draw-in speed u at the port:
//   m x'' = 2 T_set - k x - c x' - 2 T,   e' = 2 x' - u_pay + u.
// The draw-in speed is held over each accepted step (the wire's step), and
// the state is advanced by the trapezoidal rule in sub-steps short against
// the span's mode; its energy changes by exactly the works booked below.
//
// The nozzle: capstan friction over its wrap angle turns the span's tension
// into the port's, T_port = T exp(mu theta s), s = u / max(|u|, v_s): the
// wire's side is the tighter one while it is drawn in.
#pragma once

#include <Eigen/Core>

#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

// The nozzle's capstan ratio T_port / T_tensioner at draw-in speed u [m/s],
// regularized below stick_speed [m/s] as the contact's friction is.
double capstanRatio(double mu, double wrap_angle_rad, double u, double stick_speed);

class Tensioner {
 public:
  // `span_rigidity` [N]: the wire's axial rigidity EA. The arm starts
  // centred and at rest, the span at the setpoint's tension.
  Tensioner(const TensionerParams& p, double span_rigidity, double setpoint_N);

  // Advances from the last time to t [s] with draw-in speed u [m/s] held.
  void advance(double t, double u);
  // The tension setpoint [N]: the arm's load from the next advance on.
  void setSetpoint(double setpoint_N) { setpoint_ = setpoint_N; }

  // The span's tension, at the nozzle's tensioner side [N].
  double tension() const;
  double armPosition() const { return s_[0]; }  // x [m], + stores wire
  double armVelocity() const { return s_[1]; }  // [m/s]
  // The pay-off's feed speed [m/s].
  double payOffSpeed() const { return -(kp_ * s_[0] + ki_ * s_[3]); }

  // Energy [J]: held (arm's kinetic, its spring's and the span's), lost in
  // the damper, and the work of the arm's load (2 T_set), of the pay-off,
  // and of the wire drawn in (the span's tension times the draw-in).
  double kinetic() const { return 0.5 * p_.mass * s_[1] * s_[1]; }
  double elastic() const;
  double damped() const { return damped_; }
  double loadWork() const { return load_work_; }
  double payOffWork() const { return payoff_work_; }
  double drawnWork() const { return drawn_work_; }

  // The state, for snapshots: kValues numbers.
  static constexpr int kValues = 9;
  void save(double* out) const;
  void restore(const double* in);

 private:
  using Vec4 = Eigen::Matrix<double, 4, 1>;
  // One trapezoidal sub-step of length dt with the span taut or slack.
  void subStep(double dt, double u);

  TensionerParams p_;
  double span_k_;    // k_w [N/m]
  double kp_, ki_;   // the pay-off's loop [1/s], [1/s^2]
  double setpoint_;  // [N]
  double t_ = 0.0;   // [s]
  Vec4 s_;           // x [m], x' [m/s], e [m], integral of x [m s]
  double damped_ = 0.0, load_work_ = 0.0, payoff_work_ = 0.0, drawn_work_ = 0.0;  // [J]
  double longest_substep_;                                                        // [s]
};

}  // namespace cws
