// Contact and friction in the 3-D implicit formulation: the same penalty
// springs, stick spring and static/kinetic friction as contact.cpp, with
// their Jacobian blocks, and the flags an implicit step freezes within one
// Newton solve and rechecks after it, as contact_planar.cpp does in the
// plane. Kinetic friction opposes the trial sliding velocity, as in the
// explicit model (its direction is not frozen: in 3-D it turns); the
// direction a point slid in at the step's start tells when the sliding
// reversed within the step (then the point sticks).
#include <algorithm>
#include <cmath>

#include "coil_winding_sim/core/assembly/spatial_assembly.hpp"
#include "coil_winding_sim/core/base/quaternion.hpp"
#include "coil_winding_sim/core/external_forces/contact.hpp"
#include "coil_winding_sim/core/external_forces/elastic_slip.hpp"

namespace cws {

void Contact::addSpatial(const SpatialState& s, SpatialAssembly& a) const {
  geometry_.place(s.t);
  const Eigen::Matrix3d id = Eigen::Matrix3d::Identity();
  for (int x = s.first * slots_; x < s.n * slots_; ++x) {
    const int surface = trial_surface_[x];
    if (surface < 0) continue;
    const int i = x / slots_;
    const Eigen::Vector3d p = s.p.col(i);
    // The Jacobian's blocks only where the evaluation wants them (most
    // evaluations are of the forces alone).
    const bool jacobian = a.wantsJacobianAt(i);
    Eigen::Vector3d nrm;
    double h;
    Eigen::Matrix3d dn;
    if (!geometry_.spatialSurface(i, surface, p, nrm, h, jacobian ? &dn : nullptr)) continue;
    // A slot that turned at every recheck: the law clipped, as explicit
    // steps take it (recheckSpatial).
    if (h <= 0.0 && trial_switches_[x] >= kMaxSwitches) continue;
    // The core's velocity as the scheme gives it (one_leg_step.hpp), and
    // the relative velocity r = v - u with its normal part.
    const Eigen::Vector3d u = s.carried.velocity(p);
    const Eigen::Vector3d r = s.v.col(i) - u;
    const double rn = r.dot(nrm);
    const Eigen::Matrix3d& du = s.carried.g_world;
    // The sliding velocity vh = P_n r and its derivative in p (through n and
    // u), for the laws that use it.
    const Eigen::Matrix3d pn = id - nrm * nrm.transpose();
    auto dvhDp = [&] { return Eigen::Matrix3d(-pn * du - (nrm * (r.transpose() * dn) + rn * dn)); };
    // Normal spring k h n, kept linear while the contact is active; with its
    // dashpot, N = k h - c_n r . n, never pulling.
    const NormalForce law = normalLaw(h, rn);
    const double normal = law.force;
    Eigen::RowVector3d dnormal_dp = Eigen::RowVector3d::Zero(),
                       dnormal_dv = Eigen::RowVector3d::Zero();
    if (jacobian) dnormal_dp = -law.d_h * nrm.transpose();
    if (c_normal_ > 0.0) {
      a.power_dissipated += dashpotPower(law, h, x, surface, s.dt);
      if (jacobian) {
        // v_n = r . n with r = v - u(p).
        dnormal_dp += law.d_vn * (r.transpose() * dn - nrm.transpose() * du);
        dnormal_dv = law.d_vn * nrm.transpose();
        a.addDampingPP(i, i, nrm * dnormal_dv);
      }
    }
    Eigen::Vector3d f = normal * nrm;
    Eigen::Matrix3d kp;
    if (jacobian) kp = nrm * dnormal_dp + normal * dn;
    if (friction_) {
      Eigen::Vector3d ft = Eigen::Vector3d::Zero();
      if (elastic_slip_) {
        // Elastic slip: the stick spring's trial force from the committed
        // anchor, returned onto the cone mu N (elastic_slip.hpp), with the
        // consistent tangent d f = S d f_trial + dir mu d N.
        const Eigen::Vector3d vh = r - rn * nrm;
        const double mu = slipLimit(x, surface, 1.0);
        const SlipReturn<3> ret = returnToCone<3>(slipTrial(x, p, vh, nrm), mu * normal);
        ft = ret.force;
        if (jacobian) {
          const Eigen::Vector3d delta =
              p - (core_.originWorld() + geometry_.rotWorldCore() * anchor_core_[x]);
          const double dnn = delta.dot(nrm);
          Eigen::Matrix3d dtrial_dp =
              -p_.stick_stiffness *
              (id - nrm * (nrm.transpose() + delta.transpose() * dn) - dnn * dn);
          Eigen::Matrix3d dtrial_dv = Eigen::Matrix3d::Zero();
          if (c_stick_ > 0.0) {
            dtrial_dp -= c_stick_ * dvhDp();
            dtrial_dv = -c_stick_ * pn;
          }
          const Eigen::Matrix3d scale = ret.scale();
          kp += scale * dtrial_dp;
          Eigen::Matrix3d cv = scale * dtrial_dv;
          if (ret.slipping) {
            kp += mu * ret.dir * dnormal_dp;
            cv += mu * ret.dir * dnormal_dv;
          }
          a.addDampingPP(i, i, cv);
        }
      } else if (trial_stuck_[x]) {
        // Stick: the spring to the anchor, its tangential part (and its
        // dashpot against the sliding velocity vh = P_n r).
        const Eigen::Vector3d delta =
            p - (core_.originWorld() +
                 geometry_.rotWorldCore() * trial_anchor_core_[x - s.first * slots_]);
        const double dnn = delta.dot(nrm);
        ft = -p_.stick_stiffness * (delta - dnn * nrm);
        if (jacobian) {
          kp += -p_.stick_stiffness *
                (id - nrm * (nrm.transpose() + delta.transpose() * dn) - dnn * dn);
        }
        if (c_stick_ > 0.0) {
          ft -= c_stick_ * (r - rn * nrm);
          if (jacobian) {
            kp -= c_stick_ * dvhDp();
            a.addDampingPP(i, i, -c_stick_ * pn);
          }
        }
      } else {
        // Slip: mu_d N against the sliding velocity vh = P_n (v - u),
        // u = G (p - o) the core's; with its derivatives in p
        // (through N, n and u) and v. Below the stick speed the direction
        // vh / |vh| is replaced by vh / stick_speed: a converged solve with
        // a point sliding that slowly sticks it (recheckSpatial), so
        // no accepted step uses that part, and Newton does not chase the
        // kink of vh / |vh| at rest.
        const Eigen::Vector3d vh = r - rn * nrm;
        const double speed = vh.norm();
        // (Without static friction nothing sticks: the law is kept whole.)
        const double floor = p_.static_friction > 0.0 ? p_.stick_speed : 0.0;
        const double scale = std::max({speed, floor, kTinySlidingSpeed});
        const Eigen::Vector3d dir = vh / scale;
        ft = -p_.kinetic_friction * normal * dir;
        if (jacobian) {
          const Eigen::Matrix3d proj = (speed >= scale ? id - dir * dir.transpose() : id) / scale;
          kp += -p_.kinetic_friction * (dir * dnormal_dp + normal * proj * dvhDp());
          a.addDampingPP(i, i, -p_.kinetic_friction * (normal * proj * pn + dir * dnormal_dv));
        }
      }
      f += ft;
      a.f_dissipative.col(i) += ft;
      a.power_dissipated += ft.dot(u);
    }
    a.addForce(i, f);
    if (jacobian) a.addStiffnessPP(i, i, kp);
    // The moving surface does work on the wire (at its exact velocity).
    a.power_external += f.dot(s.carried.exactVelocity(p));
  }
}

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
      // where the point is off it, addSpatial), which is the penalty law
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
