// The discrete elastoplastic wire of the paper's section II as an ODE system.
//
// State vector y, interleaved per free point (point 0 and frame 0 are held
// by the clamp):
//   [ W_ext, E_visc | p_1 q_1 v_1 qdot_1 | p_2 q_2 v_2 qdot_2 | ... ]
// 14 numbers per point, so that a point drawn in by the supply is appended
// at the end. W_ext [J] is the work done on the wire by applied loads,
// gravity, the moving core and the supply (including the energy the drawn-in
// wire brings), E_visc [J] the energy dissipated by viscous damping and
// friction; both are integrated with the motion for the energy balance.
#pragma once

#include <Eigen/Geometry>
#include <limits>
#include <memory>
#include <vector>

#include "coil_winding_sim/core/base/ode_system.hpp"
#include "coil_winding_sim/core/base/wire_types.hpp"
#include "coil_winding_sim/core/constraints/frame_constraints.hpp"
#include "coil_winding_sim/core/external_forces/contact.hpp"
#include "coil_winding_sim/core/external_forces/supply.hpp"
#include "coil_winding_sim/core/inner_forces/bending.hpp"
#include "coil_winding_sim/core/inner_forces/stretching.hpp"
#include "coil_winding_sim/core/inner_forces/twisting.hpp"
#include "coil_winding_sim/core/machine/rotating_core.hpp"
#include "coil_winding_sim/core/model/carried_wire.hpp"
#include "coil_winding_sim/core/model/make_effects.hpp"
#include "coil_winding_sim/core/model/newton_model_view.hpp"
#include "coil_winding_sim/core/model/retired_wire.hpp"
#include "coil_winding_sim/core/scene/core_geometry.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

class Damping;
class FreeWireContact;

struct EnergyReport {
  double kinetic = 0.0;    // [J]
  double elastic = 0.0;    // recoverable [J]
  double plastic = 0.0;    // work into plastic deformation [J]
  double viscous = 0.0;    // dissipated by damping and friction [J]
  double work_done = 0.0;  // by applied loads, gravity, core and supply [J]
  double dissipated() const { return plastic + viscous; }
  // kinetic + elastic + dissipated - work_done (0 for an exact solution).
  double imbalance() const { return kinetic + elastic + dissipated() - work_done; }
};

// Per point values for output (wire.csv): where the point is [m], world
// frame, and its figures (RetiredWire's PointFigures).
struct PointReport : PointFigures {
  Eigen::Vector3d p_world;
};

// Everything a model needs besides its scene to continue a run exactly.
struct ModelState {
  int points = 0;                 // n
  std::vector<double> y;          // the state vector's components in use
  std::vector<double> history;    // all effects' history, in effect order
  double core[4] = {0, 0, 0, 0};  // RotatingCore reference state (if any)
  int points_added = 0;
  double committed_time_s = 0.0;
  double port_distance0_m = 0.0;
  int carried = 0;                   // points the core carries (solver.carry_stuck_wire)
  std::vector<double> carried_pose;  // per carried point: p_core [m] (3), q_core (4)
  // Wire retired from the live arrays in front of point 0 (RetiredWire):
  // its points (RetiredWire::kValuesPerPoint each), its recoverable energy
  // and plastic work [J], its moment of inertia about the core axis
  // [kg m^2] and deepest penetration [m], and the pose of the clamp that
  // holds the live wire's point 0 on the core (p_core [m] (3), q_core (4)).
  int retired = 0;
  std::vector<double> retired_points;
  double retired_energy[4] = {0, 0, 0, 0};  // elastic, plastic, inertia, penetration
  // The axial force [N] of the retired segment ending at point 0 last.
  double clamp_core[8] = {0, 0, 0, 1, 0, 0, 0, 0};
  // Commanded port path ahead (PortTrajectory::exportState: t_s, x, y, z
  // per sample); empty: the port follows process.traverse_pitch.
  std::vector<double> port_command;
};

class WireModel : public OdeSystem, public NewtonModelView {
 public:
  // The scene must have passed validateScene().
  explicit WireModel(const Scene& scene);
  // Whether the prescribed point moves with the core (the clamp on the
  // core, or carried wire), or stands still (a clamp in the world).
  bool prescribedOnCore() const override { return clamp_in_core_; }

