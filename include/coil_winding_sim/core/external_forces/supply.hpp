// The wire supply of the paper's section IV (eqs. 21-22): wire is drawn into
// the simulated region through a port at constant tension F_T.
//
// The last mass point L is the inner end of the paper's boundary segment,
// which runs along zeta_L through the port to a point outside. The port
// constraint (constraints/frame_constraints) keeps the port on that line;
// this effect pulls point L outwards along zeta_L with F_T (the boundary
// segment's tension). When the outer point would pass the port, the model
// appends it as a new mass point (WireModel::acceptStep), so the wire grows.
// The port travels along the core axis by process.traverse_pitch per core
// revolution, so the wire winds as a spiral, reversing at the ends of
// process.winding_width for process.layers passes (TraverseProfile), unless
// a caller commands its path (commandPort): then it follows the commanded
// samples instead.
//
// The tension at the port is the setpoint's with the ideal tensioner and a
// frictionless nozzle. Otherwise the tensioner and the nozzle
// (machine/tensioner.hpp) make it from the wire drawn in, after each
// accepted step (afterStep), for the next step.
#pragma once

#include <optional>
#include <vector>

#include "coil_winding_sim/core/assembly/force_effect.hpp"
#include "coil_winding_sim/core/base/hysteresis.hpp"
#include "coil_winding_sim/core/constraints/frame_constraints.hpp"
#include "coil_winding_sim/core/external_forces/port_trajectory.hpp"
#include "coil_winding_sim/core/machine/rotating_core.hpp"
#include "coil_winding_sim/core/machine/tensioner.hpp"
#include "coil_winding_sim/core/machine/traverse_profile.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

// The tension where a machine's load cell sits (after the nozzle), seen at
// each accepted step: its extremes and the ripple (highest less lowest) of
// each whole core turn [N]. The list holds the turns its storage, reserved
// at the start for the scene's turns, has room for (a cell that winds on
// allocates nothing for it); the largest and the mean cover every turn.
struct TensionTrace {
  double peak = 0.0, low = 0.0;
  std::vector<double> ripple_per_turn;
  double ripple_max = 0.0, ripple_sum = 0.0;
  long ripple_turns = 0;
  bool seen = false;
  int turn = 0;  // the core turn under way
  double turn_max = 0.0, turn_min = 0.0;
  void note(double core_turns, double tension_N);
};

// The tensioner's and the nozzle's energy [J] (zero with the ideal
// tensioner, which lies outside the balance).
struct MachineEnergy {
  double kinetic = 0.0, elastic = 0.0, dissipated = 0.0, work_done = 0.0;
};

class Supply : public SinkEffect<Supply>, public EffectHistory {
 public:
  Supply(const WireConstants& c, const Scene& s, const RotatingCore* core);

  const char* name() const override { return "supply"; }
  // The boundary segment pulls the last point outwards along its frame's
  // zeta with the tension: a follower force, written once on the sink. (The
  // port constraint that holds the port on that line is the constraints':
  // constraints/frame_constraints.hpp.)
  template <class Sink>
  void law(Sink& s) const {
    s.addFollowerForce(s.n() - 1, tension_, ForcePower::kApplied);
  }
  // The commanded port's samples before t are past.
  void commit(const AcceptedStep& step) override;

  // Port motion at time t (within the step from the committed time).
  PortMotion port(double t) const;
  // Commands the port to be at p_world [m] at time t_s [s] (PortTrajectory:
  // straight lines between samples, the last held); replaces the traverse
  // law from the first command on. t_now is the committed time. Throws
  // std::invalid_argument naming the problem (not finite, stamps going
  // backwards or into the past, a jump, a port inside the turning core);
  // nothing changes then.
  void commandPort(double t_s, const Eigen::Vector3d& p_world, double t_now);
  const PortTrajectory& portCommand() const { return command_; }
  PortTrajectory& portCommand() { return command_; }
  // The tension at the port [N]: what pulls the wire.
  double tension() const { return tension_; }
  // The tension setpoint [N] (process.tension and its setpoints).
  double tensionSetpoint() const { return setpoint_; }
  // New tension setpoint [N] (>= 0): with the ideal tensioner, pulls from
  // the next evaluation on; points drawn in from then on arrive stretched
  // to the port's tension.
  void setTension(double tension);
  // After an accepted step ending at t [s]: the wire's natural length drawn
  // in since the start [m], the tension at the port's segment [N] and the
  // core's turns. The tensioner advances on the draw-in speed, and the
  // port's tension for the next step follows.
  void afterStep(double t, double fed_length_m, double measured_N, double core_turns);
  const TensionTrace& trace() const { return trace_; }
  const Tensioner* tensioner() const { return tensioner_ ? &*tensioner_ : nullptr; }
  MachineEnergy machineEnergy() const;
  void appendHistory(std::vector<double>& out) const override;
  void restoreHistory(HistoryReader& in) override;
  // Strain of wire at the supply tension (virgin loading curve) [-], and the
  // length of the boundary segment l (1 + strain) [m].
  double tensionStrain() const { return strain_; }
  double boundaryLength() const { return c_.segment_length * (1.0 + strain_); }

 private:
  HysteresisParams stretch_;  // the law new wire is stretched along
  const RotatingCore* core_;  // null: the port does not traverse
  Eigen::Vector3d port0_world_, axis_world_;
  TraverseProfile profile_;  // the port's travel along the core axis
  // The core's swept radius widened by the wire radius [m] (0: no cylinders):
  // a commanded port closer to the axis is inside the turning core.
  double swept_radius_ = 0.0;
  Eigen::Vector3d core_origin_world_;
  PortTrajectory command_;
  double setpoint_;  // [N]
  double tension_;   // at the port [N]
  double strain_;    // [-]
  // The dancer (supply.tensioner.kind dancer), and the nozzle's capstan.
  std::optional<Tensioner> tensioner_;
  double nozzle_exponent_ = 0.0;  // mu theta [-]
  double stick_speed_;            // [m/s] (contact.stick_speed)
  bool machine_ = false;          // a dancer or a nozzle with friction
  double draw_in_ = 0.0;          // over the last step [m/s]
  // The wire drawn in at past steps, t [s] and length [m], newest last: the
  // draw-in speed is taken over the passage of a segment through the port,
  // since within it the discrete wire's last point moves unevenly (as a
  // chain on a sprocket does).
  static constexpr int kFedSamples = 512;
  double fed_at_t_[kFedSamples] = {}, fed_at_m_[kFedSamples] = {};
  int fed_samples_ = 0, fed_newest_ = 0;
  double segment_length_;  // [m]
  // The draw-in speed [m/s] from the samples, after appending (t, fed).
  double drawInSpeed(double t, double fed_length_m);
  double port_work_ = 0.0;  // by the port's tension on the wire drawn in [J]
  TensionTrace trace_;
  // The port's tension from the tensioner's and the draw-in speed.
  void updatePortTension();
};

}  // namespace cws
