// The discrete elastoplastic wire of the paper's section II as an ODE system.
//
// State vector y (m = n - 1 free points; point 0 and frame 0 are clamped):
//   [ p_1..p_m (3m) | q_1..q_m (4m) | v_1..v_m (3m) | qdot_1..qdot_m (4m) |
//     W_ext, E_visc ]
// where W_ext [J] is the work done on the wire by applied loads and E_visc
// [J] the energy dissipated by viscous damping, integrated with the motion
// for the energy balance.
#pragma once

#include <memory>
#include <vector>

#include "coil_winding_sim/core/constraints/frame_constraints.hpp"
#include "coil_winding_sim/core/external_forces/contact.hpp"
#include "coil_winding_sim/core/inner_forces/bending.hpp"
#include "coil_winding_sim/core/inner_forces/stretching.hpp"
#include "coil_winding_sim/core/inner_forces/twisting.hpp"
#include "coil_winding_sim/core/rotating_core.hpp"
#include "coil_winding_sim/core/scene.hpp"
#include "coil_winding_sim/core/time_steppers/ode_system.hpp"
#include "coil_winding_sim/core/wire_types.hpp"

namespace cws {

struct EnergyReport {
  double kinetic = 0.0;    // [J]
  double elastic = 0.0;    // recoverable [J]
  double plastic = 0.0;    // work into plastic deformation [J]
  double viscous = 0.0;    // dissipated by damping [J]
  double work_done = 0.0;  // by applied loads and gravity [J]
  double dissipated() const { return plastic + viscous; }
  // kinetic + elastic + dissipated - work_done (0 for an exact solution).
  double imbalance() const { return kinetic + elastic + dissipated() - work_done; }
};

// Per point values for output (wire.csv); index i is point i.
struct PointReport {
  Eigen::Vector3d p_world;
  double axial_force_N = 0.0;          // segment ending at i (point 0: segment 0)
  double curvature_1pm = 0.0;          // |bending curvature| at joint i
  double plastic_curvature_1pm = 0.0;  // |permanent bending curvature| at joint i
  double twist_rad_per_m = 0.0;        // twist rate at joint i
  bool in_contact = false;             // touching a core cylinder
  bool stick = false;                  // held by static friction
};

class WireModel : public OdeSystem {
 public:
  // The scene must have passed validateScene().
  explicit WireModel(const Scene& scene);

  int size() const override { return static_cast<int>(y0_.size()); }
  void derivative(double t, const Eigen::VectorXd& y, Eigen::VectorXd& dydt) override;
  const Eigen::VectorXd& absoluteTolerance() const override { return atol_; }
  const Eigen::VectorXd& relativeToleranceWeight() const override { return rweight_; }
  void acceptStep(double t, const Eigen::VectorXd& y) override;

  const Eigen::VectorXd& initialState() const { return y0_; }
  const WireConstants& constants() const { return c_; }

  // Kinematics of all points (point 0 included) for a state; returns the
  // clamp's (point 0's) acceleration [m/s^2].
  Eigen::Vector3d unpack(double t, const Eigen::VectorXd& y, WireKinematics& k) const;
  // Kinematics at the last accepted step.
  const WireKinematics& committed() const { return committed_; }

  EnergyReport energy(const Eigen::VectorXd& y) const;
  double maxConstraintResidual() const { return constraints_.maxResidual(committed_); }
  PointReport point(int i) const;
  double axialForce(int j) const;  // segment j at the last accepted step [N]

  // History state of all effects, concatenated (empty without plasticity).
  std::vector<double> history() const;

  // Effects built for this scene, in evaluation order (for inspection).
  std::vector<const ForceEffect*> effects() const;
  const Stretching& stretching() const { return *stretching_; }
  const Bending& bending() const { return *bending_; }
  const Twisting* twisting() const { return twisting_.get(); }
  // Null when the scene needs no core (no contact, clamp in the world frame).
  const RotatingCore* core() const { return core_.get(); }
  RotatingCore* core() { return core_.get(); }
  const Contact* contact() const { return contact_; }

 private:
  // Clamp state of point 0 and frame 0 at time t (world frame).
  void clamp(double t, Eigen::Vector3d& p0_world, Eigen::Vector3d& v0_world,
             Eigen::Vector3d& a0_world, Eigen::Vector4d& q0) const;

  WireConstants c_;
  bool clamp_in_core_;
  Eigen::Vector3d p0_;  // clamp position, world or core frame [m]
  Eigen::Vector4d q0_;  // clamp orientation, world or core frame
  std::unique_ptr<RotatingCore> core_;
  const Contact* contact_ = nullptr;
  std::unique_ptr<Stretching> stretching_;
  std::unique_ptr<Bending> bending_;
  std::unique_ptr<Twisting> twisting_;  // null when physics.torsion is off
  std::vector<std::unique_ptr<ForceEffect>> external_;
  std::vector<ForceEffect*> all_;
  FrameConstraints constraints_;

  Eigen::VectorXd y0_, atol_, rweight_;
  WireKinematics kin_, committed_;
  WireForces forces_;
  Eigen::Matrix3Xd acc_;
  Eigen::Matrix4Xd qdd_;
};

}  // namespace cws
