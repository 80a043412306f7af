#include "coil_winding_sim/core/external_forces/contact.hpp"

#include <cmath>

#include "coil_winding_sim/core/core_geometry.hpp"

namespace cws {

Contact::Contact(const WireConstants& c, const Scene& s, const RotatingCore& core)
    : c_(c),
      p_(s.contact),
      core_(core),
      friction_(s.physics.friction),
      c_normal_(2.0 * s.contact.damping_ratio * std::sqrt(s.contact.stiffness * c.point_mass)),
      c_stick_(2.0 * s.contact.damping_ratio * std::sqrt(s.contact.stick_stiffness * c.point_mass)),
      h_ramp_(kDashpotRamp * c.radius) {
  for (const CylinderParams& cyl : s.core.cylinders) {
    centers_core_.emplace_back(cyl.center_core.x(), cyl.center_core.y(), 0.0);
    radii_.push_back(cyl.radius);
  }
  centers_world_.resize(radii_.size());
  for (const FaceParams& f : coreFaces(s.core)) {
    const Eigen::Vector2d d = f.to_core - f.from_core;
    face_from_core_.emplace_back(f.from_core.x(), f.from_core.y(), 0.0);
    face_dir_core_.emplace_back(d.x() / d.norm(), d.y() / d.norm(), 0.0);
    face_normal_core_.emplace_back(d.y() / d.norm(), -d.x() / d.norm(), 0.0);
    face_length_.push_back(d.norm());
  }
  face_from_world_.resize(face_length_.size());
  face_dir_world_.resize(face_length_.size());
  face_normal_world_.resize(face_length_.size());
  cylinder_.assign(c_.capacity, -1);
  depth_.assign(c_.capacity, 0.0);
  friction_force_.assign(c_.capacity, Eigen::Vector3d::Zero());
  if (friction_) {
    stuck_.assign(c_.capacity, 0);
    anchor_core_.assign(c_.capacity, Eigen::Vector3d::Zero());
  }
  trial_surface_.assign(c_.capacity, -1);
  trial_stuck_.assign(c_.capacity, 0);
  trial_anchor_core_.assign(c_.capacity, Eigen::Vector3d::Zero());
  trial_sign_.assign(c_.capacity, 1);
  trial_slip_world_.assign(c_.capacity, Eigen::Vector3d::Zero());
}

void Contact::placeSurfaces(double t) const {
  rot_world_core_ = core_.rotationWorldCore(t);
  const Eigen::Matrix3d& rot = rot_world_core_;
  for (std::size_t j = 0; j < radii_.size(); ++j) {
    centers_world_[j] = core_.originWorld() + rot * centers_core_[j];
  }
  if (face_length_.empty()) return;
  for (std::size_t j = 0; j < face_length_.size(); ++j) {
    face_from_world_[j] = core_.originWorld() + rot * face_from_core_[j];
    face_dir_world_[j] = rot * face_dir_core_[j];
    face_normal_world_[j] = rot * face_normal_core_[j];
  }
}

int Contact::touch(const Eigen::Vector3d& p_world, double& h, Eigen::Vector3d& n_world) const {
  int best = -1;
  h = 0.0;
  const Eigen::Vector3d& a = core_.axisWorld();
  for (std::size_t j = 0; j < radii_.size(); ++j) {
    const Eigen::Vector3d d = p_world - centers_world_[j];
    const Eigen::Vector3d d_perp = d - d.dot(a) * a;
    const double dist = d_perp.norm();
    const double depth = radii_[j] + c_.radius - dist;
    if (depth > h && dist > 0.0) {
      h = depth;
      n_world = d_perp / dist;
      best = static_cast<int>(j);
    }
  }
  // Faces: the point is over the face strip and at most a wire diameter
  // below its outer side (deeper points belong to the other side).
  for (std::size_t j = 0; j < face_length_.size(); ++j) {
    const Eigen::Vector3d d = p_world - face_from_world_[j];
    const double along = d.dot(face_dir_world_[j]);
    if (along < 0.0 || along > face_length_[j]) continue;
    const double depth = c_.radius - d.dot(face_normal_world_[j]);
    if (depth > h && depth < 2.0 * c_.radius) {
      h = depth;
      n_world = face_normal_world_[j];
      best = static_cast<int>(radii_.size() + j);
    }
  }
  return best;
}

Eigen::Vector3d Contact::friction(int i, const Eigen::Vector3d& p_world,
                                  const Eigen::Vector3d& vh_world, const Eigen::Vector3d& n_world,
                                  double normal_force, bool& slipping) const {
  slipping = true;
  if (stuck_[i]) {
    // Stick: a tangential spring to the anchor, within the static limit.
    const Eigen::Vector3d delta =
        p_world - (core_.originWorld() + rot_world_core_ * anchor_core_[i]);
    Eigen::Vector3d f_t = -p_.stick_stiffness * (delta - delta.dot(n_world) * n_world);
    if (c_stick_ > 0.0) f_t -= c_stick_ * vh_world;
    if (f_t.norm() <= p_.static_friction * normal_force) {
      slipping = false;
      return f_t;
    }
  }
  // Slip: kinetic friction against the relative tangential velocity.
  const double speed = vh_world.norm();
  if (speed == 0.0) return Eigen::Vector3d::Zero();
  return (-p_.kinetic_friction * normal_force / speed) * vh_world;
}

void Contact::addForces(double t, const WireKinematics& k, WireForces& f) const {
  placeSurfaces(t);
  for (int i = c_.first; i < c_.n; ++i) {
    const Eigen::Vector3d p = k.p_world.col(i);
    double h;
    Eigen::Vector3d n;
    if (touch(p, h, n) < 0) continue;
    const Eigen::Vector3d u = core_.velocityWorld(t, p);
    const Eigen::Vector3d v_rel = k.v_world.col(i) - u;
    const double normal = normalForce(h, v_rel.dot(n));
    Eigen::Vector3d f_c = normal * n;
    if (c_normal_ > 0.0) {
      // The dashpot's part (with the spring's where it would pull)
      // dissipates, as friction does.
      const Eigen::Vector3d f_d = (normal - p_.stiffness * h) * n;
      f.power_dissipated += f_d.dot(u);
      f.f_dissipative_world.col(i) += f_d;
    }
    if (friction_) {
      const Eigen::Vector3d vh = v_rel - v_rel.dot(n) * n;
      bool slipping;
      const Eigen::Vector3d f_t = friction(i, p, vh, n, normal, slipping);
      f_c += f_t;
      // Friction power -f_t . (v - u), counted as dissipated (also what a
      // stick spring holds; f_t is tangential, so f_t . vh = f_t . (v - u)).
      f.power_dissipated += f_t.dot(u);
      f.f_dissipative_world.col(i) += f_t;
    }
    f.f_world.col(i) += f_c;
    // The moving surface does work on the wire.
    f.power_external += f_c.dot(u);
  }
}

void Contact::commit(double t, const WireKinematics& k) {
  max_penetration_ = 0.0;
  elastic_committed_ = 0.0;
  placeSurfaces(t);
  // Carried points keep their contact and friction state: they move with
  // the core, so their penetration does not change.
  for (int i = 1; i < c_.first; ++i) {
    max_penetration_ = std::max(max_penetration_, depth_[i]);
    elastic_committed_ += 0.5 * p_.stiffness * depth_[i] * depth_[i];
  }
  for (int i = c_.first; i < c_.n; ++i) {
    const Eigen::Vector3d p = k.p_world.col(i);
    double h;
    Eigen::Vector3d n;
    const int cyl = touch(p, h, n);
    const bool changed_cylinder = cyl != cylinder_[i];
    cylinder_[i] = cyl;
    depth_[i] = cyl >= 0 ? h : 0.0;
    if (cyl >= 0) {
      max_penetration_ = std::max(max_penetration_, h);
      elastic_committed_ += 0.5 * p_.stiffness * h * h;
    }
    friction_force_[i].setZero();
    if (!friction_) continue;
    if (cyl < 0 || changed_cylinder) stuck_[i] = 0;
    if (cyl < 0) continue;
    const Eigen::Vector3d v_rel = k.v_world.col(i) - core_.velocityWorld(t, p);
    const Eigen::Vector3d vh = v_rel - v_rel.dot(n) * n;
    bool slipping;
    friction_force_[i] = friction(i, p, vh, n, normalForce(h, v_rel.dot(n)), slipping);
    if (stuck_[i] && slipping) {
      stuck_[i] = 0;  // the static limit was exceeded
    } else if (!stuck_[i] && vh.norm() < p_.stick_speed) {
      stuck_[i] = 1;  // slow enough: stick where it is
      anchor_core_[i] = rot_world_core_.transpose() * (p - core_.originWorld());
    }
  }
}

void Contact::appendHistory(std::vector<double>& out) const {
  for (int i = 0; i < c_.n; ++i) {
    out.push_back(cylinder_[i]);
    out.push_back(depth_[i]);
    if (friction_) {
      out.push_back(stuck_[i]);
      out.insert(out.end(), anchor_core_[i].data(), anchor_core_[i].data() + 3);
      out.insert(out.end(), friction_force_[i].data(), friction_force_[i].data() + 3);
    }
  }
  out.push_back(max_penetration_);
  out.push_back(elastic_committed_);
}

void Contact::shrink(const WireKinematics&) {
  // The last point sits at the port, away from the core: nothing to book.
  const int i = c_.n - 1;
  cylinder_[i] = -1;
  depth_[i] = 0.0;
  if (friction_) {
    stuck_[i] = 0;
    anchor_core_[i].setZero();
    friction_force_[i].setZero();
  }
}

double Contact::elasticEnergy(const WireKinematics&) const { return elastic_committed_; }

void Contact::restoreHistory(HistoryReader& in) {
  for (int i = 0; i < c_.n; ++i) {
    cylinder_[i] = static_cast<int>(in.next());
    depth_[i] = in.next();
    if (friction_) {
      stuck_[i] = in.next() != 0.0;
      for (int d = 0; d < 3; ++d) anchor_core_[i][d] = in.next();
      for (int d = 0; d < 3; ++d) friction_force_[i][d] = in.next();
    }
  }
  max_penetration_ = in.next();
  elastic_committed_ = in.next();
}

}  // namespace cws
