// Contact of the wire's mass points with the core and what it carries (the
// core body's cylinders and faces, the flanges, the wound wire): penalty
// springs normal to each surface and static/kinetic friction against the
// moving surface, the paper's eqs. (16)-(20), with a dashpot beside each
// spring (contact.damping_ratio; 1, the reference model). Each point keeps
// one slot per surface kind with its own contact, stick flag and anchor;
// stick and slip change only on accepted steps. What touches what (the
// surfaces, depths and normals) is ContactGeometry's (contact_geometry.hpp);
// this class holds the law and its state. SI units: m, m/s, N, N/m. See
// docs/MODEL.md, section "Contact and friction (eqs. 16-20)".
#pragma once

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <vector>

#include "coil_winding_sim/core/assembly/force_effect.hpp"
#include "coil_winding_sim/core/external_forces/contact_geometry.hpp"

namespace cws {

class Contact : public ForceEffect, public EffectHistory {
 public:
  Contact(const WireConstants& c, const Scene& s, const RotatingCore& core);

  const char* name() const override { return "contact"; }
  // New friction coefficients from the next evaluation on (validated by the
  // caller, Simulation::setFriction).
  void setFriction(double mu_static, double mu_kinetic) {
    p_.static_friction = mu_static;
    p_.kinetic_friction = mu_kinetic;
  }
  // The law, written once on the sink (contact_law.cpp).
  void addForces(ExplicitSink& s) const override { law(s); }
  void addForces(PlanarSink& s) const override { law(s); }
  void addForces(SpatialSink& s) const override { law(s); }
  // Newton steps: the surface each point touches, stick (with its anchor)
  // or slip stay frozen within one solve, set and rechecked per
  // formulation (contact_flags_planar.cpp, contact_flags_spatial.cpp;
  // elastic slip: the return map decides stick and slip at every
  // evaluation). Kinetic friction follows the trial sliding velocity (a
  // floor of the speed it is divided by, for a scene with no stick speed
  // [m/s]).
  static constexpr double kTinySlidingSpeed = 1e-12;
  void beginStep(const NewtonView& s0) override {
    if (s0.planar()) {
      beginPlanar(*s0.planar());
    } else {
      beginSpatial(*s0.spatial());
    }
  }
  bool recheck(const NewtonView& s) override {
    return s.planar() ? recheckPlanar(*s.planar()) : recheckSpatial(*s.spatial());
  }
  void commit(const AcceptedStep& step) override {
    if (step.newton) adoptFlags();
    commitAt(step.t, step.k);
  }
  void shrink(const WireKinematics& k) override;
  void retireFront(int k) override;
  // The deepest penetration of retired wire [m] (WireModel's snapshot).
  double retiredMaxPenetration() const { return retired_max_penetration_; }
  void setRetiredMaxPenetration(double h) { retired_max_penetration_ = h; }
  void appendHistory(std::vector<double>& out) const override;
  void restoreHistory(HistoryReader& in) override;
  // Energy in the normal springs at the last commit [J].
  EffectEnergy energy(const WireKinematics&) const override { return {elastic_committed_, 0.0}; }

  // With physics.wire_contact: the carried wire's poses in the core frame
  // (the model's, valid below c.first; kept by reference).
  void attachCarriedWire(const std::vector<Eigen::Vector3d>& p_core) {
    geometry_.attachCarriedWire(p_core);
  }
  // What touches what (contact_geometry.hpp).
  const ContactGeometry& geometry() const { return geometry_; }

