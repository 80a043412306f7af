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
#pragma once

#include "coil_winding_sim/core/assembly/force_effect.hpp"
#include "coil_winding_sim/core/base/hysteresis.hpp"
#include "coil_winding_sim/core/constraints/frame_constraints.hpp"
#include "coil_winding_sim/core/external_forces/port_trajectory.hpp"
#include "coil_winding_sim/core/machine/rotating_core.hpp"
#include "coil_winding_sim/core/machine/traverse_profile.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

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
  double tension() const { return tension_; }  // [N]
  // New supply tension [N] (>= 0): pulls from the next evaluation on; points
  // drawn in from then on arrive stretched to it.
  void setTension(double tension);
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
  double tension_;  // [N]
  double strain_;   // [-]
};

}  // namespace cws
