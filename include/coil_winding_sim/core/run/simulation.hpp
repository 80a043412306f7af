// One simulation run: a validated scene, its wire model and its integrator,
// with the run's statistics. The ROS node and wire_sim are thin users of it.
#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <string>

#include "coil_winding_sim/core/model/wire_model.hpp"
#include "coil_winding_sim/core/run/command_schedule.hpp"
#include "coil_winding_sim/core/run/input_log.hpp"
#include "coil_winding_sim/core/run/pace_profile.hpp"
#include "coil_winding_sim/core/run/setpoint.hpp"
#include "coil_winding_sim/core/run/wire_report.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"
#include "coil_winding_sim/core/time_steppers/time_stepper.hpp"

namespace cws {

// The full state of a run: enough to continue it exactly (same numbers to
// rounding) in a new Simulation. Yield points, stick states and anchors,
// supply points, the core's motion and the integrator's step are included,
// and the setpoints held that the model's state does not carry.
struct SimulationState {
  std::string scene_yaml;  // the resolved scene
  double time_s = 0.0;
  ModelState model;
  // What the setpoint table's rows hold now (SetpointRow::held), one per
  // kind at most; applied in this order on restore.
  std::vector<Setpoint> held;
  double next_step_s = 0.0, last_step_s = 0.0;
  StepCounts counts;
  double max_residual = 0.0, max_axial_force_N = 0.0, max_penetration_m = 0.0;
  double wall_time_s = 0.0;
};
// Holds sp in st in place of any of its kind.
void holdSetpoint(SimulationState& st, const Setpoint& sp);

class Simulation {
 public:
  // Validates the scene (throws SceneError) and builds the model.
  explicit Simulation(const Scene& scene);

  // Snapshot of the run, and a run continued from one (the scene comes with
  // it). fromState throws SceneError or std::runtime_error naming the
  // problem; nothing else changes.
  SimulationState saveState() const;
  static std::unique_ptr<Simulation> fromState(const SimulationState& state);

  // Applies a setpoint now and, once accepted, logs it at the present time
  // in inputs(): the one way a setpoint reaches the model. A value beyond
  // its row's limit (setpointRow(kind).refusal) throws
  // std::invalid_argument naming the limit's key; what the model refuses
  // throws as its target does (setpoint.hpp); a refused one is not logged
  // and leaves the run unchanged.
  void apply(const Setpoint& setpoint) {
    applyUnlogged(setpoint);
    if (keep_inputs_) inputs_.record(t_, setpoint);
  }
  // The setpoints this run accepted through apply(), in order.
  const InputLog& inputs() const { return inputs_; }
  // Whether apply() logs (from now on; default true). A cell that runs for
  // a shift and repeats nothing keeps none: the log would grow with every
  // setpoint (64 bytes each).
  void keepInputs(bool keep) { keep_inputs_ = keep; }

  // True once the port follows commands.
  bool portCommanded() const {
    return model_->supply() && model_->supply()->portCommand().active();
  }
  // Samples that can still be queued, and the time of the last queued one
  // (-infinity without commands).
  int portCommandRoom() const {
    return model_->supply() ? model_->supply()->portCommand().room() : 0;
  }
  double portCommandEnd() const {
    return model_->supply() ? model_->supply()->portCommand().lastTime()
                            : -std::numeric_limits<double>::infinity();
  }

  // Step-size collapse: an error-controlled method whose accepted step stays
  // below its collapseRatio() x the explicit stability limit l / c for
  // kCollapseSteps steps in a row is stopped (IntegrationError naming the
  // cause and the remedy): such runs would otherwise crawl for hours before
  // reaching solver.min_step.
  static constexpr long kCollapseSteps = 10000;
  // Divergence: a step that leaves a segment more than this far off its
  // frame's tangent (the constraint residual [rad]) stops the run with an
  // IntegrationError naming the method and its step, before the state runs
  // off to overflow or the supply to its storage limit. Baumgarte
  // stabilization holds a sound run near 1e-6; the stability criterion's
  // bound is 1e-3; a tension setpoint jump from 30 to 300 N (the default
  // limit) peaks at 1.0e-2 and decays within 1 ms, so the stop is 10x that.
  static constexpr double kDivergedResidual = 0.1;
  // Penetration of a point into carried wire, in wire radii, beyond which
  // a run stops: the two wires' axes nearer than one radius, wire through
  // wire. (Landings on a drum have reached 0.88 r for a step and recovered:
  // docs/MODEL.md, "Wire against wound wire".)
  static constexpr double kWireThroughWire = 1.0;

  // One accepted step, not past t_limit [s]. Throws IntegrationError.
  void step(double t_limit);
  // Steps until the scene's end time; `progress` is called about every
  // output.progress_interval_s of wall time. Accumulates wall time. `stop`,
  // if given, is asked before every step: when it returns true the run ends
  // there, before the end time (a user's interrupt).
  void run(const std::function<void(const Simulation&)>& progress = {},
           const std::function<bool()>& stop = {});

