#include "work_precision.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <mutex>
#include <sstream>

#include "coil_winding_sim/core/run/output.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"
#include "coil_winding_sim/core/scene/integrators.hpp"
#include "parallel.hpp"

namespace cws_tools {

namespace fs = std::filesystem;

namespace {

struct Run {
  std::string name, method, setting;
  std::vector<std::string> overrides;
  bool ok = false;
  std::string error;
  double wall_s = 0.0, sim_s = 0.0, bulging_m = 0.0;
  long steps = 0, evaluations = 0;
  int points = 0;
  Eigen::Matrix3Xd p_core;  // final wire in the core frame
};

void execute(const std::string& scene_path, const std::vector<std::string>& base,
             const std::string& dir, Run& r, std::mutex& log) {
  const auto start = std::chrono::steady_clock::now();
  try {
    std::vector<std::string> o = base;
    o.insert(o.end(), r.overrides.begin(), r.overrides.end());
    cws::Simulation sim(cws::loadScene(scene_path, o));
    sim.run();
    cws::writeOutputs(sim, (fs::path(dir) / r.name).string());
    const cws::WireModel& m = sim.model();
    r.points = m.wirePoints();
    r.p_core.resize(3, r.points);
    for (int i = 0; i < r.points; ++i) {
      r.p_core.col(i) = m.core() ? cws::wirePointCore(m, i) : cws::wirePoint(m, i).p_world;
    }
    const cws::BulgeReport b = cws::headlineBulging(m, sim.scene());
    r.bulging_m = b.valid ? b.height_m : 0.0;
    r.wall_s = sim.wallTime();
    r.sim_s = sim.time();
    r.steps = sim.stepper().counts().accepted + sim.stepper().counts().rejected;
    r.evaluations = sim.stepper().counts().derivative_evaluations;
    r.ok = true;
    std::lock_guard<std::mutex> lock(log);
    std::cerr << "work-precision: " << r.name << " done in " << r.wall_s << " s\n";
  } catch (const std::exception& e) {
    r.error = e.what();
    r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::lock_guard<std::mutex> lock(log);
    std::cerr << "work-precision: " << r.name << " failed: " << e.what() << "\n";
  }
}

Run make(const std::string& method, const std::string& setting,
         const std::vector<std::string>& overrides) {
  Run r;
  r.method = method;
  r.setting = setting;
  r.name = method + "_" + setting;
  r.overrides = overrides;
  r.overrides.push_back("solver.integrator=" + method);
  // The full model unless a run says otherwise (the scene may carry wire).
  r.overrides.insert(r.overrides.begin(), "solver.carry_stuck_wire=false");
  return r;
}

}  // namespace

int runWorkPrecision(const std::string& scene_path, const std::vector<std::string>& overrides,
                     const std::string& dir, int jobs) {
  const cws::Scene scene = cws::loadScene(scene_path, overrides);  // refuse a bad scene first
  cws::checkOutputDir(dir);
  const double diameter = scene.wire.diameter;

  // The reference (full model) and the sweeps: RKF45 over tolerances, the
  // fixed-step method over steps (each halving), with and without carried
  // wire; the implicit method over tolerances.
  std::vector<Run> runs;
  runs.push_back(make("rkf45", "reference", {"solver.rtol=1e-8", "solver.atol=1e-13"}));
  for (const char* tol : {"1e-4", "1e-5", "1e-6"}) {
    const double atol = std::stod(tol) * 1e-5;
    std::ostringstream a;
    a << atol;
    runs.push_back(make("rkf45", std::string("rtol") + tol,
                        {std::string("solver.rtol=") + tol, "solver.atol=" + a.str()}));
  }
  for (const char* h : {"8e-7", "4e-7", "2e-7", "1e-7", "5e-8"}) {
    runs.push_back(
        make("symplectic_euler", std::string("h") + h, {std::string("solver.fixed_step=") + h}));
  }
  // The same with the stuck wound wire carried by the core (what leaving it
  // out of the integrated system saves and costs in accuracy).
  for (const char* h : {"4e-7", "2e-7", "1e-7", "5e-8"}) {
    Run r = make("symplectic_euler", std::string("h") + h,
                 {std::string("solver.fixed_step=") + h, "solver.carry_stuck_wire=true"});
    r.method = "symplectic_euler+carry";
    r.name = "symplectic_euler_carry_h" + std::string(h);
    runs.push_back(r);
  }
  // Model uncertainty beside the step's error: the paper's undamped contact
  // springs as printed (contact.damping_ratio 0) against the reference of
  // the scene's model, at two converged explicit steps.
  for (const char* h : {"2e-7", "1e-7"}) {
    Run r = make("symplectic_euler", std::string("h") + h,
                 {std::string("solver.fixed_step=") + h, "contact.damping_ratio=0"});
    r.method = "model:damping_ratio=0";
    r.name = "model_damping0_h" + std::string(h);
    runs.push_back(r);
  }
  // The Newton-step methods over steps from 1e-6 to 1e-3 s,
  // with the wound wire carried (their intended use).
  for (const cws::IntegratorInfo& info : cws::integrators()) {
    if (!info.newton_steps) continue;
    for (const char* h : {"1e-3", "3e-4", "1e-4", "3e-5", "1e-5", "3e-6", "1e-6"}) {
      Run r = make(info.name, std::string("h") + h,
                   {std::string("solver.implicit_step=") + h, "solver.steps_per_revolution=0",
                    "solver.carry_stuck_wire=true"});
      r.method = std::string(info.name) + "+carry";
      r.name = std::string(info.name) + "_carry_h" + h;
      runs.push_back(r);
    }
  }
  // Results of an earlier sweep go first, so that none is taken for this one's.
  for (const Run& r : runs) cws::removeOutputs((fs::path(dir) / r.name).string());
  {
    std::error_code ec;
    fs::remove(fs::path(dir) / "work_precision.csv", ec);
    if (ec) throw std::runtime_error("cannot remove an earlier work_precision.csv in " + dir);
  }
  std::mutex log;
  forEachParallel(runs.size(), jobs,
                  [&](std::size_t i) { execute(scene_path, overrides, dir, runs[i], log); });

  const Run& ref = runs.front();
  if (!ref.ok) {
    std::cerr << "work-precision: the reference run failed: " << ref.error << "\n";
    return 1;
  }
  std::ostringstream csv;
  csv << "method,setting,shape_error_rel_diameter,bulging_error_rel,bulging_height_mm,points,"
         "reference_points,steps,derivative_evaluations,wall_time_s,real_time_factor,error\n";
  bool all_ok = true;
  for (std::size_t k = 1; k < runs.size(); ++k) {
    const Run& r = runs[k];
    if (!r.ok) {
      all_ok = false;
      // Failed: the wall time until it stopped, and why (quoted).
      std::string why = r.error;
      std::replace(why.begin(), why.end(), '"', '\'');
      csv << r.method << ',' << r.setting << ",failed,,,,,,," << r.wall_s << ",,\"" << why
          << "\"\n";
      continue;
    }
    // Largest point distance over the points both runs have, in the core
    // frame; a different point count is itself reported.
    const int common = std::min(r.points, ref.points);
    double worst = 0.0;
    for (int i = 0; i < common; ++i) {
      worst = std::max(worst, (r.p_core.col(i) - ref.p_core.col(i)).norm());
    }
    const double bulge_err =
        ref.bulging_m > 0.0 ? std::abs(r.bulging_m - ref.bulging_m) / ref.bulging_m : 0.0;
    char line[512];
    std::snprintf(line, sizeof line, "%s,%s,%.4e,%.4e,%.5f,%d,%d,%ld,%ld,%.3f,%.4g,\n",
                  r.method.c_str(), r.setting.c_str(), worst / diameter, bulge_err,
                  1e3 * r.bulging_m, r.points, ref.points, r.steps, r.evaluations, r.wall_s,
                  r.sim_s / r.wall_s);
    csv << line;
  }
  char ref_line[256];
  std::snprintf(ref_line, sizeof ref_line,
                "# reference: rkf45 rtol 1e-8 atol 1e-13, %.1f s wall, "
                "bulging %.5f mm, %d points\n",
                ref.wall_s, 1e3 * ref.bulging_m, ref.points);
  cws::writeFileAtomically((fs::path(dir) / "work_precision.csv").string(), csv.str() + ref_line);
  std::cout << csv.str() << ref_line;
  // A method failing on the scene is a result (in the CSV), not an error of
  // the command; only a failed reference is.
  if (!all_ok) std::cerr << "work-precision: some runs failed; see the error column\n";
  return 0;
}

}  // namespace cws_tools
