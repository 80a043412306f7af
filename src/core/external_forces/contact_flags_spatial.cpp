// The flags a 3-D Newton step freezes within one solve, set at the step's
// start and rechecked after a converged solve, as contact_flags_planar.cpp
// does in the plane; the law is contact_law.cpp's. The direction a point
// slid in at the step's start tells when the sliding reversed within the
// step (then the point sticks).
#include <algorithm>
#include <cmath>

#include "coil_winding_sim/core/assembly/spatial_assembly.hpp"
#include "coil_winding_sim/core/base/quaternion.hpp"
#include "coil_winding_sim/core/external_forces/contact.hpp"
#include "coil_winding_sim/core/external_forces/elastic_slip.hpp"

namespace cws {

void Contact::beginSpatial(const SpatialState& s0) {
  recheck_.valid = false;
  geometry_.place(s0.t);
  geometry_.syncCarriedWire();
  growSpan(trial_slip_world_, s0.n - s0.first);
  growSpan(trial_anchor_core_, s0.n - s0.first);
  const int base = s0.first * slots_;  // the span-indexed arrays' first slot
  for (int x = s0.first * slots_; x < s0.n * slots_; ++x) {
    trial_surface_[x] = surface_[x];
    trial_switches_[x] = 0;
    if (!friction_) continue;
    trial_stuck_[x] = stuck_[x];
    trial_anchor_core_[x - base] = anchor_core_[x];
    // The direction a slipping point slides in at the step's start: a
    // sliding that turns against it within the step sticks the point.
    trial_slip_world_[x - base].setZero();
    trial_releases_[x] = 0;
    Eigen::Vector3d nrm;
    double h;
    const int i = x / slots_;
    const Eigen::Vector3d p = s0.p.col(i);
    if (surface_[x] >= 0 && geometry_.spatialSurface(i, surface_[x], p, nrm, h, nullptr)) {
      const Eigen::Vector3d v_rel = s0.v.col(i) - s0.carried.velocity(p);
      const Eigen::Vector3d vh = v_rel - v_rel.dot(nrm) * nrm;
      if (vh.norm() > 0.0) trial_slip_world_[x - base] = vh.normalized();
    }
  }
}

bool Contact::recheckSpatial(const SpatialState& s) {
  geometry_.place(s.t);
  bool changed = false;
  Touch touches[kMaxSlots];
  growSpan(trial_slip_world_, s.n - s.first);
  growSpan(trial_anchor_core_, s.n - s.first);
  growSpan(recheck_touches_, s.n - s.first);
  const int base = s.first * slots_;  // the span-indexed arrays' first slot
  for (int i = s.first; i < s.n; ++i) {
    const Eigen::Vector3d p = s.p.col(i);
    geometry_.touchAll(i, p, &trial_surface_[i * slots_], touches);
    std::copy(touches, touches + slots_, &recheck_touches_[(i - s.first) * slots_]);
    for (int slot = 0; slot < slots_; ++slot) {
      const int x = i * slots_ + slot;
      // (touchAll's depth and normal are spatialSurface's for the surface
      // it found: the nearest segment of a run, the deepest cylinder.)
      const int surface = touches[slot].surface;
      const Eigen::Vector3d& nrm = touches[slot].n_world;
      const double h = touches[slot].h;
      const bool on = surface >= 0;
      // Another segment of the same run of carried wire is the same
      // surface (the solve already took the nearest of its neighbours).
      const bool fresh = !geometry_.sameSurface(surface, trial_surface_[x]);
      // A surface found and lost again within the step (a point grazing
      // it: on, its spring pushes the point out; off, nothing holds it) turns
      // at every recheck, down to steps of 1e-8 s. After kMaxSwitches
      // changes the slot keeps its surface with the law clipped (no force
      // where the point is off it, contact_law.cpp), which is the penalty law
      // itself: a loss is no change, a surface found is taken. The commit
      // takes the surfaces the geometry finds at the step's end
      // (docs/history/2026-12-06-contact-that-turns-at-every-recheck.md).
      if (fresh && trial_switches_[x] >= kMaxSwitches && surface < 0) continue;
      if (fresh && trial_switches_[x] < kMaxSwitches) ++trial_switches_[x];
      trial_surface_[x] = surface;
      if (fresh) {
        trial_stuck_[x] = 0;
        changed = true;
        s.flagChangedAt(i);
      }
      // (Elastic slip decides stick and slip within the solve.)
      if (!on || !friction_ || elastic_slip_) continue;
      const Eigen::Vector3d v_rel = s.v.col(i) - s.carried.velocity(p);
      const Eigen::Vector3d vh = v_rel - v_rel.dot(nrm) * nrm;
      const double speed = vh.norm();
      if (trial_stuck_[x]) {
        // Stick holds while the spring (and its dashpot) stays within mu_s N.
        const Eigen::Vector3d delta =
            p - (core_.originWorld() + geometry_.rotWorldCore() * trial_anchor_core_[x - base]);
        const Eigen::Vector3d pull =
            p_.stick_stiffness * (delta - delta.dot(nrm) * nrm) + c_stick_ * vh;
        if (pull.norm() > p_.static_friction * normalForce(h, v_rel.dot(nrm))) {
          trial_stuck_[x] = 0;
          trial_slip_world_[x - base] = pull.normalized();
          ++trial_releases_[x];
          changed = true;
          s.flagChangedAt(i);
        }
        continue;
      }
      // Slow enough, or the sliding reversed against the direction it had
      // at the step's start (kinetic friction stops a point, it does not
      // push it back): stick where it is (as a commit of contact.cpp does).
      // A point whose stick broke twice in this step keeps slipping: with
      // almost no normal force (a point grazing a second surface in a
      // corner) stick and slip would take turns without end.
      const Eigen::Vector3d& dir = trial_slip_world_[x - base];
      const bool known = !fresh && dir.squaredNorm() > 0.0;
      if (p_.static_friction > 0.0 && trial_releases_[x] < 2 &&
          (speed < p_.stick_speed || (known && vh.dot(dir) < p_.stick_speed))) {
        trial_stuck_[x] = 1;
        trial_anchor_core_[x - base] =
            geometry_.rotWorldCore().transpose() * (p - core_.originWorld());
        changed = true;
        s.flagChangedAt(i);
      } else if (!known && speed > 0.0) {
        trial_slip_world_[x - base] = vh / speed;
      }
    }
  }
  recheck_ = {true, s.t, s.first, s.n};
  return changed;
}

}  // namespace cws
