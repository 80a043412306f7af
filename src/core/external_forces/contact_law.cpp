// Contact and friction against the moving core, written once on the force
// sink (force_sink.hpp) for every integrator: the penalty spring normal to
// each surface with its dashpot, the stick spring to an anchor and kinetic
// friction (eqs. 16-20), with their Jacobian blocks where a Newton sink
// wants them. The integrators differ only in who decides the flags:
//   explicit steps   the surfaces (ContactGeometry::touchAll), stick and
//                    slip at every evaluation, from the committed state;
//   Newton steps     the solve's frozen flags (trial surface, stick and
//                    anchor), set by beginStep and rechecked after a
//                    converged solve (contact_flags_planar.cpp,
//                    contact_flags_spatial.cpp).
// Kinetic friction opposes the sliding velocity as it is; a 3-D Newton
// step divides it by at least the stick speed, where a converged solve
// sticks the point, and a planar one keeps its sign frozen. A planar sink
// maps the world's forces and blocks to the plane.
#include <algorithm>
#include <cmath>

#include "coil_winding_sim/core/external_forces/contact.hpp"
#include "coil_winding_sim/core/external_forces/elastic_slip.hpp"

namespace cws {

template <class Sink>
void Contact::law(Sink& s) const {
  constexpr bool kNewton = Sink::kFlagsFrozen;
  const double t = s.t();
  geometry_.place(t);
  // (A Newton step hashes the carried wire at its start, beginSpatial.)
  if constexpr (!kNewton) geometry_.syncCarriedWire();
  const Eigen::Matrix3d id = Eigen::Matrix3d::Identity();
  // d u / d p of the core's material in a Newton step (the Jacobian's
  // blocks are a Newton sink's alone).
  const Eigen::Matrix3d* du = nullptr;
  if constexpr (kNewton) du = &s.carried().g_world;
  const int base = s.first() * slots_;  // the span-indexed arrays' first slot
  Touch found[kMaxSlots];
  for (int i = s.first(); i < s.n(); ++i) {
    const Eigen::Vector3d p = s.p(i);
    if constexpr (!kNewton) {
      if (!geometry_.touchAll(i, p, &surface_[i * slots_], found)) continue;
    }
    // The Jacobian's blocks only where the evaluation wants them (most
    // evaluations are of the forces alone).
    const bool jacobian = s.jacobian(i);
    for (int slot = 0; slot < slots_; ++slot) {
      const int x = i * slots_ + slot;
      int surface;
      Eigen::Vector3d nrm;
      double h;
      Eigen::Matrix3d dn;
      if constexpr (kNewton) {
        surface = trial_surface_[x];
        if (surface < 0) continue;
        if (!geometry_.spatialSurface(i, surface, p, nrm, h, jacobian ? &dn : nullptr)) continue;
        // A slot that turned at every recheck: the law clipped, as
        // explicit steps take it (recheckSpatial).
        if (h <= 0.0 && trial_switches_[x] >= kMaxSwitches) continue;
      } else {
        surface = found[slot].surface;
        if (surface < 0) continue;
        nrm = found[slot].n_world;
        h = found[slot].h;
      }
      // The core material's velocity (Newton steps: as the scheme gives
      // it, one_leg_step.hpp) and the relative velocity r = v - u, its
      // normal part and the sliding velocity vh = P_n r.
      Eigen::Vector3d u;
      if constexpr (kNewton) {
        u = s.carried().velocity(p);
      } else {
        u = core_.velocityWorld(t, p);
      }
      const Eigen::Vector3d r = s.v(i) - u;
      const double rn = r.dot(nrm);
      const Eigen::Vector3d vh = r - rn * nrm;
      // Its derivative in p (through n and u), for the laws that use it.
      const Eigen::Matrix3d pn = id - nrm * nrm.transpose();
      auto dvhDp = [&] {
        return Eigen::Matrix3d(-pn * *du - (nrm * (r.transpose() * dn) + rn * dn));
      };
      // Normal spring k h n, kept linear in a Newton solve while the
      // contact is active; with its dashpot N = k h - c_n r . n, never
      // pulling.
      const NormalForce law = normalLaw(h, rn);
      const double normal = law.force;
      Eigen::RowVector3d dnormal_dp = Eigen::RowVector3d::Zero(),
                         dnormal_dv = Eigen::RowVector3d::Zero();
      if (jacobian) dnormal_dp = -law.d_h * nrm.transpose();
      if (c_normal_ > 0.0) {
        if constexpr (kNewton) {
          s.addPower(dashpotPower(law, h, x, surface, s.dt()), 0.0);
          if (jacobian) {
            // v_n = r . n with r = v - u(p).
            dnormal_dp += law.d_vn * (r.transpose() * dn - nrm.transpose() * *du);
            dnormal_dv = law.d_vn * nrm.transpose();
            s.addPointDamping(i, nrm * dnormal_dv);
          }
        } else {
          // The dashpot's part (with the spring's where it would pull)
          // dissipates, as friction does.
          const Eigen::Vector3d f_d = (normal - p_.stiffness * h) * nrm;
          s.addPower(f_d.dot(u), 0.0);
          s.addDissipation(i, f_d);
        }
      }
      Eigen::Vector3d f = normal * nrm;
      Eigen::Matrix3d kp;
      if (jacobian) kp = nrm * dnormal_dp + normal * dn;
      Eigen::Vector3d ft = Eigen::Vector3d::Zero();
      if (friction_ && elastic_slip_) {
        // Elastic slip: the stick spring's trial force from the committed
        // anchor, returned onto the cone mu N (elastic_slip.hpp), with the
        // consistent tangent d f = S d f_trial + dir mu d N.
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
          s.addPointDamping(i, cv);
        }
      } else if (friction_) {
        // Stick: the tangential spring to the anchor (and its dashpot
        // against the sliding velocity). Explicit steps break it where it
        // passes mu_s N; a Newton solve keeps its flag (the recheck breaks
        // it).
        bool slipping = true;
        if (kNewton ? trial_stuck_[x] : stuck_[x]) {
          const Eigen::Vector3d& anchor_core =
              kNewton ? trial_anchor_core_[x - base] : anchor_core_[x];
          const Eigen::Vector3d delta =
              p - (core_.originWorld() + geometry_.rotWorldCore() * anchor_core);
          const double dnn = delta.dot(nrm);
          ft = -p_.stick_stiffness * (delta - dnn * nrm);
          if (c_stick_ > 0.0) ft -= c_stick_ * vh;
          slipping = !kNewton && !(ft.norm() <= p_.static_friction * normal);
          if (jacobian) {
            kp += -p_.stick_stiffness *
                  (id - nrm * (nrm.transpose() + delta.transpose() * dn) - dnn * dn);
            if (c_stick_ > 0.0) {
              kp -= c_stick_ * dvhDp();
              s.addPointDamping(i, -c_stick_ * pn);
            }
          }
        }
        if (slipping && !kNewton) {
          // Slip in an explicit step: mu_d N against the sliding velocity.
          const double speed = vh.norm();
          ft = speed == 0.0 ? Eigen::Vector3d::Zero().eval()
                            : ((-p_.kinetic_friction * normal / speed) * vh).eval();
        } else if (slipping && s.slideAxis()) {
          // Slip in a planar Newton step: the sliding has one direction
          // along the surface, tan = a x n (a the plane's normal), and its
          // sign stays frozen within the solve as the other flags do (the
          // recheck sticks a point whose sliding reversed).
          const Eigen::Vector3d& a = *s.slideAxis();
          const Eigen::Vector3d tan = a.cross(nrm);
          const double mu = p_.kinetic_friction * trial_sign_[x];
          ft = -mu * normal * tan;
          if (jacobian) {
            Eigen::Matrix3d a_cross;
            a_cross << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
            kp += -mu * (tan * dnormal_dp + normal * (a_cross * dn));
            s.addPointDamping(i, -mu * tan * dnormal_dv);
          }
        } else if (slipping) {
          // Slip in a 3-D Newton step: mu_d N against vh, u = G (p - o) the
          // core's; with its derivatives in p (through N, n and u) and v.
          // Below the stick speed the direction vh / |vh| is replaced by
          // vh / stick_speed: a converged solve with a point sliding that
          // slowly sticks it (the recheck), so no accepted step uses that
          // part, and Newton does not chase the kink of vh / |vh| at rest.
          const double speed = vh.norm();
          // (Without static friction nothing sticks: the law is kept whole.)
          const double floor = p_.static_friction > 0.0 ? p_.stick_speed : 0.0;
          const double scale = std::max({speed, floor, kTinySlidingSpeed});
          const Eigen::Vector3d dir = vh / scale;
          ft = -p_.kinetic_friction * normal * dir;
          if (jacobian) {
            const Eigen::Matrix3d proj = (speed >= scale ? id - dir * dir.transpose() : id) / scale;
            kp += -p_.kinetic_friction * (dir * dnormal_dp + normal * proj * dvhDp());
            s.addPointDamping(i, -p_.kinetic_friction * (normal * proj * pn + dir * dnormal_dv));
          }
        }
      }
      if (friction_) {
        // Friction power -f_t . (v - u), counted as dissipated (also what a
        // stick spring holds; f_t is tangential, so f_t . vh = f_t . (v - u)).
        f += ft;
        s.addPower(ft.dot(u), 0.0);
      }
      s.addPointForce(i, f, ft);
      if (jacobian) s.addPointStiffness(i, kp);
      // The moving surface does work on the wire (at its exact velocity).
      if constexpr (kNewton) {
        s.addPower(0.0, f.dot(s.carried().exactVelocity(p)));
      } else {
        s.addPower(0.0, f.dot(u));
      }
    }
  }
}
template void Contact::law(ExplicitSink&) const;
template void Contact::law(PlanarSink&) const;
template void Contact::law(SpatialSink&) const;

}  // namespace cws