  // The state vector: kAuxStates energy terms [W_ext, E_visc], then
  // kStatesPerPoint per free point i >= 1: p (3), q (4), v (3), qdot (4).
  static constexpr int kAuxStates = 2;
  static constexpr int kStatesPerPoint = 14;
  int size() const override { return stateOffset(c_.n); }
  int capacity() const override { return stateOffset(c_.capacity); }
  void derivative(double t, ConstRef y, Ref dydt) override;
  const Eigen::VectorXd& absoluteTolerance() const override { return atol_; }
  const Eigen::VectorXd& relativeToleranceWeight() const override { return rweight_; }
  void acceptStep(double t, Eigen::VectorXd& y) override;
  bool semiImplicitUpdate(double h, ConstRef dydt, Ref y) const override;
  // [W_ext, E_visc | 14 per point]. A point's acceleration depends on its
  // neighbours' states and, through bending moments that the rotational
  // constraints pass on to the segments, on the next ones: radius 2 (further
  // coupling through the constraint solve falls ~100x per point).
  ChainStructure chainStructure() const override { return {kAuxStates, kStatesPerPoint, 2}; }
  NewtonModelView* newtonModel() override { return this; }
  const NewtonModelSetup& newtonSetup() const override { return newton_setup_; }
  int stateOffsetOf(int i) const override { return stateOffset(i); }
  void acceptCoreVelocity(const Eigen::Matrix3d& g_world,
                          const Eigen::Vector3d& origin_world) override {
    committed_.core_g_world = g_world;
    committed_.core_origin_world = origin_world;
    committed_.scheme_core = true;
  }
  double carriedEnergyChange(double t0, double t1) const override;
  double spanLandingSpeed(int gap) const override {
    return contact_ ? contact_->spanLandingSpeed(committed_, committed_time_, gap) : 0.0;
  }
  // Offset of point i's block (p, q, v, qdot) in the state vector (i >= 1).
  static int stateOffset(int i) { return kAuxStates + kStatesPerPoint * (i - 1); }
  // Pose and motion at time t [s] of the prescribed point first-1 (the
  // clamp, or the last point the core carries) and of its frame.
  void prescribedPose(double t, Eigen::Vector3d& p_world, Eigen::Vector3d& v_world,
                      Eigen::Vector4d& q, Eigen::Vector4d& qd) const override;
  // All effects, in evaluation order, and those with a history (implicit
  // steppers set their flags).
  const std::vector<ForceEffect*>& effectList() override { return all_; }
  const std::vector<EffectHistory*>& historyList() override { return effects_.histories(); }
  void acceptNewtonFlags() override { newton_flags_ = true; }
  PortMotion portMotion(double t) const override;

  const Eigen::VectorXd& initialState() const { return y0_; }
  const WireConstants& constants() const override { return c_; }

  // Kinematics of point 0 and of points from..n-1 for a state; returns the
  // clamp's (point 0's) acceleration [m/s^2].
  Eigen::Vector3d unpack(double t, ConstRef y, WireKinematics& k, int from = 1) const;
  // Kinematics at the last accepted step, of the whole wire.
  const WireKinematics& committed() const {
    placeCarriedWire();
    return committed_;
  }
  // The same without placing deferred carried wire: valid from the
  // boundary point first-1 on (for the steppers).
  const WireKinematics& integratedKinematics() const override { return committed_; }

  EnergyReport energy(const Eigen::VectorXd& y) const;
  double maxConstraintResidual() const { return constraints_.maxResidual(committed_); }

