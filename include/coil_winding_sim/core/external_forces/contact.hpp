// Contact of the wire's mass points with the core and what it carries (the
// core body's cylinders and faces, the flanges, the wound wire): penalty
// springs normal to each surface and static/kinetic friction against the
// moving surface, the paper's eqs. (16)-(20), with a dashpot beside each
// spring (contact.damping_ratio; 1, the reference model). Each point keeps
// one slot per surface kind with its own contact, stick flag and anchor;
// stick and slip change only on accepted steps. SI units: m, m/s, N, N/m.
// See docs/MODEL.md, section "Contact and friction (eqs. 16-20)".
#pragma once

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <vector>

#include "coil_winding_sim/core/assembly/force_effect.hpp"
#include "coil_winding_sim/core/external_forces/carried_wire_index.hpp"
#include "coil_winding_sim/core/machine/rotating_core.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

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
  // The law is written per formulation: explicit (contact.cpp), planar
  // (contact_planar.cpp) and 3-D (contact_spatial.cpp).
  void addForces(ExplicitSink& s) const override { addExplicit(s.t(), s.kinematics(), s.forces()); }
  void addForces(PlanarSink& s) const override { addPlanar(s.state(), s.assembly()); }
  void addForces(SpatialSink& s) const override { addSpatial(s.state(), s.assembly()); }
  // Newton steps: the surface each point touches, stick (with its anchor)
  // or slip (with its direction) stay frozen within one solve (elastic
  // slip: the return map decides stick and slip at every evaluation). In
  // 3-D kinetic friction follows the trial sliding velocity (a floor of the
  // speed it is divided by, for a scene with no stick speed [m/s]).
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
  void attachCarriedWire(const std::vector<Eigen::Vector3d>& p_core) { carried_p_core_ = &p_core; }

  // Slots per point: the core body, a flange, and the wire runs (a point
  // in a disordered coil can rest on four wires at once).
  static constexpr int kWireSlots = 4;
  static constexpr int kMaxSlots = 2 + kWireSlots;
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
  // the capstan zone does. Carried wire is judged by it (wound_wire.cpp):
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
  int wireSurface() const { return wire_base_; }
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
    const double h0 = sameSurface(surface, surface_[x]) ? depth_[x] : 0.0;
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
  int skipPoints() const { return skip_points_; }

 private:
  void addExplicit(double t, const WireKinematics& k, WireForces& f) const;
  void addPlanar(const PlanarState& s, PlanarAssembly& a) const;
  void addSpatial(const SpatialState& s, SpatialAssembly& a) const;
  void beginPlanar(const PlanarState& s0);
  bool recheckPlanar(const PlanarState& s);
  void beginSpatial(const SpatialState& s0);
  bool recheckSpatial(const SpatialState& s);
  // The Newton step's flags become the committed ones (before commitAt).
  void adoptFlags();
  void commitAt(double t, const WireKinematics& k);
  // Places the cylinder axes and faces in the world at time t, once per
  // evaluation.
  void placeSurfaces(double t) const;
  // Deepest surface of the core body touching point p (as placed): its
  // index (cylinders, then faces; -1 if none), the penetration [m] and the
  // outward normal.
  int touch(const Eigen::Vector3d& p_world, double& h, Eigen::Vector3d& n_world) const;
  // Every surface touching point i at p (as placed), one per slot (surface
  // -1: none); the wire runs go to the slots whose surfaces in `ref` (the
  // point's committed or trial slots) they continue. False: none touches.
  struct Touch {
    int surface = -1;
    double h = 0.0;
    Eigen::Vector3d n_world = Eigen::Vector3d::Zero();
  };
  bool touchAll(int i, const Eigen::Vector3d& p_world, const int* ref, Touch* out) const;
  // Is a point at r_world from the core's origin, `along` [m] along the
  // core axis, within the flanges' reach from the axis?
  bool withinFlangeReach(const Eigen::Vector3d& r_world, double along) const {
    return (r_world - along * core_.axisWorld()).norm() <= flange_radius_;
  }
  // The carried wire's runs touching point i (core-frame position), deepest
  // first, at most kMaxRuns; returns how many.
  static constexpr int kMaxRuns = 8;
  int touchWire(int i, const Eigen::Vector3d& p_core, Touch* runs) const;
  // Squared distance [m^2] of p_core from carried segment j (core frame),
  // the offset from the segment's nearest point (not normalized), and
  // whether that point is inside the segment (else at an end).
  // (Inline: every query takes a few.)
  double segmentOffset(int j, const Eigen::Vector3d& p_core, Eigen::Vector3d& offset_core,
                       bool& inside) const {
    const Eigen::Vector3d& from = (*carried_p_core_)[j];
    const Eigen::Vector3d& d = segment_dir_core_[j];
    const double s = (p_core - from).dot(d) / segment_length2_[j];
    inside = s > 0.0 && s < 1.0;
    offset_core = p_core - (from + std::clamp(s, 0.0, 1.0) * d);
    return offset_core.squaredNorm();
  }
  // Segments point i may touch: carried (both ends below c.first), and not
  // its neighbours along the wire. Largest such j (-1: none).
  int lastWireSegment(int i) const { return std::min(c_.first - 2, i - 1 - skip_points_); }
  // Is `a` the same surface as `b` for stick (a run of the carried wire
  // counts as one)?
  bool sameSurface(int a, int b) const {
    if (a == b) return true;
    return a >= wire_base_ && b >= wire_base_ && std::abs(a - b) <= kSameRun;
  }
  static constexpr int kSameRun = 2;
  // Hashes the carried segments not yet hashed (all again after a release).
  void syncCarriedWire() const;
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
    const bool held = stuck_[x] && sameSurface(surface, surface_[x]);
    return (held ? std::max(p_.static_friction, p_.kinetic_friction) : p_.kinetic_friction) *
           normal_force;
  }
  Eigen::Vector3d slipTrial(int x, const Eigen::Vector3d& p_world, const Eigen::Vector3d& vh_world,
                            const Eigen::Vector3d& n_world) const {
    const Eigen::Vector3d delta =
        p_world - (core_.originWorld() + rot_world_core_ * anchor_core_[x]);
    return -p_.stick_stiffness * (delta - delta.dot(n_world) * n_world) - c_stick_ * vh_world;
  }

  // Frozen surface of point i in the plane at the placed time: outward
  // normal, penetration [m] and d normal / dx [1/m]; false if the point is
  // at the surface's axis (no normal).
  bool planarSurface(const PlanarState& s, int surface, const Eigen::Vector2d& x,
                     Eigen::Vector2d& normal, double& depth, Eigen::Matrix2d& dnormal) const;
  // Velocity of the core material at plane point x [m/s].
  Eigen::Vector2d planarSurfaceVelocity(const PlanarState& s, const Eigen::Vector2d& x) const;
  // Its gradient d u / d x in the plane [1/s].
  Eigen::Matrix2d planarCarriedGradient(const PlanarState& s) const;
  // The same in 3-D for point i: outward normal, penetration [m], and d
  // normal / dp [1/m] where `dnormal` is given. A carried segment j stands
  // for the run j-1..j+1 (the nearest of the three).
  bool spatialSurface(int i, int surface, const Eigen::Vector3d& p_world,
                      Eigen::Vector3d& normal_world, double& depth, Eigen::Matrix3d* dnormal) const;

  // Sums the carried points' penetration again from the first one on.
  void forgetCarriedSums();

  const WireConstants& c_;  // the model's: n grows with a supply
  ContactParams p_;
  const RotatingCore& core_;
  std::vector<Eigen::Vector3d> centers_core_;
  std::vector<double> radii_;
  mutable std::vector<Eigen::Vector3d> centers_world_;  // scratch, sized once
  mutable Eigen::Matrix3d rot_world_core_;              // core pose as placed
  // The core angle the surfaces were last placed at [rad] (placed again
  // only when it moves; NaN: never placed).
  mutable double placed_angle_ = std::numeric_limits<double>::quiet_NaN();
  // Faces: start, unit direction and outward normal in the core frame, length.
  std::vector<Eigen::Vector3d> face_from_core_, face_dir_core_, face_normal_core_;
  std::vector<double> face_length_;
  mutable std::vector<Eigen::Vector3d> face_from_world_, face_dir_world_, face_normal_world_;
  // Flanges: axial position from the core's origin [m] and the side the
  // winding lies on (+1: along the core axis). They turn in their own plane.
  std::vector<double> flange_at_;
  std::vector<double> flange_side_;
  double flange_radius_ = 0.0;  // their reach from the core axis [m]
  // How far from the core axis the core body and the carried wire reach a
  // point [m] (beyond both and the flanges, nothing touches).
  double body_reach_ = 0.0;
  mutable double carried_reach_ = 0.0;
  // Carried wire: its poses (the model's), the broad phase, how many
  // segments it holds, and the points next to a point along the wire that
  // never count as touching it.
  const std::vector<Eigen::Vector3d>* carried_p_core_ = nullptr;
  mutable CarriedWireIndex carried_index_;
  // Per carried segment j (set as it is hashed): p_j+1 - p_j in the core
  // frame and its squared length.
  mutable std::vector<Eigen::Vector3d> segment_dir_core_;
  mutable std::vector<double> segment_length2_;
  mutable int indexed_segments_ = 0;
  // Per point, the segments of the cell its last query read that lie within
  // the reach and near_skin_ of where it was (in the cell's order): a
  // Verlet list. A later query within the skin of that place, in the same
  // cell and with the same index, reads the list instead of the cell, and
  // meets the same segments in the same order, less ones it cannot touch.
  struct NearList {
    Eigen::Vector3d p_core = Eigen::Vector3d::Zero();
    std::int64_t cell = 0;
    unsigned version = 0;
    int count = -1;  // -1: none (or more than kNearMax)
  };
  static constexpr int kNearMax = 32;
  mutable std::vector<NearList> near_;
  mutable std::vector<int> near_segments_;  // kNearMax per point
  double near_skin_ = 0.0;                  // [m]
  // The list of point i valid at p_core, made anew where it is not;
  // nullptr: too many segments near, read the cell.
  const int* nearSegments(int i, const Eigen::Vector3d& p_core, int& count) const;
  int skip_points_ = 0;
  // Slots per point and their roles; surface ids: cylinders, faces,
  // flanges, then the carried segments from wire_base_.
  int slots_ = 1, flange_slot_ = -1, wire_slot_ = 1, wire_base_ = 0;
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
