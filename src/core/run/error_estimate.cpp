#include "coil_winding_sim/core/run/error_estimate.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "coil_winding_sim/core/run/coil_report.hpp"
#include "coil_winding_sim/core/run/input_log.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"
#include "coil_winding_sim/core/scene/integrators.hpp"

namespace cws {

namespace {
// The Newton-step methods' refinement of the step.
constexpr double kNewtonRefinement = 0.25;

bool newtonSteps(const Scene& scene) {
  const IntegratorInfo* info = findIntegrator(scene.solver.integrator);
  return info && info->newton_steps;
}

// Point i at the end of a run, in the core frame where there is a core.
Eigen::Vector3d pointOf(const Simulation& sim, int i) {
  const WireModel& m = sim.model();
  return m.core() ? wirePointCore(m, i) : wirePoint(m, i).p_world;
}

// How many points the wound curve of a run holds: to its last point on the core
// (the whole wire where nothing is wound).
int woundCount(const Simulation& sim) {
  const BulgeReport b = bulging(sim.model());
  const int n = sim.model().wirePoints();
  return b.valid && b.wound_points >= 2 ? std::min(b.wound_points, n) : n;
}

// Its first `count` points, core frame.
std::vector<Eigen::Vector3d> curveOf(const Simulation& sim, int count) {
  std::vector<Eigen::Vector3d> curve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) curve[static_cast<std::size_t>(i)] = pointOf(sim, i);
  return curve;
}

double pointSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d d = b - a;
  const double len2 = d.squaredNorm();
  const double s = len2 > 0.0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + s * d)).norm();
}

// The largest distance of a's points from polyline b (one way).
double oneWay(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b) {
  const int nb = static_cast<int>(b.size());
  double worst = 0.0;
  for (int i = 0; i < static_cast<int>(a.size()); ++i) {
    const auto& p = a[static_cast<std::size_t>(i)];
    if (nb == 1) {
      worst = std::max(worst, (p - b[0]).norm());
      continue;
    }
    double best = std::numeric_limits<double>::infinity();
    const int from = std::clamp(i - kCurveWindow, 0, nb - 2);
    const int to = std::clamp(i + kCurveWindow, 0, nb - 2);
    for (int j = from; j <= to; ++j) {
      best = std::min(best, pointSegment(p, b[static_cast<std::size_t>(j)],
                                         b[static_cast<std::size_t>(j + 1)]));
    }
    worst = std::max(worst, best);
  }
  return worst;
}
}  // namespace

double refinementScale(const Scene& scene) {
  return newtonSteps(scene) ? 1.0 / (1.0 - kNewtonRefinement) : 1.0;
}

Scene refinedScene(const Scene& scene, std::string& refinement) {
  Scene s = scene;
  const IntegratorInfo* info = findIntegrator(s.solver.integrator);
  if (info && info->explicit_fixed_step) {
    s.solver.fixed_step = 0.5 * fixedStep(scene);
    refinement = "solver.fixed_step / 2";
  } else if (info && info->newton_steps) {
    s.solver.implicit_step *= kNewtonRefinement;
    s.solver.steps_per_revolution /= kNewtonRefinement;
    s.solver.strike_step *= kNewtonRefinement;
    refinement =
        "a quarter of the step (solver.implicit_step and solver.strike_step / 4, "
        "solver.steps_per_revolution x 4), the difference x 4/3";
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
  // The step the stepper resumes with, refined alike (the Newton-step
  // methods resume with it; an explicit fixed step comes from the scene).
  st.next_step_s *= newtonSteps(scene) ? kNewtonRefinement : 0.5;
  return st;
}

double curveDistance(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b) {
  if (a.empty() || b.empty()) return 0.0;
  return std::max(oneWay(a, b), oneWay(b, a));
}

RunDifference differenceOf(const Simulation& run, const Simulation& other) {
  RunDifference d;
  // The part both wound (one run may have one more point down on the core:
  // that point would stand a segment beyond the other curve's end).
  const int count = std::min(woundCount(run), woundCount(other));
  d.shape_rel_diameter =
      curveDistance(curveOf(run, count), curveOf(other, count)) / run.scene().wire.diameter;
  const BulgeReport a = headlineBulging(run.model(), run.scene()),
                    b = headlineBulging(other.model(), other.scene());
  if (a.valid && b.valid && b.height_m > 0.0) {
    d.bulging_valid = true;
    d.bulging_rel = std::abs(a.height_m - b.height_m) / b.height_m;
  }
  return d;
}

ErrorEstimate compareWithRefined(const Simulation& run, const Simulation& refined,
                                 const std::string& refinement) {
  ErrorEstimate e;
  e.refinement = refinement;
  e.scale = refinementScale(run.scene());
  e.wall_s = run.wallTime();
  e.refined_wall_s = refined.wallTime();
  const RunDifference d = differenceOf(run, refined);
  e.shape_error_rel_diameter = e.scale * d.shape_rel_diameter;
  e.bulging_valid = d.bulging_valid;
  e.bulging_error_rel = e.scale * d.bulging_rel;
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
