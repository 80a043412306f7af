// Contact of the wire's mass points with the core's cylinders and flat
// faces: virtual springs on the surfaces and static/kinetic friction against
// the moving surface, eqs. (16)-(20).
//
// Penetration h is measured from the wire's surface: h = R + r - distance of
// the point from the cylinder axis, or r - height of the point over a face;
// the normal force is k h n (eq. 18). A point touching several surfaces
// feels the deepest.
// Friction (when switched on) uses the relative velocity to the surface,
// v_h = tangential part of (v - u_j) (eqs. 16-17), with u_j the core's
// rigid-body velocity at the mass point: wire carried round by the core (its
// centre at radius R + r) has no relative velocity. Stick is represented by an
// anchor: a stuck point is tied to a material point of the core (stored in
// the core frame) by a stiff tangential spring; the point stays stuck while
// that spring's force is within mu_s N (eqs. 19-20: the point does not move
// along the surface). When it exceeds mu_s N the point slips and feels
// mu_d N against v_h (eq. 18). A slipping point sticks again, with a new
// anchor where it is, once |v_h| falls below contact.stick_speed.
// With contact.damping_ratio > 0 a dashpot acts beside each spring: the
// normal force is k h - c_n v_n (never pulling), v_n the speed away from the
// surface, and a stuck point's force -k_s delta - c_s v_h; the limit mu_s N
// applies to that sum. Stick and
// slip change only on accepted steps; within a step the trial state follows
// the committed one (the paper's "the calculation is redone").
#pragma once

#include <algorithm>
#include <vector>

#include "coil_winding_sim/core/rotating_core.hpp"
#include "coil_winding_sim/core/scene.hpp"
#include "coil_winding_sim/core/wire_types.hpp"

namespace cws {

class Contact : public ForceEffect {
 public:
  Contact(const WireConstants& c, const Scene& s, const RotatingCore& core);

  const char* name() const override { return "contact"; }
  void addForces(double t, const WireKinematics& k, WireForces& f) const override;
  // Implicit steps: the surface each point touches, stick (with its
  // anchor) or slip (with its direction) stay frozen within one Newton
  // solve; contact_planar.cpp.
  void addPlanarForces(const PlanarState& s, PlanarAssembly& a) const override;
  void beginImplicitStep(const PlanarState& s0) override;
  bool recheckFlags(const PlanarState& s) override;
  // The same in 3-D (contact_spatial.cpp). Kinetic friction follows the
  // trial sliding velocity (a floor of the speed it is divided by, for a
  // scene with no stick speed [m/s]).
  static constexpr double kTinySlidingSpeed = 1e-12;
  void addSpatialForces(const SpatialState& s, SpatialAssembly& a) const override;
  void beginSpatialStep(const SpatialState& s0) override;
  bool recheckSpatialFlags(const SpatialState& s) override;
  void adoptFlags() override;
  void commit(double t, const WireKinematics& k) override;
  void shrink(const WireKinematics& k) override;
  void appendHistory(std::vector<double>& out) const override;
  void restoreHistory(HistoryReader& in) override;
  // Energy in the normal springs at the last commit [J].
  double elasticEnergy(const WireKinematics& k) const override;

  // At the last commit: is point i touching the core, is it stuck.
  bool inContact(int i) const { return cylinder_[i] >= 0; }
  bool stuck(int i) const { return friction_ && stuck_[i] != 0; }
  // The present implicit step's trial flags (tests).
  int trialSurface(int i) const { return trial_surface_[i]; }
  bool trialStuck(int i) const { return friction_ && trial_stuck_[i] != 0; }
  double stickSpeed() const { return p_.stick_speed; }  // [m/s]
  // Friction force on point i at the last commit [N], world frame.
  const Eigen::Vector3d& frictionForce(int i) const { return friction_force_[i]; }
  // Deepest penetration over all points at the last commit [m].
  double maxPenetration() const { return max_penetration_; }