  static constexpr int kWireSlots = ContactGeometry::kWireSlots;
  static constexpr int kMaxSlots = ContactGeometry::kMaxSlots;
  int slots() const { return slots_; }
  // At the last commit: is point i touching any surface, is it stuck on one.
  bool inContact(int i) const {
    for (int s = 0; s < slots_; ++s)
      if (surface_[i * slots_ + s] >= 0) return true;
    return false;
  }
  bool stuck(int i) const {
    if (!friction_) return false;
    for (int s = 0; s < slots_; ++s)
      if (stuck_[i * slots_ + s]) return true;
    return false;
  }
  // Is point i at rest on a surface at the last commit: stuck, or (elastic
  // slip) sliding slower than contact.stick_speed, as a point creeping in
  // the capstan zone does. Carried wire is judged by it (CarriedWire::decide):
  // the same points as stuck() under the stick_speed law.
  bool resting(int i) const {
    if (!friction_) return false;
    for (int s = 0; s < slots_; ++s) {
      const int x = i * slots_ + s;
      if (stuck_[x] || (elastic_slip_ && surface_[x] >= 0 && slow_[x])) return true;
    }
    return false;
  }
  // The surface of point i's slot s at the last commit (-1: none), and the
  // first id of the carried wire's segments (segment j of the whole wire,
  // retired points included: wireSurface() + j).
  int surface(int i, int s = 0) const { return surface_[i * slots_ + s]; }
  int wireSurface() const { return geometry_.wireBase(); }
  // Penetration [m] of point i's slot s at the last commit.
  double penetration(int i, int s = 0) const { return depth_[i * slots_ + s]; }
  // The fastest landing in the present implicit step's trial flags of a
  // point of the free span, at least `gap` points beyond the last point
  // that touched at the last commit (time t [s], kinematics k): its speed
  // relative to the core material then [m/s]; 0 when none landed (a span
  // the core strikes, ImplicitStepper; span_landing.cpp).
  double spanLandingSpeed(const WireKinematics& k, double t, int gap) const;
  // The present implicit step's trial flags of the core body's slot (tests).
  int trialSurface(int i, int s = 0) const { return trial_surface_[i * slots_ + s]; }
  bool trialStuck(int i, int s = 0) const { return friction_ && trial_stuck_[i * slots_ + s] != 0; }
  double stickSpeed() const { return p_.stick_speed; }  // [m/s]
  // Friction force on point i at the last commit, over its slots [N], world
  // frame.
  Eigen::Vector3d frictionForce(int i) const {
    Eigen::Vector3d f = Eigen::Vector3d::Zero();
    for (int s = 0; s < slots_; ++s) f += friction_force_[i * slots_ + s];
    return f;
  }
  // Deepest penetration over all points at the last commit [m].
  double maxPenetration() const { return max_penetration_; }
  // The integrated point deepest in carried wire at the last commit: its
  // penetration [m] (0: none), the point and the carried segment.
  struct WireDepth {
    double depth_m = 0.0;
    int point = -1, segment = -1;
  };
  const WireDepth& deepestInWire() const { return deepest_in_wire_; }

  // Normal force at penetration h [m] and speed v_n [m/s] away from the
  // surface [N], with its derivatives in h [N/m] and v_n [N s/m]: the
  // spring, with the dashpot if damped, never pulling. The dashpot grows
  // over the first kDashpotRamp of the wire radius of penetration, so that
  // the force does not jump by c v_n where a point first touches. (An
  // implicit step keeps an active contact's spring linear below h = 0.)
  struct NormalForce {
    double force, d_h, d_vn;
  };
  NormalForce normalLaw(double h, double v_n) const {
    const double k = p_.stiffness;
    if (c_normal_ == 0.0 || h <= 0.0) return {k * h, k, 0.0};
    const bool ramping = h < h_ramp_;
    const double c = ramping ? c_normal_ * h / h_ramp_ : c_normal_;
    const double f = k * h - c * v_n;
    if (f <= 0.0) return {0.0, 0.0, 0.0};
    return {f, ramping ? k - c_normal_ * v_n / h_ramp_ : k, -c};
  }
  // The normal dashpot's dissipation [W] over an implicit step of dt [s]
  // that ends at penetration h [m] under `law`, at the step's mean normal
  // speed (the change from the committed penetration of slot x) rather than
  // the end speed: a step across an impact it does not resolve ends at a
  // speed far from the step's mean (and rings under a method that damps
  // little), where c v_n^2 would book more than the impact's energy.
  double dashpotPower(const NormalForce& law, double h, int x, int surface, double dt) const {
    if (c_normal_ == 0.0 || h <= 0.0) return 0.0;
    const double h0 = geometry_.sameSurface(surface, surface_[x]) ? depth_[x] : 0.0;
    const double v_n = -(h - h0) / dt;
    // Clipped (never pulling): the dashpot takes the spring's force.
    if (law.force <= 0.0) return p_.stiffness * h * v_n;
    return -law.d_vn * v_n * v_n;
  }
  // The laws' parameters, for contact between free segments
  // (free_wire_contact.hpp): the penalty stiffness [N/m], mu_d, and the
  // points next to a point along the wire that never count as touching it.
  double stiffness() const { return p_.stiffness; }
  double kineticFriction() const { return friction_ ? p_.kinetic_friction : 0.0; }
  double staticFriction() const { return friction_ ? p_.static_friction : 0.0; }  // mu_s
  int skipPoints() const { return geometry_.skipPoints(); }

 private:
  template <class Sink>
  void law(Sink& s) const;
  void beginPlanar(const PlanarState& s0);
  bool recheckPlanar(const PlanarState& s);
  void beginSpatial(const SpatialState& s0);
  bool recheckSpatial(const SpatialState& s);
  // The Newton step's flags become the committed ones (before commitAt).
  void adoptFlags();
  void commitAt(double t, const WireKinematics& k);
  using Touch = ContactGeometry::Touch;
  static constexpr double kDashpotRamp = 1e-3;  // (normalLaw's ramp, in wire radii)
  double normalForce(double h, double v_n) const { return normalLaw(h, v_n).force; }
  // Tangential friction force on point i [N] given the committed stick state;
  // sets `slipping` when the stick spring would exceed mu_s N.
  Eigen::Vector3d friction(int i, const Eigen::Vector3d& p_world, const Eigen::Vector3d& vh_world,
                           const Eigen::Vector3d& n_world, double normal_force,
                           bool& slipping) const;

