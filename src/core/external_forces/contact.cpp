#include "coil_winding_sim/core/external_forces/contact.hpp"

#include <algorithm>
#include <cmath>

#include "coil_winding_sim/core/external_forces/elastic_slip.hpp"
#include "coil_winding_sim/core/scene/core_geometry.hpp"

namespace cws {

Contact::Contact(const WireConstants& c, const Scene& s, const RotatingCore& core)
    : c_(c),
      p_(s.contact),
      core_(core),
      geometry_(c, s, core),
      slots_(geometry_.slots()),
      flange_slot_(geometry_.flangeSlot()),
      wire_base_(geometry_.wireBase()),
      friction_(s.physics.friction),
      elastic_slip_(s.contact.friction_law == "elastic_slip"),
      c_normal_(2.0 * s.contact.damping_ratio * std::sqrt(s.contact.stiffness * c.point_mass)),
      c_stick_(2.0 * s.contact.damping_ratio * std::sqrt(s.contact.stick_stiffness * c.point_mass)),
      h_ramp_(kDashpotRamp * c.radius) {
  const std::size_t slots = static_cast<std::size_t>(c_.capacity) * slots_;
  surface_.assign(slots, -1);
  depth_.assign(slots, 0.0);
  friction_force_.assign(slots, Eigen::Vector3d::Zero());
  if (friction_) {
    stuck_.assign(slots, 0);
    anchor_core_.assign(slots, Eigen::Vector3d::Zero());
    slow_.assign(slots, 0);
  }
  trial_surface_.assign(slots, -1);
  trial_stuck_.assign(slots, 0);
  trial_sign_.assign(slots, 1);
  trial_releases_.assign(slots, 0);
  trial_switches_.assign(slots, 0);
  const std::size_t span_slots =
      static_cast<std::size_t>(std::min(c_.capacity, kReservedSpan)) * slots_;
  trial_anchor_core_.assign(span_slots, Eigen::Vector3d::Zero());
  trial_slip_world_.assign(span_slots, Eigen::Vector3d::Zero());
  recheck_touches_.assign(span_slots, Touch());
}

Eigen::Vector3d Contact::friction(int i, const Eigen::Vector3d& p_world,
                                  const Eigen::Vector3d& vh_world, const Eigen::Vector3d& n_world,
                                  double normal_force, bool& slipping) const {
  slipping = true;
  if (stuck_[i]) {
    // Stick: a tangential spring to the anchor, within the static limit.
    const Eigen::Vector3d delta =
        p_world - (core_.originWorld() + geometry_.rotWorldCore() * anchor_core_[i]);
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

void Contact::commitAt(double t, const WireKinematics& k) {
  deepest_in_wire_ = WireDepth();
  geometry_.place(t);
  geometry_.syncCarriedWire();
  // Carried points keep their contact and friction state: they move with
  // the core, so their penetration does not change. Only the points carried
  // since the last commit are added (all again after a release).
  if (c_.first < carried_summed_) forgetCarriedSums();
  for (int x = carried_summed_ * slots_; x < c_.first * slots_; ++x) {
    carried_max_penetration_ = std::max(carried_max_penetration_, depth_[x]);
    carried_elastic_ += 0.5 * p_.stiffness * depth_[x] * depth_[x];
  }
  carried_summed_ = std::max(carried_summed_, c_.first);
  max_penetration_ = std::max(carried_max_penetration_, retired_max_penetration_);
  elastic_committed_ = carried_elastic_;
  // An implicit step's last recheck found the surfaces at this state
  // already (its end state, at this time): they are read, not searched for.
  const bool rechecked =
      recheck_.valid && recheck_.t == t && recheck_.first == c_.first && recheck_.n == c_.n;
  recheck_.valid = false;
  Touch found[kMaxSlots];
  for (int i = c_.first; i < c_.n; ++i) {
    const Eigen::Vector3d p = k.p_world.col(i);
    const Touch* touches = found;
    if (rechecked) {
      touches = &recheck_touches_[(i - c_.first) * slots_];
    } else {
      geometry_.touchAll(i, p, &surface_[i * slots_], found);
    }
    for (int s = 0; s < slots_; ++s) {
      const int x = i * slots_ + s;
      const Touch& c = touches[s];
      const bool changed_surface = !geometry_.sameSurface(c.surface, surface_[x]);
      surface_[x] = c.surface;
      depth_[x] = c.surface >= 0 ? c.h : 0.0;
      if (c.surface >= 0) {
        max_penetration_ = std::max(max_penetration_, c.h);
        elastic_committed_ += 0.5 * p_.stiffness * c.h * c.h;
        if (c.surface >= wire_base_ && c.h > deepest_in_wire_.depth_m) {
          deepest_in_wire_ = {c.h, i, c.surface - wire_base_ - c_.retired};
        }
      }
      friction_force_[x].setZero();
      if (!friction_) continue;
      if (c.surface < 0 || changed_surface) stuck_[x] = 0;
      if (c.surface < 0) {
        // Elastic slip: a point that touches later starts from where it
        // was, carried with the surface.
        if (elastic_slip_)
          anchor_core_[x] = geometry_.rotWorldCore().transpose() * (p - core_.originWorld());
        continue;
      }
      const Eigen::Vector3d& n = c.n_world;
      // (Against the core material's velocity by the committed step's
      // scheme where that differs from the exact one: a point at rest
      // sticks, wire_types.hpp.)
      const Eigen::Vector3d v_rel =
          k.v_world.col(i) - k.coreVelocity(p, core_.velocityWorld(t, p), p_.stick_speed);
      const Eigen::Vector3d vh = v_rel - v_rel.dot(n) * n;
      if (elastic_slip_) {
        // The return map from the committed anchor and limit (stuck_ was
        // reset above on a new surface); a slip moves the anchor to where
        // the spring alone gives the returned force.
        const SlipReturn<3> r = returnToCone<3>(
            slipTrial(x, p, vh, n), slipLimit(x, c.surface, normalForce(c.h, v_rel.dot(n))));
        friction_force_[x] = r.force;
        stuck_[x] = !r.slipping;
        slow_[x] = vh.norm() < p_.stick_speed;
        if (r.slipping) {
          anchor_core_[x] = geometry_.rotWorldCore().transpose() *
                            (p + r.force / p_.stick_stiffness - core_.originWorld());
        }
        continue;
      }
      bool slipping;
      friction_force_[x] = friction(x, p, vh, n, normalForce(c.h, v_rel.dot(n)), slipping);
      if (stuck_[x] && slipping) {
        stuck_[x] = 0;  // the static limit was exceeded
      } else if (!stuck_[x] && vh.norm() < p_.stick_speed) {
        stuck_[x] = 1;  // slow enough: stick where it is
        anchor_core_[x] = geometry_.rotWorldCore().transpose() * (p - core_.originWorld());
      }
    }
  }
}

void Contact::appendHistory(std::vector<double>& out) const {
  for (int x = 0; x < c_.n * slots_; ++x) {
    out.push_back(surface_[x]);
    out.push_back(depth_[x]);
    if (friction_) {
      out.push_back(stuck_[x] + 2 * slow_[x]);  // (bit 1: slow, elastic slip)
      out.insert(out.end(), anchor_core_[x].data(), anchor_core_[x].data() + 3);
      out.insert(out.end(), friction_force_[x].data(), friction_force_[x].data() + 3);
    }
  }
  out.push_back(max_penetration_);
  out.push_back(elastic_committed_);
}

void Contact::shrink(const WireKinematics&) {
  // The last point sits at the port, away from the core: nothing to book.
  for (int x = (c_.n - 1) * slots_; x < c_.n * slots_; ++x) {
    surface_[x] = -1;
    depth_[x] = 0.0;
    if (friction_) {
      stuck_[x] = slow_[x] = 0;
      anchor_core_[x].setZero();
      friction_force_[x].setZero();
    }
  }
}

void Contact::retireFront(int k) {
  const std::size_t drop = static_cast<std::size_t>(k) * slots_;
  const std::size_t used = static_cast<std::size_t>(c_.n) * slots_;
  // What the retired slots held: their deepest penetration stays in the
  // run's figure, their springs' energy leaves the committed sums (the
  // model books it as the retired wire's).
  // (Point 0, the clamp, is in neither sum: the old point k, the new
  // clamp, leaves them too.)
  for (std::size_t x = slots_; x < std::min(drop + slots_, used); ++x) {
    retired_max_penetration_ = std::max(retired_max_penetration_, depth_[x]);
    const double e = 0.5 * p_.stiffness * depth_[x] * depth_[x];
    elastic_committed_ -= e;
    if (static_cast<int>(x / slots_) < carried_summed_) carried_elastic_ -= e;
  }
  carried_summed_ = std::max(1, carried_summed_ - k);
  // (Surface ids of the carried wire number the whole wire's segments: they
  // stay.)
  dropFront(surface_, drop, used, -1);
  dropFront(depth_, drop, used, 0.0);
  dropFront(friction_force_, drop, used, Eigen::Vector3d::Zero().eval());
  if (friction_) {
    dropFront(stuck_, drop, used, char{0});
    dropFront(anchor_core_, drop, used, Eigen::Vector3d::Zero().eval());
    dropFront(slow_, drop, used, char{0});
  }
  dropFront(trial_surface_, drop, used, -1);
  dropFront(trial_stuck_, drop, used, char{0});
  dropFront(trial_sign_, drop, used, static_cast<signed char>(1));
  dropFront(trial_releases_, drop, used, static_cast<signed char>(0));
  dropFront(trial_switches_, drop, used, static_cast<signed char>(0));
  if (deepest_in_wire_.point >= 0) {
    deepest_in_wire_.point -= k;
    deepest_in_wire_.segment = std::max(0, deepest_in_wire_.segment - k);
  }
  recheck_.valid = false;
  // The carried wire's segments are hashed anew, numbered from the new
  // front (in the order they were hashed: ascending).
  geometry_.forgetCarriedWire(c_.n);
}

void Contact::forgetCarriedSums() {
  carried_summed_ = 1;
  carried_max_penetration_ = carried_elastic_ = 0.0;
}

void Contact::restoreHistory(HistoryReader& in) {
  for (int x = 0; x < c_.n * slots_; ++x) {
    surface_[x] = static_cast<int>(in.next());
    depth_[x] = in.next();
    if (friction_) {
      const int flags = static_cast<int>(in.next());
      stuck_[x] = (flags & 1) != 0;
      slow_[x] = (flags & 2) != 0;
      for (int d = 0; d < 3; ++d) anchor_core_[x][d] = in.next();
      for (int d = 0; d < 3; ++d) friction_force_[x][d] = in.next();
    }
  }
  max_penetration_ = in.next();
  elastic_committed_ = in.next();
  recheck_.valid = false;
  forgetCarriedSums();
  // The carried wire may be another: hashed anew when next used.
  geometry_.forgetCarriedWire(0);
}

}  // namespace cws
