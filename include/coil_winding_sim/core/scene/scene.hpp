// A scene: every input of one simulation run, as a plain struct.
//
// Scenes come from YAML (see config/scenes/default.yaml for the documented
// schema). They are validated in exactly one place, validateScene(), before
// anything is allocated or run. All quantities are SI (REP 103).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "coil_winding_sim/core/base/hysteresis.hpp"

namespace cws {

// The most mass points a scene may ask for. Storage grows with the points
// (a few kB per point), so validateScene refuses more instead of exhausting memory.
constexpr int kMaxScenePoints = 100000;
// The live points a job's estimate asks for at most where buried wire
// retires from the live arrays (Scene::carriesWoundWire,
// WireModel::retireBuriedWire): the wire older than that lives on in a
// compact store of about 100 bytes a point.
constexpr int kAutoLivePoints = 30000;
// The most points of wire a job may wind, retired ones included: about
// 1 GB of their records, some 170,000 turns of the paper's core.
constexpr double kMaxWirePoints = 1.0e7;

// A scene that cannot be run. key() names the offending YAML key path.
class SceneError : public std::runtime_error {
 public:
  SceneError(const std::string& key, const std::string& why)
      : std::runtime_error("scene key '" + key + "': " + why), key_(key), why_(why) {}
  const std::string& key() const { return key_; }
  const std::string& why() const { return why_; }  // the message without the key

