#include "coil_winding_sim/core/external_forces/supply.hpp"

#include <cmath>

#include "coil_winding_sim/core/quaternion.hpp"

namespace cws {

namespace {
constexpr double kTwoPi = 6.283185307179586;

// Strain on the virgin loading curve of the stretch law at axial force f.
double virginStrain(const HysteresisParams& p, double f) {
  const double yield_force = p.elastic_rigidity * p.yield;
  if (f <= yield_force || p.plastic_rigidity <= 0.0) return f / p.elastic_rigidity;
  return p.yield + (f - yield_force) / p.plastic_rigidity;
}
}  // namespace

Supply::Supply(const WireConstants& c, const Scene& s, const RotatingCore* core)
    : c_(c),
      core_(core),
      port0_world_(s.supply.port_position_world),
      axis_world_(s.core.axis_world.normalized()),
      pitch_(s.process.traverse_pitch),
      tension_(s.process.tension) {
  stretch_ = s.wire.stretch;
  if (!s.physics.plasticity) stretch_.plastic_rigidity = stretch_.elastic_rigidity;
  strain_ = virginStrain(stretch_, tension_);
}

void Supply::setTension(double tension) {
  tension_ = tension;
  strain_ = virginStrain(stretch_, tension_);
}

PortMotion Supply::port(double t) const {
  PortMotion m;
  m.p_world = port0_world_;
  if (core_ && pitch_ != 0.0) {
    const double per_rad = pitch_ / kTwoPi;  // [m/rad]
    m.p_world += per_rad * core_->angle(t) * axis_world_;
    m.v_world = per_rad * core_->omega(t) * axis_world_;
    m.a_world = per_rad * core_->angularAcceleration(t) * axis_world_;
  }
  return m;
}

void Supply::addForces(double, const WireKinematics& k, WireForces& f) const {
  // The boundary segment pulls the last point outwards along its zeta axis.
  const int last = c_.n - 1;
  const Eigen::Vector3d zeta = quat::zeta(k.q.col(last));
  const Eigen::Vector3d pull = tension_ * zeta;
  f.f_world.col(last) += pull;
  f.f_work_world.col(last) += pull;
}

}  // namespace cws