  // Elastic slip (contact.friction_law, elastic_slip.hpp): the limit [N]
  // of slot x touching `surface` at normal force N [N], mu_s N where it
  // stuck on that surface at the last commit, else mu_d N; and the trial
  // force of the stick spring to its committed anchor with its dashpot
  // against the sliding velocity vh_world [N].
  double slipLimit(int x, int surface, double normal_force) const {
    const bool held = stuck_[x] && geometry_.sameSurface(surface, surface_[x]);
    return (held ? std::max(p_.static_friction, p_.kinetic_friction) : p_.kinetic_friction) *
           normal_force;
  }
  Eigen::Vector3d slipTrial(int x, const Eigen::Vector3d& p_world, const Eigen::Vector3d& vh_world,
                            const Eigen::Vector3d& n_world) const {
    const Eigen::Vector3d delta =
        p_world - (core_.originWorld() + geometry_.rotWorldCore() * anchor_core_[x]);
    return -p_.stick_stiffness * (delta - delta.dot(n_world) * n_world) - c_stick_ * vh_world;
  }

  // Velocity of the core material at plane point x [m/s].
  Eigen::Vector2d planarSurfaceVelocity(const PlanarState& s, const Eigen::Vector2d& x) const;

  // Sums the carried points' penetration again from the first one on.
  void forgetCarriedSums();

  const WireConstants& c_;  // the model's: n grows with a supply
  ContactParams p_;
  const RotatingCore& core_;
  ContactGeometry geometry_;
  // The geometry's slot layout, read at every index: slots per point,
  // the flanges' slot, and the first surface id of the carried wire.
  const int slots_, flange_slot_, wire_base_;
  bool friction_;
  bool elastic_slip_ = false;  // contact.friction_law: elastic_slip
  // Dashpots of the normal and the stick spring [N s/m] (0: undamped), and
  // the penetration over which the normal one grows [m].
  double c_normal_ = 0.0, c_stick_ = 0.0, h_ramp_ = 0.0;
  // Per point and slot (index i * slots_ + s; planar scenes have one slot,
  // so there it is the point's index), committed: surface in contact (-1:
  // none); with friction the stick flag and the anchor in the core frame.
  std::vector<int> surface_;
  std::vector<char> stuck_;
  std::vector<Eigen::Vector3d> anchor_core_;
  std::vector<char> slow_;  // elastic slip: sliding below stick_speed at the last commit
  std::vector<Eigen::Vector3d> friction_force_;  // output only
  std::vector<double> depth_;                    // committed penetration [m]
  double max_penetration_ = 0.0;
  double retired_max_penetration_ = 0.0;  // of the retired slots [m]
  WireDepth deepest_in_wire_;
  double elastic_committed_ = 0.0;
  // The carried points' share of the two above, summed over points
  // 1..carried_summed_-1 in index order (carried points keep their
  // penetration, so a commit adds only the points carried since the last).
  int carried_summed_ = 1;
  double carried_max_penetration_ = 0.0, carried_elastic_ = 0.0;
  // Implicit steps' trial flags (capacity, per slot): surface, stick, anchor (core
  // frame) and slip direction (+1 / -1 along the surface tangent n x normal).
  std::vector<int> trial_surface_;
  std::vector<char> trial_stuck_;
  std::vector<Eigen::Vector3d> trial_anchor_core_;  // per slot of the integrated span, as below
  std::vector<signed char> trial_sign_;
  // 3-D: the world direction a slipping point slid in at the step's start,
  // or in which it began to slip (unit; zero: none yet). Per slot of the
  // integrated span (index (i - first) * slots_ + slot), as
  // recheck_touches_: sized for kReservedSpan points, grown on demand
  // (growSpan), as the Newton system is (issue 57: storage for 100,000
  // points).
  std::vector<Eigen::Vector3d> trial_slip_world_;
  static constexpr int kReservedSpan = 1024;
  template <class T>
  void growSpan(std::vector<T>& v, int points) const {
    const std::size_t need = static_cast<std::size_t>(points) * slots_;
    if (v.size() < need) v.resize(std::max(need, 2 * v.size()));
  }
  // How often a slot's stick broke within the present step.
  std::vector<signed char> trial_releases_;
  // 3-D: how often a slot's surface changed within the present step; from
  // kMaxSwitches on, the slot's law is clipped and a loss is no change
  // (recheckSpatial).
  std::vector<signed char> trial_switches_;
  static constexpr int kMaxSwitches = 2;
  // 3-D: the surfaces the last recheck found per slot, at time t for points
  // first..n-1 (valid until the step's commit reads them, a new step or a
  // restore): an accepted step's end state is its last recheck's. Per slot
  // of that span (index (i - first) * slots_ + slot).
  struct RecheckAt {
    bool valid = false;
    double t = 0.0;  // [s]
    int first = 0, n = 0;
  };
  std::vector<Touch> recheck_touches_;
  RecheckAt recheck_;
};

}  // namespace cws