 private:
  // Places the cylinder axes and faces in the world at time t, once per
  // evaluation.
  void placeSurfaces(double t) const;
  // Deepest surface touching point p (as placed): its index (cylinders, then
  // faces; -1 if none), the penetration [m] and the outward normal.
  int touch(const Eigen::Vector3d& p_world, double& h, Eigen::Vector3d& n_world) const;
  // Normal force at penetration h [m] and speed v_n [m/s] away from the
  // surface [N], with its derivatives in h [N/m] and v_n [N s/m]: the
  // spring, with the dashpot if damped, never pulling. The dashpot grows
  // over the first kDashpotRamp of the wire radius of penetration, so that
  // the force does not jump by c v_n where a point first touches. (An
  // implicit step keeps an active contact's spring linear below h = 0.)
  struct NormalForce {
    double force, d_h, d_vn;
  };
  static constexpr double kDashpotRamp = 1e-3;
  NormalForce normalLaw(double h, double v_n) const {
    const double k = p_.stiffness;
    if (c_normal_ == 0.0 || h <= 0.0) return {k * h, k, 0.0};
    const bool ramping = h < h_ramp_;
    const double c = ramping ? c_normal_ * h / h_ramp_ : c_normal_;
    const double f = k * h - c * v_n;
    if (f <= 0.0) return {0.0, 0.0, 0.0};
    return {f, ramping ? k - c_normal_ * v_n / h_ramp_ : k, -c};
  }
  double normalForce(double h, double v_n) const { return normalLaw(h, v_n).force; }
  // Tangential friction force on point i [N] given the committed stick state;
  // sets `slipping` when the stick spring would exceed mu_s N.
  Eigen::Vector3d friction(int i, const Eigen::Vector3d& p_world, const Eigen::Vector3d& vh_world,
                           const Eigen::Vector3d& n_world, double normal_force,
                           bool& slipping) const;

  // Frozen surface of point i in the plane at the placed time: outward
  // normal, penetration [m] and d normal / dx [1/m]; false if the point is
  // at the surface's axis (no normal).
  bool planarSurface(const PlanarState& s, int surface, const Eigen::Vector2d& x,
                     Eigen::Vector2d& normal, double& depth, Eigen::Matrix2d& dnormal) const;
  // Velocity of the core material at plane point x [m/s].
  Eigen::Vector2d planarSurfaceVelocity(const PlanarState& s, const Eigen::Vector2d& x) const;
  // Its gradient d u / d x in the plane [1/s].
  Eigen::Matrix2d planarCarriedGradient(const PlanarState& s) const;
  // The same in 3-D: outward normal, penetration [m], d normal / dp [1/m].
  bool spatialSurface(int surface, const Eigen::Vector3d& p_world, Eigen::Vector3d& normal_world,
                      double& depth, Eigen::Matrix3d& dnormal) const;

  const WireConstants& c_;  // the model's: n grows with a supply
  ContactParams p_;
  const RotatingCore& core_;
  std::vector<Eigen::Vector3d> centers_core_;
  std::vector<double> radii_;
  mutable std::vector<Eigen::Vector3d> centers_world_;  // scratch, sized once
  mutable Eigen::Matrix3d rot_world_core_;              // core pose as placed
  // Faces: start, unit direction and outward normal in the core frame, length.
  std::vector<Eigen::Vector3d> face_from_core_, face_dir_core_, face_normal_core_;
  std::vector<double> face_length_;
  mutable std::vector<Eigen::Vector3d> face_from_world_, face_dir_world_, face_normal_world_;
  bool friction_;
  // Dashpots of the normal and the stick spring [N s/m] (0: undamped), and
  // the penetration over which the normal one grows [m].
  double c_normal_ = 0.0, c_stick_ = 0.0, h_ramp_ = 0.0;
  // Per point, committed: cylinder in contact (-1: none); with friction the
  // stick flag and the anchor in the core frame.
  std::vector<int> cylinder_;
  std::vector<char> stuck_;
  std::vector<Eigen::Vector3d> anchor_core_;
  std::vector<Eigen::Vector3d> friction_force_;  // output only
  std::vector<double> depth_;                    // committed penetration [m]
  double max_penetration_ = 0.0;
  double elastic_committed_ = 0.0;
  // Implicit steps' trial flags (capacity): surface, stick, anchor (core
  // frame) and slip direction (+1 / -1 along the surface tangent n x normal).
  std::vector<int> trial_surface_;
  std::vector<char> trial_stuck_;
  std::vector<Eigen::Vector3d> trial_anchor_core_;
  std::vector<signed char> trial_sign_;
  // 3-D: the world direction a slipping point slid in at the step's start,
  // or in which it began to slip (unit; zero: none yet).
  std::vector<Eigen::Vector3d> trial_slip_world_;
};

}  // namespace cws