  // The whole wire, from its fixed end: the points retired from the live
  // arrays (retireBuriedWire), then the live points 0..n-1, so that live
  // point i is whole-wire point retiredPoints() + i (its reports:
  // run/wire_report.hpp). contactSurface takes whole-wire indices w.
  int wirePoints() const { return c_.retired + c_.n; }
  int retiredPoints() const { return c_.retired; }
  const RetiredWire& retiredWire() const { return retired_; }
  // Live point i's figures and its stand-off from the winding surface [m]
  // (needs a core) at the last accepted step, as a retirement records them.
  PointReport livePoint(int i) const;
  double liveStandOff(int i) const;
  // The surface point w touched in contact slot s at the last accepted step
  // (Contact::surface; retired wire: when it retired); -1: none.
  int contactSurface(int w, int s) const {
    return w < c_.retired ? retired_[w].surface[s] : contact_->surface(w - c_.retired, s);
  }
  double axialForce(int j) const;  // live segment j at the last accepted step [N]
  // The wire's axial force at the supply port [N]: the last segment's, what
  // a load cell at the nozzle measures (a scene with a supply).
  double portAxialForce() const { return axialForce(c_.n - 2); }
  // The last point touching the core at the last accepted step (whole-wire
  // index); -1: none, or a scene without contact.
  int lastInContact() const;

  // History state of all effects, concatenated (empty without plasticity).
  std::vector<double> history() const;

  // Effects built for this scene, in evaluation order (for inspection).
  std::vector<const ForceEffect*> effects() const;
  const Stretching& stretching() const { return *stretching_; }
  const Bending& bending() const { return *bending_; }
  const Twisting* twisting() const { return twisting_; }
  // Null when the scene needs no core (no contact, supply or core clamp).
  const RotatingCore* core() const override { return core_.get(); }
  RotatingCore* core() { return core_.get(); }
  const Contact* contact() const { return contact_; }
  // Contact between free segments (physics.wire_contact; else null).
  const FreeWireContact* freeWireContact() const { return free_wire_contact_; }
  // Friction and damping coefficients changed mid-run (Simulation::
  // setFriction, setDamping; validated there).
  void setFriction(double mu_static, double mu_kinetic);
  void setDamping(const DampingParams& d);
  const Supply* supply() const { return supply_; }
  // Snapshot of the model with its state vector y; restore() checks sizes
  // and finiteness and throws std::runtime_error naming what is wrong,
  // leaving nothing half-restored only if the caller discards the model.
  ModelState saveState(const Eigen::VectorXd& y) const;
  void restoreState(const ModelState& m, Eigen::VectorXd& y);
  // Setpoints (between steps): core speed [rad/s], supply tension [N].
  void setCoreSpeed(double omega);
  void setSupplyTension(double tension);
  // Commanded port position p_world [m] at t_s [s] (Supply::commandPort);
  // throws std::invalid_argument (also without a supply).
  void setPortCommand(const Eigen::Vector3d& p_world, double t_s);

  // Time of the last accepted step [s].
  double committedTime() const { return committed_time_; }
  // Natural length of wire drawn in through the port since the start [m].
  double fedLength() const;
  // The core's cross-section (null: a core without cylinders, or none).
  const CoreSection* section() const { return section_.get(); }
  // Points 1..carriedPoints() move rigidly with the core and are not
  // integrated (solver.carry_stuck_wire); 0 otherwise.
  int carriedPoints() const { return c_.first - 1; }
  // Deferred carried wire (for steppers that read only the integrated
  // points and the boundary point first-1, as the Newton-step ones do): an
  // accepted step then places only the boundary point. The other carried
  // points are placed in committed() when the whole wire is next read
  // (committed(), livePoint(), liveStandOff()), and in a state vector by
  // placeCarriedWire(y), which energy(y) and saveState(y) require first
  // (Simulation::state() and Simulation::energy() call it). This keeps a
  // step's cost independent of the wound wire's length.
  void setCarriedDeferred(bool deferred) { carried_deferred_ = deferred; }
  // Places deferred carried wire in the committed kinematics, and in y, the
  // state of the last accepted step (caches: logically const).
  void placeCarriedWire() const;
  void placeCarriedWire(Eigen::VectorXd& y) const;

  // Buried wire leaves the live arrays: when the wire's storage is full
  // (appendPoint), the carried points more than keepTurns() core turns of
  // wire behind the first integrated point retire into the compact
  // RetiredWire store, and the live arrays are numbered from the next one,
  // which becomes the clamp on the core. Nothing integrated reaches that
  // wire: later turns lie on the layers above it. Returns how many points
  // retired (0: none can).
  int retireBuriedWire(Eigen::VectorXd& y);
  double keepTurns() const { return keep_turns_; }
  // Counts the points retired since the start (steppers that keep a past
  // per point move it with the live arrays: OdeSystem::pointsRetired).
  long pointsRetired() const override { return c_.retired; }

