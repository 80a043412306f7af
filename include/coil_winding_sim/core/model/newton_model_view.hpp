// What a Newton formulation reads of the wire model: a narrow view the
// model offers and the implicit stepper hands to the formulation it builds
// (newton_formulations.hpp). The model does not know the formulations.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "coil_winding_sim/core/base/wire_types.hpp"
#include "coil_winding_sim/core/constraints/frame_constraints.hpp"

namespace cws {

class RotatingCore;
class ForceEffect;
class EffectHistory;

// The scene's facts a formulation needs beyond the solver's keys.
struct NewtonModelSetup {
  bool planar = false;            // physics.planar: the planar formulation
  bool port = false;              // physics.supply: the port's multipliers
  double elastic_rigidity = 0.0;  // wire.stretch.elastic_rigidity EA [N]
  Eigen::Vector3d core_axis_world = Eigen::Vector3d::UnitZ();  // core.axis_world
};

class NewtonModelView {
 public:
  virtual ~NewtonModelView() = default;
  virtual const NewtonModelSetup& newtonSetup() const = 0;
  virtual const WireConstants& constants() const = 0;
  // Kinematics at the last accepted step, valid from the boundary point
  // first-1 on (deferred carried wire is not placed).
  virtual const WireKinematics& integratedKinematics() const = 0;
  // All effects, in evaluation order, and those with a history (the
  // formulation sets their flags).
  virtual const std::vector<ForceEffect*>& effectList() = 0;
  virtual const std::vector<EffectHistory*>& historyList() = 0;
  // The step being accepted is a Newton step: its flags, as last
  // rechecked, are the ones the model's commit that follows adopts.
  virtual void acceptNewtonFlags() = 0;
  // Null when the scene needs no core.
  virtual const RotatingCore* core() const = 0;
  // The supply port's motion at time t [s] (newtonSetup().port: the scene
  // has a supply), for the port constraint.
  virtual PortMotion portMotion(double t) const = 0;
  // Pose and motion at time t [s] of the prescribed point first-1 (the
  // clamp, or the last point the core carries) and of its frame, and
  // whether it moves with the core.
  virtual void prescribedPose(double t, Eigen::Vector3d& p_world, Eigen::Vector3d& v_world,
                              Eigen::Vector4d& q, Eigen::Vector4d& qd) const = 0;
  virtual bool prescribedOnCore() const = 0;
  // Offset of point i's block (p, q, v, qdot) in the state vector (i >= 1).
  virtual int stateOffsetOf(int i) const = 0;
  // The velocity the step being accepted gives the core material, u =
  // g_world (p_world - origin_world) [m/s], as its scheme moves the core:
  // the model's commit that follows measures the wire's motion relative to
  // the core with it (wire at rest moves with the core by the scheme, not
  // by the exact rotation).
  virtual void acceptCoreVelocity(const Eigen::Matrix3d& g_world,
                                  const Eigen::Vector3d& origin_world) = 0;
  // After a solve: the fastest point of the free span that lands in it at
  // least `gap` points beyond the wound wire, by its speed relative to the
  // core at the last accepted step [m/s] (0: none; Contact::
  // spanLandingSpeed).
  virtual double spanLandingSpeed(int gap) const = 0;
  // The kinetic energy the core gives the carried wire (points
  // 1..first-1, turning rigidly with it) from t0 to t1 [J]: the core's
  // work on it, which the explicit model books as the carried points'
  // power (WireModel::derivative) and a Newton step books from this.
  virtual double carriedEnergyChange(double t0, double t1) const = 0;
};

}  // namespace cws
