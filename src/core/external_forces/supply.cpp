#include "coil_winding_sim/core/external_forces/supply.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "coil_winding_sim/core/assembly/planar_assembly.hpp"
#include "coil_winding_sim/core/assembly/spatial_assembly.hpp"
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
    : c_(c),
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

void Supply::addExplicit(const WireKinematics& k, WireForces& f) const {
  // The boundary segment pulls the last point outwards along its zeta axis.
  const int last = c_.n - 1;
  const Eigen::Vector3d zeta = quat::zeta(k.q.col(last));
  const Eigen::Vector3d pull = tension_ * zeta;
  f.f_world.col(last) += pull;
  f.f_work_world.col(last) += pull;
}

void Supply::addPlanar(const PlanarState& s, PlanarAssembly& a) const {
  const int last = s.n - 1;
  const Eigen::Vector2d d = s.segment(last - 1);
  const double len = d.norm();
  const Eigen::Vector2d u = d / len;
  const Eigen::Matrix2d id = Eigen::Matrix2d::Identity();
  const Eigen::Matrix2d proj = id - u * u.transpose();
  // The boundary segment's tension pulls the last point along the last
  // segment (its frame's zeta): a follower force.
  a.addForce(last, tension_ * u);
  a.f_work.col(last) += tension_ * u;
  const Eigen::Matrix2d kt = (tension_ / len) * proj;
  a.addStiffness(last, last, kt);
  a.addStiffness(last, last - 1, -kt);
  // Port constraint (eq. 22 in the plane): the port lies on the line of the
  // last segment, g = cross(u, e) = 0 with e = x_L - p_s [m]. Its force
  // lambda dg/dx; the row holds -scale g.
  const PortMotion pm = port(s.t);
  const Eigen::Vector2d e = s.x.col(last) - s.plane.toPlane(pm.p_world);
  const double g = planar::cross(u, e);
  const Eigen::Vector2d w = -planar::perp(e);
  const Eigen::Vector2d g_d = proj * w / len;   // dg/dd
  const Eigen::Vector2d g_e = planar::perp(u);  // dg/de
  const Eigen::Vector2d grad_last = g_d + g_e, grad_prev = -g_d;
  const double lambda = s.lambda_port;
  a.addForce(last, lambda * grad_last);
  a.addForce(last - 1, lambda * grad_prev);
  // The moving port works on the wire through the constraint force.
  a.power_external += lambda * g_e.dot(s.plane.vectorToPlane(pm.v_world));
  // Scale: the row in N, like the force rows (the axial stiffness EA / l).
  a.setConstraint(g, stretch_.elastic_rigidity / c_.segment_length);
  if (!a.wantsJacobian()) return;
  a.addConstraintGradient(last, grad_last);
  a.addConstraintGradient(last - 1, grad_prev);
  // lambda d^2 g / dx^2 over (x_{L-1}, x_L), with d = x_L - x_{L-1} and e.
  const Eigen::Vector2d pw = proj * w;
  const Eigen::Matrix2d h_dd =
      -(u.dot(w) * proj + u * pw.transpose() + pw * u.transpose()) / (len * len);
  const Eigen::Matrix2d h_ed = planar::perpMatrix() * proj / len;  // d g_e / dd
  a.addStiffness(last, last, lambda * (h_dd + h_ed + h_ed.transpose()));
  a.addStiffness(last, last - 1, lambda * (-h_dd - h_ed));
  a.addStiffness(last - 1, last, lambda * (-h_dd - h_ed.transpose()));
  a.addStiffness(last - 1, last - 1, lambda * h_dd);
}

void Supply::addSpatial(const SpatialState& s, SpatialAssembly& a) const {
  // The boundary segment's tension along the last frame's zeta, as
  // addForces does; the port constraint (eq. 22): the port lies on the line
  // of that frame's zeta through the last point, g = e . (xi, eta) = 0 with
  // e = p_L - p_s, held by the multipliers lambda_port.
  const int last = s.n - 1;
  const quat::Vec4 q = s.q.col(last);
  const Eigen::Vector3d pull = tension_ * quat::zeta(q);
  a.addForce(last, pull);
  a.f_work.col(last) += pull;
  const PortMotion pm = port(s.t);
  const Eigen::Vector3d e = s.p.col(last) - pm.p_world;
  const Eigen::Vector3d axis[2] = {quat::xi(q), quat::eta(q)};
  const quat::Mat34 jac[2] = {quat::xiJacobian(q), quat::etaJacobian(q)};
  const double scale = stretch_.elastic_rigidity / c_.segment_length;
  for (int r = 0; r < 2; ++r) {
    const double lambda = s.lambda_port[r];
    a.addForce(last, lambda * axis[r]);
    a.addQForce(last, lambda * jac[r].transpose() * e);
    // The moving port works on the wire through the constraint force.
    a.power_external += lambda * axis[r].dot(pm.v_world);
    const int row = a.portRow() + r;
    a.setConstraint(row, e.dot(axis[r]), scale);
    if (!a.wantsJacobian()) continue;
    a.addConstraintGradientP(row, last, axis[r]);
    a.addConstraintGradientQ(row, last, jac[r].transpose() * e);
    a.addStiffnessPQ(last, last, lambda * jac[r]);
    a.addStiffnessQP(last, last, lambda * jac[r].transpose());
  }
  if (!a.wantsJacobian()) return;
  a.addStiffnessPQ(last, last, tension_ * quat::zetaJacobian(q));
  a.addStiffnessQQ(last, last,
                   s.lambda_port[0] * quat::xiHessian(e) + s.lambda_port[1] * quat::etaHessian(e));
}

}  // namespace cws
