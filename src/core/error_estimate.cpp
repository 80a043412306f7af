#include "coil_winding_sim/core/error_estimate.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "coil_winding_sim/core/input_log.hpp"
#include "coil_winding_sim/core/simulation.hpp"
#include "coil_winding_sim/core/time_steppers/integrators.hpp"

namespace cws {

Scene refinedScene(const Scene& scene, std::string& refinement) {
  Scene s = scene;
  const IntegratorInfo* info = findIntegrator(s.solver.integrator);
  if (info && info->explicit_fixed_step) {
    s.solver.fixed_step = 0.5 * fixedStep(scene);
    refinement = "solver.fixed_step / 2";
  } else if (info && info->newton_steps) {
    s.solver.implicit_step *= 0.5;
    refinement = "solver.implicit_step / 2";
  } else {
    s.solver.rtol *= 0.1;
    s.solver.atol *= 0.1;
    refinement = "solver.rtol and solver.atol / 10";
  }
  return s;
}

SimulationState refinedState(const SimulationState& start, std::string& refinement) {
  SimulationState st = start;
  const Scene scene = sceneFromYamlText(start.scene_yaml);
  const Scene refined = refinedScene(scene, refinement);
  st.scene_yaml = sceneToYamlText(refined);
  // The step the stepper resumes with, halved too (the Newton-step methods
  // resume with it; an explicit fixed step comes from the scene).
  st.next_step_s *= 0.5;
  return st;
}

namespace {
// Point i at the end of a run, in the core frame where there is a core.
Eigen::Vector3d pointOf(const Simulation& sim, int i) {
  const Eigen::Vector3d p = sim.model().committed().p_world.col(i);
  const RotatingCore* core = sim.model().core();
  return core ? core->pointCore(sim.time(), p) : p;
}
}  // namespace

ErrorEstimate compareWithRefined(const Simulation& run, const Simulation& refined,
                                 const std::string& refinement) {
  ErrorEstimate e;
  e.refinement = refinement;
  e.wall_s = run.wallTime();
  e.refined_wall_s = refined.wallTime();
  const int common = std::min(run.model().constants().n, refined.model().constants().n);
  double worst = 0.0;
  for (int i = 0; i < common; ++i) {
    worst = std::max(worst, (pointOf(run, i) - pointOf(refined, i)).norm());
  }
  e.shape_error_rel_diameter = worst / run.scene().wire.diameter;
  const BulgeReport a = run.model().bulging(), b = refined.model().bulging();
  if (a.valid && b.valid && b.height_m > 0.0) {
    e.bulging_valid = true;
    e.bulging_error_rel = std::abs(a.height_m - b.height_m) / b.height_m;
  }
  return e;
}

std::optional<ErrorEstimate> estimateFromInputs(const SimulationState& start,
                                                const InputLog& inputs, const Simulation& finished,
                                                const std::function<bool()>& stop) {
  std::string refinement;
  const auto wall0 = std::chrono::steady_clock::now();
  std::unique_ptr<Simulation> refined = Simulation::fromState(refinedState(start, refinement));
  if (!inputs.replay(*refined, finished.time(), stop)) return std::nullopt;
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  ErrorEstimate e = compareWithRefined(finished, *refined, refinement);
  e.refined_wall_s = wall_s;
  return e;
}

}  // namespace cws