  double time() const { return t_; }           // simulated time [s]
  double endTime() const { return t_end_; }    // [s]
  double wallTime() const { return wall_s_; }  // wall time spent in run() [s]
  double realTimeFactor() const { return wall_s_ > 0.0 ? t_ / wall_s_ : 0.0; }
  // The stretch of run() that ran slowest against real time, with the
  // integrator's work in it (pace_profile.hpp).
  const PaceStretch& slowestStretch() const { return pace_.slowest(); }
  const Scene& scene() const { return scene_; }
  // Room for `points` more live points: buried wire retires from the live
  // arrays where the storage would not hold them (WireModel::
  // retireBuriedWire). Between steps; false: it still would not.
  bool makeRoom(int points);
  const WireModel& model() const { return *model_; }
  WireModel& model() { return *model_; }
  const TimeStepper& stepper() const { return *stepper_; }
  // The state with the whole wire at the last accepted step (deferred
  // carried wire placed first: WireModel::setCarriedDeferred).
  const Eigen::VectorXd& state() const {
    model_->placeCarriedWire(y_);
    return y_;
  }
  EnergyReport energy() const { return model_->energy(state()); }
  // Largest values over all accepted steps.
  double maxConstraintResidual() const { return max_residual_; }
  double maxAxialForce() const { return max_axial_force_; }  // [N]
  // Deepest contact penetration over all accepted steps [m] (0 without contact).
  double maxPenetration() const { return max_penetration_; }
  // Core revolutions turned so far (0 without a core).
  double coreTurns() const;

 private:
  // The setpoints' targets (setpointTable's rows; apply() checks their
  // limits and logs them).
  friend const std::vector<SetpointRow>& setpointTable();
  void applyUnlogged(const Setpoint& setpoint);
  // Core angular velocity [rad/s] (reached at the scene's acceleration
  // limit) and supply tension [N], from the present time on. Ignored when
  // the scene has no core / no supply.
  void setCoreSpeed(double omega);
  void setSupplyTension(double tension);
  // Commanded supply-port position p_world [m, world frame] at simulated
  // time t_s [s]: the port moves on straight lines between the commanded
  // samples (constant velocity between them) and holds the last one; the
  // first command starts from where the port is and replaces the traverse
  // law (process.traverse_pitch). Steps end at sample times. Samples may lie
  // ahead of the present time (PortTrajectory::kCapacity of them).
  // Throws std::invalid_argument naming what is wrong (a non-finite value, a
  // stamp before the simulated time or the last sample, a jump, a port
  // inside the turning core, no supply); the run is unchanged then.
  void setPortCommand(const Eigen::Vector3d& p_world, double t_s) {
    model_->setPortCommand(p_world, t_s);
  }
  // Changes made while running, from the next step on: the friction
  // coefficients (contact.static_friction, contact.kinetic_friction) and the
  // viscous damping (damping.translational [N s/m^2], damping.rotational
  // [N m s/m]). Checked by the scene's own rules first; a refused change
  // throws SceneError naming the key and leaves everything as it was (so
  // does a change of an effect the scene switches off). The scene takes the
  // new values, so snapshots carry them.
  void setFriction(double mu_static, double mu_kinetic);
  void setDamping(const DampingParams& d);

  void afterStep();
  // Applies the scene's commands (process.commands) due by now; they are
  // part of the scene, so a rerun of it repeats them: not logged.
  void applyDueCommands();
  // A core speed ramp: its end [s] and |acceleration| [rad/s^2].
  struct Ramp {
    double end_s = -std::numeric_limits<double>::infinity();
    double acceleration_rad_s2 = 0.0;
  };
  void checkCollapse(const Ramp& ramp);
  std::string withRampCause(const std::string& what, double t_fail_s, const Ramp& ramp) const;

  Scene scene_;
  std::unique_ptr<WireModel> model_;
  std::unique_ptr<TimeStepper> stepper_;
  // The state; mutable for the deferred carried wire it is brought up to
  // date with when read (WireModel::setCarriedDeferred).
  mutable Eigen::VectorXd y_;
  double t_ = 0.0;
  double t_end_ = 0.0;
  double wall_s_ = 0.0;
  PaceProfile pace_;
  InputLog inputs_;
  CommandSchedule commands_;  // process.commands not yet applied
  bool keep_inputs_ = true;
  double max_residual_ = 0.0;
  double max_axial_force_ = 0.0;
  double max_penetration_ = 0.0;
  double collapse_step_s_ = 0.0;  // the stepper's collapseRatio() l / c [s]
  long small_steps_ = 0;          // accepted steps in a row below it
  double small_since_s_ = 0.0;    // time the present run of them began [s]
  Ramp small_ramp_;               // the core speed ramp under way then
};

}  // namespace cws
