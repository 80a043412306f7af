// The flags a planar Newton step freezes within one solve (the surface
// each point touches, stick with its anchor, the sliding direction a
// reversal is judged against), set at the step's start and rechecked after
// a converged solve (docs/MODEL.md, "Implicit integration"); the law is
// contact_law.cpp's. Planar scenes have one slot per point (flanges and
// wire contact are 3-D), so a slot's index is its point's.
#include <cmath>

#include "coil_winding_sim/core/assembly/planar_assembly.hpp"
#include "coil_winding_sim/core/external_forces/contact.hpp"

namespace cws {

Eigen::Vector2d Contact::planarSurfaceVelocity(const PlanarState& s,
                                               const Eigen::Vector2d& x) const {
  return s.plane.vectorToPlane(s.carried.velocity(s.plane.toWorld(x)));
}

void Contact::beginPlanar(const PlanarState& s0) {
  growSpan(trial_anchor_core_, s0.n - s0.first);
  geometry_.place(s0.t);
  for (int i = s0.first; i < s0.n; ++i) {
    trial_surface_[i] = surface_[i];
    if (!friction_) continue;
    trial_stuck_[i] = stuck_[i];
    trial_anchor_core_[i - s0.first] = anchor_core_[i];
    trial_releases_[i] = 0;
    // A slipping point keeps the direction it slides in.
    trial_sign_[i] = 1;
    Eigen::Vector2d nrm;
    double h;
    Eigen::Matrix2d dn;
    const Eigen::Vector2d x = s0.x.col(i);
    if (surface_[i] >= 0 && geometry_.planarSurface(s0, surface_[i], x, nrm, h, dn)) {
      const double vt = (s0.v.col(i) - planarSurfaceVelocity(s0, x)).dot(planar::perp(nrm));
      trial_sign_[i] = vt < 0.0 ? -1 : 1;
    }
  }
}

bool Contact::recheckPlanar(const PlanarState& s) {
  growSpan(trial_anchor_core_, s.n - s.first);
  geometry_.place(s.t);
  bool changed = false;
  for (int i = s.first; i < s.n; ++i) {
    const Eigen::Vector2d x = s.x.col(i);
    double h_world;
    Eigen::Vector3d n_world;
    const int surface = geometry_.touch(s.plane.toWorld(x), h_world, n_world);
    Eigen::Vector2d nrm;
    double h = 0.0;
    Eigen::Matrix2d dn;
    const bool on = surface >= 0 && geometry_.planarSurface(s, surface, x, nrm, h, dn);
    const bool fresh = surface != trial_surface_[i];
    if (fresh) {
      trial_surface_[i] = surface;
      trial_stuck_[i] = 0;
      changed = true;
    }
    // (Elastic slip decides stick and slip within the solve.)
    if (!on || !friction_ || elastic_slip_) continue;
    const Eigen::Vector2d tan = planar::perp(nrm);
    const Eigen::Vector2d r = s.v.col(i) - planarSurfaceVelocity(s, x);
    const double vt = r.dot(tan);
    if (trial_stuck_[i]) {
      // Stick holds while the spring (and its dashpot) stays within mu_s N.
      const Eigen::Vector2d delta =
          x - s.plane.toPlane(core_.originWorld() +
                              geometry_.rotWorldCore() * trial_anchor_core_[i - s.first]);
      const double pull = p_.stick_stiffness * delta.dot(tan) + c_stick_ * vt;
      if (std::abs(pull) > p_.static_friction * normalForce(h, r.dot(nrm))) {
        trial_stuck_[i] = 0;
        trial_sign_[i] = pull < 0.0 ? -1 : 1;
        ++trial_releases_[i];
        changed = true;
      }
    } else if (p_.static_friction > 0.0 && trial_releases_[i] < 2 &&
               (fresh ? std::abs(vt) < p_.stick_speed : trial_sign_[i] * vt < p_.stick_speed)) {
      // Slow enough, or the sliding would have reversed within the step
      // (kinetic friction stops a point, it does not push it back): stick
      // where it is (as a commit of contact.cpp does). Without static
      // friction a stuck point would slip at once: it keeps sliding. A
      // point whose stick broke twice in this step keeps slipping, as in
      // 3-D: with almost no normal force (a point that barely touches) the
      // dashpot's pull alone passes mu_s N, and stick and slip would take
      // turns without end.
      trial_stuck_[i] = 1;
      trial_anchor_core_[i - s.first] =
          geometry_.rotWorldCore().transpose() * (s.plane.toWorld(x) - core_.originWorld());
      changed = true;
    } else if (fresh) {
      trial_sign_[i] = vt < 0.0 ? -1 : 1;
    }
  }
  return changed;
}

void Contact::adoptFlags() {
  // Elastic slip: the commit decides from the committed state, as the solve
  // did (a surface adopted here would hide that it is new).
  if (elastic_slip_) return;
  for (int x = c_.first * slots_; x < c_.n * slots_; ++x) {
    surface_[x] = trial_surface_[x];
    if (!friction_) continue;
    stuck_[x] = trial_stuck_[x];
    anchor_core_[x] = trial_anchor_core_[x - c_.first * slots_];
  }
}

}  // namespace cws