 private:
  std::string key_;
  std::string why_;
};

// Two-line (bilinear, kinematic-hardening) law of one deformation mode, per
// unit length: generalized strain x (strain [-], curvature [1/m] or twist
// [rad/m]) against generalized stress (force [N] or moment [N m]).
struct WireParams {
  // The wire from what a user knows (scene/wire_catalogue.hpp): the keys
  // below it given as `auto` are made from these three when the scene is
  // loaded (paper_table_1: Table 1's numbers, the values below).
  std::string material = "paper_table_1";
  double nominal_diameter = 0.0;   // bare conductor [m]; 0: paper_table_1's own 1.0 mm
  int insulation_grade = 0;        // IEC 60317-0-1 grade 1-3 of the enamel; 0: bare
  double diameter = 1.0e-3;        // overall: contact and the layers' geometry [m]
  double line_density = 7.02e-3;   // [kg/m] (Table 1, corrected)
  double length = 0.05;            // initial wire length [m]
  double segment_length = 1.0e-3;  // largest natural segment length [m]
  HysteresisParams stretch{4.89e4, 1.10e3, 8.0e-4};  // EA [N], yield strain
  HysteresisParams bend{3.06e-3, 1.13e-4, 1.6};      // EI [N m^2], [1/m]
  HysteresisParams torsion{4.32e-3, 9.0e-5, 1.31};   // GJ [N m^2], [rad/m]
};

struct ContactParams {
  double static_friction = 0.23;   // mu_s [-]
  double kinetic_friction = 0.17;  // mu_d [-]
  double stiffness = 2.0e6;        // virtual spring k_j per mass point [N/m], eq. (18)
  double stick_stiffness = 2.0e6;  // tangential spring holding a stuck point [N/m]
  double stick_speed = 1.0e-3;     // slip returns to stick below this speed [m/s]
  // stick_speed: the paper's kinetic friction against the sliding velocity,
  // stick below stick_speed; elastic_slip: the stick spring returned onto
  // the friction cone (external_forces/elastic_slip.hpp).
  std::string friction_law = "stick_speed";
  // Dashpots beside the normal and the stick spring, as a fraction of the
  // critical damping 2 sqrt(k M) of one mass point on each [-]. 1 (the
  // reference model): a landing dissipates; 0: the paper's undamped
  // springs as printed, which ring at 80 kHz.
  double damping_ratio = 1.0;
};

// One cylinder of the core, parallel to the core axis.
struct CylinderParams {
  Eigen::Vector2d center_core{0.0, 0.0};  // axis position in the core's xy plane [m]
  double radius = 2.5e-3;                 // [m]
};

// A flat face of the core, parallel to its axis: the strip over the segment
// from -> to in the core's xy plane; the outside is on the right of
// from -> to (list faces counter-clockwise around the core).
struct FaceParams {
  Eigen::Vector2d from_core{0.0, 0.0};  // [m]
  Eigen::Vector2d to_core{0.0, 0.0};    // [m]
};

// A bobbin as drawn (core.shape). kind "cylinders": the core is
// core.cylinders and core.faces as given. kind "rounded_rectangle": a
// width x height section (core x, y) [m] with corners of corner_radius [m],
// made into its corner cylinders and the flat sides between them
// (applyCoreShape, core_geometry.hpp).
struct CoreShapeParams {
  std::string kind = "cylinders";
  double width = 0.0;          // [m]
  double height = 0.0;         // [m]
  double corner_radius = 0.0;  // [m]
};

// The rigid core: turns about its z axis, which passes through `position`
// along `axis` (world frame).
struct CoreParams {
  Eigen::Vector3d position_world{0.0, 0.0, 0.0};  // [m]
  Eigen::Vector3d axis_world{0.0, 0.0, 1.0};      // [-], normalized on use
  bool start_at_speed = true;               // true: turning at process.core_speed_rpm from t = 0
  double max_angular_acceleration = 2.0e4;  // speed changes follow this [rad/s^2]
  std::vector<CylinderParams> cylinders;
  std::vector<FaceParams> faces;
  bool hull_faces = false;  // add the flat faces between neighbouring cylinders
  // With physics.flanges: how far the flanges reach beyond the core's
  // outermost surface (its swept radius) [m].
  double flange_height = 3.0e-3;
  // With physics.flanges: the distance between them [m]; 0: the winding
  // width (a traverse set wider than the bobbin reverses late).
  double flange_spacing = 0.0;
  CoreShapeParams shape;  // made into cylinders, faces and hull_faces on loading
};

// Keys whose name says rpm carry revolutions per minute; everything else is
// SI. The one conversion to an angular velocity [rad/s].
inline double rpmToRadPerSec(double rpm) { return rpm * 2.0 * M_PI / 60.0; }

// A setpoint the job gives at a simulated time (process.commands): the core
// speed, the supply tension, or both.
struct ProcessCommand {
  double time = 0.0;                     // [s]
  std::optional<double> core_speed_rpm;  // [rpm]
  std::optional<double> tension;         // [N]
};

struct ProcessParams {
  double core_speed_rpm = 600.0;  // [rpm]
  double tension = 30.0;          // supply tension [N]
  double traverse_pitch = 0.0;    // port travel along the core axis per core turn [m]
  double winding_width =
      0.0;         // between the flanges; the traverse reverses at its ends [m] (0: never)
  int layers = 0;  // the job's planned traverse passes (0: no end); process.turns
                   // beyond them go on in further layers (Scene::traverseLayers)
  double max_core_speed_rpm = 6000.0;  // setpoints beyond +- this are refused [rpm]
  double max_tension = 300.0;          // setpoints above this are refused [N]
  double turns = 1.75;                 // core revolutions to run [-]
  std::optional<double> duration;      // [s]; when set, overrides turns
  // Setpoints at simulated times, in time order (a machine's program, or a
  // fault: the core reversed, the tension dropped).
  std::vector<ProcessCommand> commands;
  // A traverse that stops (a machine fault): from core turn
  // traverse_stall_turn [-] it stays where it is for traverse_stall_turns
  // [-] core turns, then goes on (0 turns: never stops).
  double traverse_stall_turn = 0.0;
  double traverse_stall_turns = 0.0;
};

struct SolverParams {
  // rkf45 | symplectic_euler | implicit_euler | bdf2
  std::string integrator = "rkf45";
  double rtol = 1.0e-6;          // relative tolerance [-]
  double atol = 1.0e-11;         // absolute tolerance on positions [m]
  double min_step = 1.0e-12;     // step floor [s]; below it the run stops
  double max_step = 1.0e-4;      // [s]
  double initial_step = 1.0e-7;  // [s]
  // Step of the fixed-step integrators [s]; unset (YAML `auto`): a safe
  // fraction of the scene's explicit stability limit (fixedStep()).
  std::optional<double> fixed_step;
  double baumgarte_nu = 5000.0;  // constraint stabilization nu [1/s], eq. (6)
  // Implicit integrators (implicit_euler, bdf2): the
  // longest step [s], and the steps per core revolution at the core's speed
  // [-] (the step is at most one revolution over this: at 300, shorter
  // than implicit_step above 2,000 rpm only; 0: steps of implicit_step at
  // any speed); Newton's convergence bound on the largest position update
  // [m], its iteration limit, and how often a step is solved again after a
  // contact, stick or slip flag changed.
  double implicit_step = 1.0e-4;
  double steps_per_revolution = 300.0;
  // Struck spans (docs/MODEL.md, "Steps through a struck span"): where the
  // core strikes the free span, a point of it landing at least
  // kStrikeGap points beyond the wound wire at a speed relative to the core
  // of at least ImplicitStepper::kStrikeSpeed, the Newton steps go down to strike_step
  // [s] and stay there for ImplicitStepper::kStrikeWindow (strike_step 0:
  // never; at or above implicit_step: no shorter steps). On by default: it
  // puts the paper's 1200 rpm cases within 2 % in bulging of the explicit
  // model.
  double strike_step = 1.0e-6;
  double newton_tol = 1.0e-8;
  int newton_max_iterations = 30;
  // Wound wire held by static friction moves rigidly with the core and leaves
  // the integrated system (with contact, friction and start.frame core;
  // elsewhere it has no effect).
  bool carry_stuck_wire = false;
};

// Which effects a scene needs. What is off is neither computed nor allocated.
struct PhysicsSwitches {
  bool torsion = true;
  bool plasticity = true;
  bool gravity = false;
  bool damping = false;
  bool air_drag = false;  // quadratic drag of the air (AirDrag)
  bool contact = false;   // virtual springs on the core's cylinders and faces
  bool friction = false;  // static/kinetic friction on contact (needs contact)
  bool flanges = false;   // the core's flanges at the ends of process.winding_width (3-D)
  // Wire against the wound wire the core carries, segments as capsules (3-D).
  bool wire_contact = false;
  bool supply = false;  // wire drawn in through a port at constant tension
  bool planar = false;  // motion kept in the plane normal to the core axis
};

// The wire supply (paper's section IV): the wire enters through a port at
// p_s(t) = port_position + the traverse's offset (TraverseProfile) * core axis.
// What stands between the tension setpoint and the wire at the port
// (supply.tensioner; docs/MODEL.md, "A tensioner and a nozzle"). kind
// "ideal": the port's tension is the setpoint. "dancer": a spring-loaded arm
// whose pulley stores wire, loaded to twice the setpoint, with a servo
// pay-off that keeps the arm centred; the span of wire from the pay-off over
// the pulley to the nozzle is elastic.
struct TensionerParams {
  std::string kind = "ideal";
  double mass = 0.03;        // the arm's moving mass at its pulley [kg]
  double stiffness = 100.0;  // of its spring about the centre [N/m]
  double damping = 2.0;      // of its damper [N s/m]
  double bandwidth = 30.0;   // of the pay-off's position loop [rad/s]
  double span_length = 0.5;  // wire from the pay-off over the pulley to the nozzle [m]
};

struct SupplyParams {
  Eigen::Vector3d port_position_world{0.0, -0.03, 0.0};  // [m] at t = 0
  int max_points = 0;  // storage for this many points; 0: estimated from the scene
  TensionerParams tensioner;
  // Capstan friction of the nozzle the wire runs through to the port: the
  // port's tension is the tensioner's times exp(mu theta) while wire is drawn
  // in [-], over its wrap angle theta [rad].
  double nozzle_friction = 0.0;
  double nozzle_wrap_angle = 0.0;
};

struct GravityParams {
  Eigen::Vector3d acceleration_world{0.0, 0.0, -9.81};  // [m/s^2]
};

struct DampingParams {
  double translational = 0.0;  // viscous force per length and speed [N s/m^2]
  double rotational = 0.0;     // viscous moment per length and spin [N m s/m]
};

// Quadratic drag of still air on the wire (physics.air_drag).
struct AirDragParams {
  double density = 1.2;           // of the air [kg/m^3]
  double drag_coefficient = 1.2;  // of a cylinder across the flow [-]
};

// The fixed end of the wire (mass point 0), clamped in position and direction.
struct StartParams {
  std::string type = "clamped";
  std::string frame = "world";
  Eigen::Vector3d position{0.0, 0.0, 0.0};   // [m] in `frame`
  Eigen::Vector3d direction{1.0, 0.0, 0.0};  // wire tangent at the clamp [-]
};

// One keyframe of the free end's load schedule; values between keyframes are
// interpolated linearly and held after the last one.
struct LoadKeyframe {
  double time = 0.0;                                       // [s]
  Eigen::Vector3d force_world = Eigen::Vector3d::Zero();   // [N]
  Eigen::Vector3d moment_world = Eigen::Vector3d::Zero();  // [N m]
};

struct EndParams {
  std::string type = "free";
  std::vector<LoadKeyframe> load{LoadKeyframe{}};
};

struct OutputParams {
  double progress_interval_s = 1.0;  // wall time between progress lines [s]
};

struct Scene {
  WireParams wire;
  ContactParams contact;
  CoreParams core;
  SupplyParams supply;
  ProcessParams process;
  SolverParams solver;
  PhysicsSwitches physics;
  GravityParams gravity;
  DampingParams damping;
  AirDragParams air_drag;
  StartParams start;
  EndParams end;
  OutputParams output;
  // The keys the loaded scene made from others (given as `auto`), and from
  // what, for print-scene; not a key.
  std::vector<std::string> made_keys;
  std::string made_from;

