#include "coil_winding_sim/core/run/simulation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "coil_winding_sim/core/external_forces/free_wire_contact.hpp"
#include "coil_winding_sim/core/run/run_checks.hpp"
#include "coil_winding_sim/core/scene/integrators.hpp"
#include "coil_winding_sim/core/scene/setpoint_limits.hpp"

namespace cws {

namespace {
Scene validated(const Scene& s) {
  validateScene(s);
  return s;
}
}  // namespace

Simulation::Simulation(const Scene& scene) : scene_(validated(scene)) {
  model_ = std::make_unique<WireModel>(scene_);
  // The steppers take the fixed step resolved (solver.fixed_step: auto).
  SolverParams solver = scene_.solver;
  solver.fixed_step = fixedStep(scene_);
  stepper_ = makeTimeStepper(solver, *model_);
  // The Newton-step methods read only the integrated wire: the carried wire
  // is placed when it is read, not at every step.
  const IntegratorInfo* info = findIntegrator(scene_.solver.integrator);
  model_->setCarriedDeferred(info && info->newton_steps);
  y_ = model_->initialState();
  t_end_ = scene_.endTime();
  collapse_step_s_ = stepper_->collapseRatio() * explicitStepLimit(scene_);
  for (const ProcessCommand& c : scene_.process.commands) {
    if (c.core_speed_rpm)
      commands_.add(c.time, Setpoint::coreSpeed(rpmToRadPerSec(*c.core_speed_rpm)));
    if (c.tension) commands_.add(c.time, Setpoint::supplyTension(*c.tension));
  }
  applyDueCommands();
  afterStep();
}

void Simulation::applyDueCommands() {
  commands_.takeDue(t_, [&](double, const Setpoint& c) { applyUnlogged(c); });
}

double Simulation::coreTurns() const {
  const RotatingCore* core = model_->core();
  return core ? core->angle(t_) / (2.0 * M_PI) : 0.0;
}

void Simulation::afterStep() {
  max_residual_ = std::max(max_residual_, model_->maxConstraintResidual());
  if (model_->contact()) {
    max_penetration_ = std::max(max_penetration_, model_->contact()->maxPenetration());
  }
  // Segments of carried wire do not change: they were measured while they
  // were integrated.
  const int segments = model_->constants().n - 1;
  for (int j = model_->constants().first - 1; j < segments; ++j) {
    max_axial_force_ = std::max(max_axial_force_, std::abs(model_->axialForce(j)));
  }
}

void Simulation::applyUnlogged(const Setpoint& setpoint) {
  const std::string why = setpointRefusal(SetpointLimits::of(scene_.process), setpoint);
  if (!why.empty()) throw std::invalid_argument(why);
  setpointRow(setpoint.kind).target(*this, setpoint);
}

void Simulation::setCoreSpeed(double omega) {
  const RotatingCore* core = model_->core();
  const bool ramps = core && omega != core->command();
  model_->setCoreSpeed(omega);
  if (ramps) stepper_->kink();
}

bool Simulation::makeRoom(int points) {
  const WireConstants& c = model_->constants();
  if (c.n + points > c.capacity) model_->retireBuriedWire(y_);
  return c.n + points <= c.capacity;
}

void Simulation::setSupplyTension(double tension) { model_->setSupplyTension(tension); }

SimulationState Simulation::saveState() const {
  SimulationState st;
  st.scene_yaml = sceneToYamlText(scene_);
  st.time_s = t_;
  st.model = model_->saveState(state());
  for (const SetpointRow& row : setpointTable()) {
    Setpoint held;
    if (row.held && row.held(*this, held)) st.held.push_back(held);
  }
  st.next_step_s = stepper_->nextStep();
  st.last_step_s = stepper_->lastStep();
  st.counts = stepper_->counts();
  st.max_residual = max_residual_;
  st.max_axial_force_N = max_axial_force_;
  st.max_penetration_m = max_penetration_;
  st.wall_time_s = wall_s_;
  return st;
}

void holdSetpoint(SimulationState& st, const Setpoint& sp) {
  for (Setpoint& held : st.held) {
    if (held.kind == sp.kind) {
      held = sp;
      return;
    }
  }
  st.held.push_back(sp);
}

std::unique_ptr<Simulation> Simulation::fromState(const SimulationState& st) {
  auto sim = std::make_unique<Simulation>(sceneFromYamlText(st.scene_yaml));
  if (!std::isfinite(st.time_s) || st.time_s < 0.0) {
    throw std::runtime_error("snapshot time is not a finite, non-negative number");
  }
  if (!(st.next_step_s > 0.0) || !std::isfinite(st.next_step_s)) {
    throw std::runtime_error("snapshot step size is not positive");
  }
  sim->model_->restoreState(st.model, sim->y_);
  sim->t_ = st.time_s;
  // The setpoints held, through their rows' checks and targets (not
  // logged: the scene's own values start a run, and these were logged
  // where they were set).
  for (const Setpoint& held : st.held) {
    const SetpointRow& row = setpointRow(held.kind);
    if (!row.held) {
      throw std::runtime_error(std::string("snapshot holds a ") + row.name +
                               " setpoint, which the model's state carries");
    }
    try {
      sim->applyUnlogged(held);
    } catch (const std::exception& e) {
      throw std::runtime_error(std::string("snapshot's ") + row.name + " setpoint: " + e.what());
    }
  }
  // The scene's commands due by then are in the state restored.
  sim->commands_.takeDue(sim->t_, [](double, const Setpoint&) {});
  sim->stepper_->restore(st.next_step_s, st.last_step_s, st.counts);
  sim->max_residual_ = st.max_residual;
  sim->max_axial_force_ = st.max_axial_force_N;
  sim->max_penetration_ = st.max_penetration_m;
  sim->wall_s_ = st.wall_time_s;
  return sim;
}

void Simulation::step(double t_limit) {
  // No step across the end of a core speed ramp (RotatingCore::rampEnd);
  // a ramp end within rounding of t is passed.
  // The ramp under way at the step's start, for a failure's message.
  Ramp ramp;
  if (const RotatingCore* core = model_->core()) {
    const double t_ramp = core->rampEnd();
    if (t_ramp < t_limit && t_ramp > t_ + 1e-12 * std::max(1.0, std::abs(t_))) t_limit = t_ramp;
    ramp = {t_ramp, std::abs(core->angularAcceleration(t_))};
  }
  // Nor across a command of the scene (process.commands).
  t_limit = std::min(t_limit, commands_.nextTime());
  // Nor across a commanded port sample (a velocity kink of the port).
  if (const Supply* supply = model_->supply()) {
    t_limit = std::min(t_limit, supply->portCommand().nextKink(t_));
  }
  // Implicit steps follow the process: at most one core revolution over
  // solver.steps_per_revolution, at the faster of the core's present and
  // commanded speeds (a ramp runs between them).
  const double per_revolution = scene_.solver.steps_per_revolution;
  if (const RotatingCore* core = model_->core(); core && per_revolution > 0.0) {
    constexpr double kTwoPi = 6.283185307179586;
    const double omega = std::max(std::abs(core->omega(t_)), std::abs(core->command()));
    double longest = std::numeric_limits<double>::infinity();
    if (omega > 0.0) {
      // To 10 significant digits: a speed given in rpm gives the step a
      // user expects (1e-4 s at 1200 rpm and 500 steps, not 1e-4 less an
      // ulp; a wound coil's path can depend on the step's last bit).
      const double exact = kTwoPi / (omega * per_revolution);
      const double digits = std::pow(10.0, 9.0 - std::floor(std::log10(exact)));
      longest = std::round(exact * digits) / digits;
    }
    stepper_->limitStep(longest);
  }
  try {
    stepper_->step(*model_, t_, y_, t_limit);
  } catch (const IntegrationError& e) {
    throw IntegrationError(withRampCause(e.what(), t_, ramp));
  }
  // One pass: a sum is finite only if every term is (states never come
  // near the overflow that could make finite terms sum to infinity).
  // (The energy terms, and the wire from the boundary point on: deferred
  // carried wire is placed, not integrated.)
  const int from = WireModel::stateOffset(std::max(model_->constants().first - 1, 1));
  if (!std::isfinite(y_.head(2).sum() + y_.segment(from, model_->size() - from).sum())) {
    throw IntegrationError("the state became non-finite at t = " + std::to_string(t_) + " s");
  }
  if (collapse_step_s_ > 0.0) checkCollapse(ramp);
  // A step that ended where a speed ramp ends: the acceleration jumps.
  if (ramp.end_s > 0.0 && std::abs(t_ - ramp.end_s) <= 1e-12 * std::max(1.0, std::abs(t_))) {
    stepper_->kink();
  }
  afterStep();
  applyDueCommands();
  if (max_residual_ > kDivergedResidual) {
    throw IntegrationError(withRampCause(
        remedy::diverged(scene_, t_, max_residual_, stepper_->name(), stepper_->lastStep()), t_,
        ramp));
  }
  // Wire wholly beyond a flange's face (its centre more than a radius
  // out), below the rim, has gone over the flange (or through it): a scrap
  // coil, which the run does not wind on. (Wire resting on the rim, and a
  // span from a port outside the flanges passing beyond it, are not; the
  // carried wire does not move.)
  if (const Contact* contact = model_->contact()) {
    const ContactGeometry& geometry = contact->geometry();
    const WireConstants& c = model_->constants();
    if (geometry.flangeSlot() >= 0) {
      for (int i = std::max(c.first - 1, 1); i < c.n; ++i) {
        const ContactGeometry::FlangeSide side =
            geometry.flangeSide(y_.segment<3>(WireModel::stateOffset(i)));
        if (side.outside_m > c.radius && side.from_axis_m < side.reach_m) {
          throw IntegrationError(remedy::overFlange(scene_, t_, i, side.flange, side.outside_m,
                                                    side.from_axis_m, side.reach_m));
        }
      }
    }
  }
  // Wire deeper than its radius in other wire has passed into it: a sound
  // coil rests a few percent of the radius deep, and from there it would be
  // pushed out with energy the run never had.
  if (const Contact* contact = model_->contact()) {
    Contact::WireDepth deep = contact->deepestInWire();
    const char* what = "wound wire";
    if (const FreeWireContact* free = model_->freeWireContact()) {
      if (free->deepest().depth_m > deep.depth_m) {
        deep = {free->deepest().depth_m, free->deepest().point, free->deepest().segment};
        what = "free wire";
      }
    }
    const double radius = model_->constants().radius;
    if (deep.depth_m > kWireThroughWire * radius) {
      throw IntegrationError(remedy::wireThroughWire(
          scene_, t_, what, deep.point, deep.depth_m / radius, deep.segment, stepper_->name()));
    }
  }
}

std::string Simulation::withRampCause(const std::string& what, double t_fail_s,
                                      const Ramp& ramp) const {
  return remedy::withinRamp(scene_, what, stepper_->name(), t_fail_s, ramp.end_s,
                            ramp.acceleration_rad_s2);
}

void Simulation::checkCollapse(const Ramp& ramp) {
  const double h = stepper_->lastStep();
  // (A single step clipped short to an end time counts once; the next
  // normal step clears the count.)
  if (h >= collapse_step_s_) {
    small_steps_ = 0;
    return;
  }
  if (small_steps_++ == 0) {
    small_since_s_ = t_ - h;
    small_ramp_ = ramp;
  }
  if (small_steps_ < kCollapseSteps) return;
  throw IntegrationError(
      withRampCause(remedy::collapsed(scene_, stepper_->name(), small_steps_, collapse_step_s_,
                                      stepper_->collapseRatio(), small_since_s_, t_, h),
                    small_since_s_, small_ramp_));
}

void Simulation::run(const std::function<void(const Simulation&)>& progress,
                     const std::function<bool()>& stop) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const double wall0 = wall_s_;
  auto last_report = start;
  const auto interval = std::chrono::duration<double>(scene_.output.progress_interval_s);
  pace_.start(PaceProfile::count(t_, wall0, *stepper_));
  while (t_ < t_end_) {
    if (stop && stop()) break;
    step(t_end_);
    const auto now = Clock::now();
    wall_s_ = wall0 + std::chrono::duration<double>(now - start).count();
    pace_.record(PaceProfile::count(t_, wall_s_, *stepper_));
    if (progress && now - last_report >= interval) {
      progress(*this);
      last_report = now;
    }
  }
  wall_s_ = wall0 + std::chrono::duration<double>(Clock::now() - start).count();
  pace_.finish(PaceProfile::count(t_, wall_s_, *stepper_));
}

void Simulation::setFriction(double mu_static, double mu_kinetic) {
  if (!scene_.physics.friction) {
    throw SceneError("physics.friction",
                     "friction is off in this scene: its coefficients do not act");
  }
  Scene next = scene_;
  next.contact.static_friction = mu_static;
  next.contact.kinetic_friction = mu_kinetic;
  validateScene(next);
  scene_ = next;
  model_->setFriction(mu_static, mu_kinetic);
}

void Simulation::setDamping(const DampingParams& d) {
  if (!scene_.physics.damping) {
    throw SceneError("physics.damping",
                     "damping is off in this scene: its coefficients do not act");
  }
  Scene next = scene_;
  next.damping = d;
  validateScene(next);
  scene_ = next;
  model_->setDamping(d);
}

}  // namespace cws