 private:
  // How many points may retire now: the carried wire more than keepTurns()
  // turns about the core axis behind the first integrated point (0: none).
  int retirablePoints() const;
  // Clamp state of point 0 and frame 0 at time t (world frame).
  void clamp(double t, Eigen::Vector3d& p0_world, Eigen::Vector3d& v0_world,
             Eigen::Vector3d& a0_world, Eigen::Vector4d& q0, Eigen::Vector4d& qd0) const;
  // Distance from the last point to the port along its zeta axis [m].
  double portDistance(double t, const WireKinematics& k) const;
  // Appends a mass point drawn in through the port (between steps).
  void appendPoint(double t, Eigen::VectorXd& y);
  // The reverse: the last point, drawn back out past the port, leaves.
  void removeLastPoint(double t, Eigen::VectorXd& y);
  // Carried wire (solver.carry_stuck_wire): the rigid pose of carried point
  // i at time t, written into y and the committed kinematics; and, after
  // an accepted step, what CarriedWire decides the core carries, carried out.
  void placeCarried(double t, int i, Eigen::VectorXd& y);
  void placeCarried(double t, int i);                    // the committed kinematics only
  void writeCommitted(int i, Eigen::VectorXd& y) const;  // point i's committed state into y
  // Throws std::logic_error where a reader of y comes before
  // placeCarriedWire(y) (a programming error, not an input one).
  void requirePlacedState() const;
  void updateCarried(double t, Eigen::VectorXd& y);

  WireConstants c_;
  bool clamp_in_core_;
  Eigen::Vector3d p0_;  // clamp position, world or core frame [m]
  Eigen::Vector4d q0_;  // clamp orientation, world or core frame
  // The scene's clamp (p0_, q0_ hold a carried point once wire retired).
  Eigen::Vector3d p0_start_;
  Eigen::Vector4d q0_start_;
  Eigen::Vector3d planar_normal_world_ = Eigen::Vector3d::Zero();  // zero: 3-D
  std::unique_ptr<RotatingCore> core_;
  Contact* contact_ = nullptr;
  FreeWireContact* free_wire_contact_ = nullptr;
  Damping* damping_ = nullptr;
  Supply* supply_ = nullptr;
  std::unique_ptr<CoreSection> section_;  // with a core that has cylinders
  EffectSet effects_;                     // makeEffects: what the scene switches on
  Stretching* stretching_ = nullptr;
  Bending* bending_ = nullptr;
  Twisting* twisting_ = nullptr;  // null when physics.torsion is off
  std::vector<ForceEffect*> all_;
  bool newton_flags_ = false;  // the step being accepted is a Newton step's
  FrameConstraints constraints_;
  int points_added_ = 0;
  double committed_time_ = 0.0;  // [s]
  double port_distance0_ = 0.0;  // [m] at t = 0
  bool carry_ = false;
  CarriedWire carried_;             // the wound wire the core carries (solver.carry_stuck_wire)
  RetiredWire retired_;             // buried wire retired from the live arrays
  int retired_reserve_ = 0;         // records reserved for the job's whole wire
  double clamp_axial_force_ = 0.0;  // [N] the retired segment ending at point 0
  double keep_turns_ = 0.0;         // carried turns kept live behind the integrated wire
  bool carried_deferred_ = false;
  // Carried poses at committed_time_ in committed_ and in the state vector.
  bool carried_kinematics_placed_ = true;
  mutable bool carried_state_placed_ = true;

  NewtonModelSetup newton_setup_;  // what a Newton formulation reads of the scene
  Eigen::VectorXd y0_, atol_, rweight_;
  WireKinematics kin_, committed_;
  WireForces forces_;
  Eigen::Matrix3Xd acc_;
  Eigen::Matrix4Xd qdd_;
};

}  // namespace cws