  // Number of segments and the natural segment length actually used: the
  // wire's length divided into equal segments no longer than segment_length.
  int segmentCount() const;
  double naturalSegmentLength() const;
  // Simulated time to run [s]: process.duration, else the time the core
  // needs for process.turns (at process.core_speed_rpm, after its ramp).
  double endTime() const;
  // Length of the model's segments [m]: wire.segment_length with a supply,
  // else naturalSegmentLength().
  double modelSegmentLength() const;
  // Mass points at t = 0 and the storage reserved for points [-], as
  // doubles so that an absurd scene cannot overflow them (validateScene
  // bounds both by kMaxScenePoints before the model converts them). Without
  // a supply both are segmentCount() + 1. With one, the points are the span
  // from the clamp to the port in segments of wire.segment_length, and the
  // storage is supply.max_points or an estimate of the wire drawn in until
  // endTime().
  double initialPoints() const;
  double pointCapacity() const;
  // The points of the whole wire at the job's end (retired ones included),
  // estimated from the core's size, the fastest commanded speed and the
  // job's length.
  double wirePointsEstimate() const;
  // Does the core carry wound wire rigidly (solver.carry_stuck_wire, where
  // friction holds it on a core that also holds the fixed end)? Only then
  // can buried wire retire from the live arrays.
  bool carriesWoundWire() const;
  // The points a run that turns the core by core_angle_rad [rad] needs
  // (supply.max_points aside): a replay's commands set the angle.
  double pointCapacityForAngle(double core_angle_rad) const;
  // Turns per pass of the traverse [-]: its travel W - d over the pitch
  // (0: no reversal, no winding width or no pitch).
  double turnsPerLayer() const;
  // The layers the job winds: process.layers, its plan, or more where
  // process.turns winds past them (validateScene refuses more than the
  // bobbin holds; 0: no end).
  int plannedLayers() const;
  // The passes the traverse lays before the port stops (0: no end): on a
  // bobbin (physics.flanges) as many as it holds, as a machine's traverse
  // goes on reversing while the spindle turns, so that wire wound past the
  // plan (the cell winding on after its job) lies in further layers rather
  // than piling up at a flange; else plannedLayers().
  int traverseLayers() const;
  // Of process.turns, those the traverse moves in [-]: less a stall's
  // turns (process.traverse_stall_turns) within the job.
  double traverseTurns() const;
  // The turns the bobbin holds (bobbinLayers() of turnsPerLayer(); +inf
  // without flanges or a traverse that reverses) [-].
  double bobbinTurns() const;
  // Layers the bobbin holds under core.flange_height, packed as closely as
  // wire packs (d (1 + (layers - 1) sqrt(3) / 2) high) [-].
  int bobbinLayers() const;
};

// Checks every value; throws SceneError naming the first bad key.
void validateScene(const Scene& scene);

// Stability limit of an explicit step for this wire [s]: the time l / c a
// wave needs to cross a segment (axial, or torsional with torsion on).
double explicitStepLimit(const Scene& scene);

// The fraction of explicitStepLimit() that solver.fixed_step: auto takes
// (docs/MODEL.md, "Time integration").
constexpr double kAutoStepFraction = 0.25;

// The step of the fixed-step integrators [s]: solver.fixed_step, or with
// `auto` kAutoStepFraction of explicitStepLimit(), at most solver.max_step.
double fixedStep(const Scene& scene);

// Loads the defaults, then `path` (if not empty; a top-level `base: FILE`
// in it loads FILE, relative to it, first), then each "key.path=value"
// override in order; refuses unknown keys and wrong types, then validates.
Scene loadScene(const std::string& path, const std::vector<std::string>& overrides);

// A scene from YAML text (as sceneToYamlText writes it), over the defaults,
// validated; throws SceneError.
Scene sceneFromYamlText(const std::string& text);

// The fully resolved scene as YAML text (the schema, with values).
std::string sceneToYamlText(const Scene& scene);

}  // namespace cws
