#include "coil_winding_sim/core/external_forces/supply.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "coil_winding_sim/core/base/quaternion.hpp"

namespace cws {

namespace {

// Strain on the virgin loading curve of the stretch law at axial force f.
double virginStrain(const HysteresisParams& p, double f) {
  const double yield_force = p.elastic_rigidity * p.yield;
  if (f <= yield_force || p.plastic_rigidity <= 0.0) return f / p.elastic_rigidity;
  return p.yield + (f - yield_force) / p.plastic_rigidity;
}
}  // namespace

Supply::Supply(const WireConstants& c, const Scene& s, const RotatingCore* core)
    : SinkEffect(c),
      core_(core),
      port0_world_(s.supply.port_position_world),
      axis_world_(s.core.axis_world.normalized()),
      profile_(TraverseProfile::of(s.process.traverse_pitch, s.process.winding_width,
                                   s.wire.diameter, s.traverseLayers())
                   .stalled(s.process.traverse_stall_turn, s.process.traverse_stall_turns)),
      core_origin_world_(s.core.position_world),
      tension_(s.process.tension) {
  for (const CylinderParams& cyl : s.core.cylinders) {
    swept_radius_ = std::max(swept_radius_, cyl.center_core.norm() + cyl.radius + c.radius);
  }
  stretch_ = s.wire.stretch;
  if (!s.physics.plasticity) stretch_.plastic_rigidity = stretch_.elastic_rigidity;
  strain_ = virginStrain(stretch_, tension_);
}

void Supply::setTension(double tension) {
  tension_ = tension;
  strain_ = virginStrain(stretch_, tension_);
}

void Supply::commit(const AcceptedStep& step) { command_.commit(step.t); }

void Supply::commandPort(double t_s, const Eigen::Vector3d& p_world, double t_now) {
  if (swept_radius_ > 0.0 && p_world.allFinite()) {
    // Distance from the core axis: inside the swept core the wire could not
    // leave the port.
    const Eigen::Vector3d r = p_world - core_origin_world_;
    const double radial = (r - r.dot(axis_world_) * axis_world_).norm();
    if (radial < swept_radius_) {
      std::ostringstream msg;
      msg << "port command (" << p_world.x() << ", " << p_world.y() << ", " << p_world.z()
          << ") m at t = " << t_s << " s lies inside the turning core: " << radial
          << " m from its axis, the core with the wire reaches " << swept_radius_ << " m";
      throw std::invalid_argument(msg.str());
    }
  }
  command_.append(t_s, p_world, t_now, port(t_now).p_world);
}

PortMotion Supply::port(double t) const {
  if (command_.active()) return command_.at(t);
  PortMotion m;
  m.p_world = port0_world_;
  if (core_ && profile_.pitch != 0.0) {
    // The traverse, geared to the core's angle (traverse_profile.hpp).
    const TraverseProfile::Position tp = profile_.at(core_->angle(t));
    m.p_world += tp.offset * axis_world_;
    m.v_world = tp.per_rad * core_->omega(t) * axis_world_;
    m.a_world = tp.per_rad * core_->angularAcceleration(t) * axis_world_;
  }
  return m;
}

}  // namespace cws
