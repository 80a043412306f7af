// wire_sim: command-line front end of the simulation core.
//
//   wire_sim run [--scene FILE] [--set key.path=value ...] [--out DIR]
//   wire_sim print-scene [--scene FILE] [--set key.path=value ...]
//   wire_sim study [--scene FILE] [--set key.path=value ...] [--out DIR] [--jobs N | --slurm ...]
//   wire_sim work-precision [--scene FILE] [--set key.path=value ...] [--out DIR] [--jobs N]
//   wire_sim stability [--scene FILE] [--set ...] [--out DIR] [--jobs N] [--only NAME] [--method M]
//                      [--budget SECONDS] [--checkpoint SECONDS] [--fresh | --report]
//   wire_sim sweep [--scene FILE] [--set ...] (--grid KEY=VALUES ... | --cases FILE)
//                  [--out DIR] [--jobs N | --slurm [--partition P] [--time T] [--mem M]
//                  [--account A] [--max-running N] [--max-array-size N] [--dry-run]]
//   wire_sim sweep-run DIR INDEX
//   wire_sim sweep-gather DIR
//   wire_sim urdf [--scene FILE] [--set ...] [--overrides "[key=value, ...]"]
//                 [--on-error fail|world]
#include <signal.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "calibrate.hpp"
#include "cell_urdf.hpp"
#include "coil_winding_sim/core/base/text_format.hpp"
#include "coil_winding_sim/core/run/output.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"
#include "coil_winding_sim/core/scene/integrators.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"
#include "coil_winding_sim/ros/offline_replay.hpp"
#include "stability.hpp"
#include "study.hpp"
#include "sweep.hpp"
#include "sweep_slurm.hpp"
#include "wire_sim_usage.hpp"
#include "work_precision.hpp"

#ifndef CWS_DEFAULT_SCENE
#define CWS_DEFAULT_SCENE ""
#endif

namespace {

struct Args {
  std::string command;
  std::string scene;
  std::vector<std::string> overrides;
  std::string out;
  int jobs = 2;
  bool error_estimate = false;            // run: --error-estimate
  cws_tools::StabilityOptions stability;  // --only, --budget, --checkpoint, --fresh
  std::vector<cws_tools::GridAxis> grid;  // sweep: --grid
  std::string cases;                      // sweep: --cases
  double sweep_budget_s = 0.0;            // sweep: --budget (0: none)
  std::vector<std::string> positional;    // sweep-run DIR INDEX, sweep-gather DIR
  bool slurm = false;                     // sweep: --slurm
  cws_tools::SlurmOptions slurm_options;  // --partition, --time, ... --dry-run
};

// Exit codes: 0 success, 1 the run failed, 2 bad command line or scene,
// 128 + N stopped by signal N.
int usageError(const std::string& msg) {
  std::cerr << "wire_sim: " << msg << "\n" << cws_tools::kWireSimUsage;
  return 2;
}

// An output directory that cannot be used (exit 2, like a bad option).
class OutDirError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Creates and probes the output directory; a failure is the --out option's.
void checkOut(const std::string& dir) {
  try {
    cws::checkOutputDir(dir);
  } catch (const std::exception& e) {
    throw OutDirError(std::string("bad --out: ") + e.what());
  }
}

// SIGINT / SIGTERM during `run`: the signal number, and the run stops after
// its current step. SA_RESETHAND restores the default action, so a second
// signal ends the process at once (a step that never ends).
volatile std::sig_atomic_t g_stop_signal = 0;

void onStopSignal(int sig) { g_stop_signal = sig; }

void installStopHandlers() {
  struct sigaction sa {};
  sa.sa_handler = onStopSignal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

bool stopRequested() { return g_stop_signal != 0; }

// This program's path, for the processes a sweep starts.
std::string selfExe() { return std::filesystem::read_symlink("/proc/self/exe").string(); }

std::string defaultScene() {
  // Installed or source-tree default scene; empty means built-in defaults.
  const std::string path = CWS_DEFAULT_SCENE;
  if (!path.empty() && std::filesystem::exists(path)) return path;
  return "";
}

int run(const Args& a) {
  const std::string scene_path = a.scene.empty() ? defaultScene() : a.scene;
  // The scene first (a refused scene leaves the output directory untouched),
  // then the output directory; both before anything runs.
  const cws::Scene scene = cws::loadScene(scene_path, a.overrides);
  if (a.command == "print-scene") {
    std::cout << cws::sceneToYamlText(scene);
    return 0;
  }
  if (a.command == "work-precision") {
    const std::string out = a.out.empty() ? "out/work_precision" : a.out;
    checkOut(out);
    return cws_tools::runWorkPrecision(scene_path, a.overrides, out, a.jobs);
  }
  if (a.command == "stability") {
    const std::string out = a.out.empty() ? "out/stability" : a.out;
    checkOut(out);
    cws_tools::StabilityOptions o = a.stability;
    o.jobs = a.jobs;
    o.stop = [] { return g_stop_signal != 0; };
    const int rc = cws_tools::runStability(scene_path, a.overrides, out, o,
                                           a.slurm ? &a.slurm_options : nullptr, selfExe());
    return rc < 0 ? 128 + g_stop_signal : rc;
  }
  if (a.command == "sweep") {
    const std::string out = a.out.empty() ? "out/sweep" : a.out;
    cws_tools::SweepPlan plan;
    if (!a.cases.empty()) {
      plan = cws_tools::readCasesFile(scene_path, a.overrides, a.cases);
    } else {
      plan = cws_tools::gridPlan(scene_path, a.overrides, a.grid);
    }
    // A relative scene path would not hold for a case run elsewhere.
    if (!plan.scene.empty()) plan.scene = std::filesystem::absolute(plan.scene).string();
    if (a.sweep_budget_s > 0.0)
      plan.options.emplace_back("budget", cws::formatNumber(a.sweep_budget_s, "%.17g"));
    cws_tools::checkPlan(plan);
    checkOut(out);
    if (a.slurm) return cws_tools::runSweepSlurm(plan, out, a.slurm_options, selfExe());
    const int rc = cws_tools::runSweepLocal(plan, out, a.jobs, selfExe(), stopRequested);
    return rc < 0 ? 128 + g_stop_signal : rc;
  }
  if (a.command == "study") {
    const std::string out = a.out.empty() ? "out/study" : a.out;
    checkOut(out);
    const int rc =
        cws_tools::runStudy(scene_path, a.overrides, out, a.jobs,
                            a.slurm ? &a.slurm_options : nullptr, selfExe(), stopRequested);
    return rc < 0 ? 128 + g_stop_signal : rc;
  }
  // Remove the results of an earlier run, so that a failed or stopped run
  // leaves no valid-looking summary.
  const std::string out = a.out.empty() ? "out/run" : a.out;
  checkOut(out);
  try {
    cws::removeOutputs(out);
  } catch (const std::exception& e) {
    throw OutDirError(std::string("bad --out: ") + e.what());
  }

  cws::Simulation sim(scene);
  std::cerr << "wire_sim: " << sim.model().constants().n << " points, " << sim.stepper().name()
            << ", until t = " << sim.endTime() << " s\n";
  // A run that ends early (a signal, or an error it cannot go on from)
  // writes the state it reached, marked "stopped" in summary.json.
  try {
    // The time left at the pace since the last progress line, not the
    // run's mean: a run that slows down (a crawl) says so.
    double last_t = sim.time(), last_wall = sim.wallTime();
    sim.run(
        [&](const cws::Simulation& s) {
          const double rtf = s.realTimeFactor();
          const double recent =
              s.wallTime() > last_wall ? (s.time() - last_t) / (s.wallTime() - last_wall) : rtf;
          last_t = s.time();
          last_wall = s.wallTime();
          const double remaining = recent > 0.0 ? (s.endTime() - s.time()) / recent : 0.0;
          std::fprintf(stderr,
                       "  t = %.6f s of %.6f s, real-time factor %.3g (%.3g lately), ~%.0f s "
                       "left, step %.3g s\n",
                       s.time(), s.endTime(), rtf, recent, remaining, s.stepper().lastStep());
        },
        [] { return g_stop_signal != 0; });
  } catch (const cws::IntegrationError& e) {
    const cws::RunStop stop{"error", e.what()};
    cws::writeOutputs(sim, out, nullptr, &stop);
    std::fprintf(stderr, "wire_sim: the partial results up to t = %.6g s are in %s (\"stopped\")\n",
                 sim.time(), out.c_str());
    throw;
  }
  if (g_stop_signal != 0) {
    const int sig = g_stop_signal;
    const char* name = sig == SIGINT ? "SIGINT" : "SIGTERM";
    char text[200];
    std::snprintf(text, sizeof text, "stopped by %s at t = %.6g s of %.6g s", name, sim.time(),
                  sim.endTime());
    const cws::RunStop stop{name, text};
    cws::writeOutputs(sim, out, nullptr, &stop);
    std::fprintf(stderr, "wire_sim: %s; the partial results are in %s (\"stopped\")\n", text,
                 out.c_str());
    return 128 + sig;
  }
  // --error-estimate: the same scene again, refined, and the difference.
  std::unique_ptr<cws::ErrorEstimate> estimate;
  if (a.error_estimate) {
    std::string refinement;
    cws::Simulation refined(cws::refinedScene(scene, refinement));
    std::fprintf(stderr, "wire_sim: error estimate: the scene again with %s\n", refinement.c_str());
    refined.run({}, [] { return g_stop_signal != 0; });
    if (g_stop_signal != 0) {
      const int sig = g_stop_signal;
      const char* name = sig == SIGINT ? "SIGINT" : "SIGTERM";
      const cws::RunStop stop{name, std::string("stopped by ") + name +
                                        " during the error estimate (the run itself finished)"};
      cws::writeOutputs(sim, out, nullptr, &stop);
      std::fprintf(stderr,
                   "wire_sim: stopped by %s during the error estimate; the run's results, without "
                   "the estimate, are in %s (\"stopped\")\n",
                   name, out.c_str());
      return 128 + sig;
    }
    estimate =
        std::make_unique<cws::ErrorEstimate>(cws::compareWithRefined(sim, refined, refinement));
  }
  cws::writeOutputs(sim, out, estimate.get());
  const cws::EnergyReport e = sim.energy();
  // The method that ran, and in one line how to get the converged explicit
  // reference of the same model, and the run's own error.
  std::printf(
      "done: %s, t = %.6g s in %.3g s wall (real-time factor %.3g), %ld steps (%ld rejected)\n"
      "      max constraint residual %.3g, max axial force %.4g N, energy imbalance %.3g J\n"
      "      results in %s/summary.json and %s/wire.csv\n"
      "      converged reference: --set solver.integrator=symplectic_euler (make reference); "
      "this run's error: --error-estimate (docs/PERFORMANCE.md)\n",
      sim.stepper().name(), sim.time(), sim.wallTime(), sim.realTimeFactor(),
      sim.stepper().counts().accepted, sim.stepper().counts().rejected, sim.maxConstraintResidual(),
      sim.maxAxialForce(), e.imbalance(), out.c_str(), out.c_str());
  if (estimate) {
    std::printf(
        "      error estimate (against the scene with %s): shape %.3g of the wire "
        "diameter, bulging %.3g, in %.3g s against %.3g s\n",
        estimate->refinement.c_str(), estimate->shape_error_rel_diameter,
        estimate->bulging_error_rel, estimate->wall_s, estimate->refined_wall_s);
  }
  const cws::BulgeReport b = cws::headlineBulging(sim.model(), sim.scene());
  if (b.valid) {
    std::printf(
        "      bulging height %.4f mm at point %d (%.1f mm from the fixed end), "
        "%.3f core turns, %.1f mm of wire fed\n",
        1e3 * b.height_m, b.index, 1e3 * b.arc_length_m, sim.coreTurns(),
        1e3 * sim.model().fedLength());
    if (sim.scene().physics.wire_contact) {
      std::printf("      build-up of the layers %.4f mm (the largest stand-off from the core)\n",
                  1e3 * b.build_up_m);
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty()) {
    std::cerr << cws_tools::kWireSimUsage;
    return 2;
  }
  for (const std::string& arg : args) {
    if (arg == "--help" || arg == "-h") {
      std::cout << cws_tools::kWireSimUsage;
      return 0;
    }
  }
  Args a;
  a.command = args[0];
  if (a.command == "urdf") return cws_tools::urdfMain(args, defaultScene());
  if (a.command == "replay") return cws_ros::replayMain(args, defaultScene());
  if (a.command == "calibrate") {
    // Ctrl-C: the running replays stop, the best so far is written.
    installStopHandlers();
    const int rc = cws_tools::calibrateMain(args, defaultScene(), selfExe(), stopRequested);
    return rc < 0 ? 128 + (g_stop_signal ? g_stop_signal : SIGINT) : rc;
  }
  // sweep-run DIR INDEX and sweep-gather DIR: a sweep's case, its table.
  if (a.command == "sweep-run" || a.command == "sweep-gather") {
    const std::size_t want = a.command == "sweep-run" ? 3 : 2;
    if (args.size() != want) {
      return usageError(
          a.command + " takes " +
          (want == 3 ? "a sweep's directory and a case index" : "a sweep's directory"));
    }
    try {
      if (a.command == "sweep-gather") return cws_tools::gatherSweep(args[1]);
      std::size_t used = 0;
      const unsigned long index = std::stoul(args[2], &used);
      if (used != args[2].size()) throw std::invalid_argument(args[2]);
      // SIGINT from the sweep, SIGTERM from Slurm at a task's time limit:
      // the case stops after its current step (a stability run keeps a
      // checkpoint) and stays pending.
      installStopHandlers();
      const int rc = cws_tools::runSweepCase(args[1], index, stopRequested);
      return rc < 0 ? 128 + g_stop_signal : rc;
    } catch (const cws_tools::SweepError& e) {
      std::cerr << "wire_sim: " << e.what() << "\n";
      return 2;
    } catch (const std::invalid_argument&) {
      return usageError("sweep-run: the case index '" + args[2] + "' is not a whole number");
    } catch (const std::exception& e) {
      std::cerr << "wire_sim: " << a.command << " failed: " << e.what() << "\n";
      return 1;
    }
  }
  if (a.command != "run" && a.command != "print-scene" && a.command != "study" &&
      a.command != "work-precision" && a.command != "stability" && a.command != "sweep") {
    return usageError("unknown command '" + a.command + "'");
  }
  const bool takes_out = a.command != "print-scene";
  const bool takes_jobs = a.command == "study" || a.command == "work-precision" ||
                          a.command == "stability" || a.command == "sweep";
  const bool sweep = a.command == "sweep";
  bool seen_cases = false;
  const bool stability = a.command == "stability";
  bool seen_scene = false, seen_out = false, seen_jobs = false, seen_only = false,
       seen_method = false, seen_budget = false, seen_checkpoint = false, seen_fresh = false,
       seen_estimate = false, seen_slurm = false, seen_dry_run = false;
  const bool takes_slurm = sweep || stability || a.command == "study";
  std::vector<std::string> slurm_given;  // Slurm's options, refused without --slurm
  for (std::size_t i = 1; i < args.size(); ++i) {
    const std::string& opt = args[i];
    // The option's value: present and not empty (an empty --scene or --out,
    // say from an unset shell variable, would silently mean the default).
    std::string value;
    auto take = [&](const char* what) -> std::string {
      if (i + 1 >= args.size()) return opt + " needs " + what;
      value = args[++i];
      if (value.empty()) return opt + " needs " + what + ", got an empty argument";
      return "";
    };
    // Each of these options once: a second one would silently win.
    auto once = [&](bool& seen) -> std::string {
      if (seen) return opt + " given twice";
      seen = true;
      return "";
    };
    std::string problem;
    if (opt == "--scene") {
      problem = once(seen_scene);
      if (problem.empty()) problem = take("a file");
      a.scene = value;
    } else if (opt == "--set") {
      problem = take("key.path=value");
      a.overrides.push_back(value);
    } else if (opt == "--out" && takes_out) {
      problem = once(seen_out);
      if (problem.empty()) problem = take("a directory");
      a.out = value;
    } else if (opt == "--jobs" && takes_jobs) {
      problem = once(seen_jobs);
      if (problem.empty()) problem = take("a number");
      if (problem.empty()) {
        try {
          std::size_t used = 0;
          a.jobs = std::stoi(value, &used);
          if (used != value.size() || a.jobs < 1 || a.jobs > 64) {
            throw std::invalid_argument(value);
          }
        } catch (const std::exception&) {
          problem = "--jobs needs a whole number from 1 to 64, got '" + value + "'";
        }
      }
    } else if (opt == "--only" && stability) {
      problem = once(seen_only);
      if (problem.empty()) problem = take("a case name");
      a.stability.only = value;
    } else if (opt == "--method" && stability) {
      problem = once(seen_method);
      if (problem.empty()) problem = take("an integrator");
      if (problem.empty() && !cws::findIntegrator(value)) {
        std::string names;
        for (const std::string& n : cws::integratorNames())
          names += (names.empty() ? "" : ", ") + n;
        problem = "--method: unknown integrator '" + value + "' (available: " + names + ")";
      }
      a.stability.method = value;
    } else if ((opt == "--budget" && (stability || sweep)) ||
               (opt == "--checkpoint" && stability)) {
      const bool budget = opt == "--budget";
      problem = once(budget ? seen_budget : seen_checkpoint);
      if (problem.empty()) problem = take("seconds");
      if (problem.empty()) {
        double& seconds =
            !budget ? a.stability.checkpoint_s : (sweep ? a.sweep_budget_s : a.stability.budget_s);
        try {
          std::size_t used = 0;
          seconds = std::stod(value, &used);
          if (used != value.size() || !(seconds > 0.0) || !std::isfinite(seconds)) {
            throw std::invalid_argument(value);
          }
        } catch (const std::exception&) {
          problem = opt + " needs a positive number of seconds, got '" + value + "'";
        }
      }
    } else if (opt == "--grid" && sweep) {
      problem = take("KEY=VALUES");
      if (problem.empty()) {
        try {
          a.grid.push_back(cws_tools::parseGridAxis(value));
        } catch (const cws_tools::SweepError& e) {
          problem = e.what();
        }
      }
    } else if (opt == "--cases" && sweep) {
      problem = once(seen_cases);
      if (problem.empty()) problem = take("a CSV file");
      a.cases = value;
    } else if (opt == "--slurm" && takes_slurm) {
      problem = once(seen_slurm);
      a.slurm = true;
    } else if (opt == "--dry-run" && takes_slurm) {
      problem = once(seen_dry_run);
      a.slurm_options.dry_run = true;
      slurm_given.push_back(opt);
    } else if (cws_tools::isSlurmValueOption(opt) && takes_slurm) {
      problem = take("a value");
      if (problem.empty()) problem = cws_tools::setSlurmOption(a.slurm_options, opt, value);
      slurm_given.push_back(opt);
    } else if (opt == "--error-estimate" && a.command == "run") {
      problem = once(seen_estimate);
      a.error_estimate = true;
    } else if ((opt == "--fresh" || opt == "--report") && stability) {
      if (seen_fresh) {
        problem = "--fresh and --report exclude each other, and each comes once";
      }
      seen_fresh = true;
      (opt == "--fresh" ? a.stability.fresh : a.stability.report_only) = true;
    } else if (!opt.empty() && opt[0] == '-') {
      problem = "unknown option '" + opt + "' for " + a.command + " (it takes --scene, --set" +
                (takes_out ? ", --out" : "") + (takes_jobs ? ", --jobs" : "") +
                (a.command == "run" ? ", --error-estimate" : "") +
                (stability ? ", --only, --method, --budget, --checkpoint, --fresh, --report" : "") +
                (sweep ? ", --grid, --cases, --budget" : "") +
                (takes_slurm ? ", --slurm, --partition, --time, --mem, --account, --max-running, "
                               "--max-array-size, --dry-run"
                             : "") +
                ")";
    } else {
      problem = "unexpected argument '" + opt + "' (options come as --scene FILE, --set ...)";
    }
    if (!problem.empty()) return usageError(problem);
  }
  if (sweep && !a.cases.empty() && !a.grid.empty()) {
    return usageError("--grid and --cases exclude each other");
  }
  if (!a.slurm && !slurm_given.empty()) {
    return usageError(slurm_given.front() +
                      " is an option of --slurm (the sweep runs locally without it)");
  }
  if (a.slurm && seen_jobs) {
    return usageError(
        "--jobs runs cases on this machine; with --slurm, --max-running N limits the tasks at "
        "once");
  }
  if (a.command == "run" || stability || sweep || a.command == "study") installStopHandlers();
  try {
    return run(a);
  } catch (const cws::SceneError& e) {
    std::cerr << "wire_sim: bad scene: " << e.what() << "\n";
    return 2;
  } catch (const cws_tools::SweepError& e) {
    std::cerr << "wire_sim: " << e.what() << "\n";
    return 2;
  } catch (const OutDirError& e) {
    std::cerr << "wire_sim: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "wire_sim: run failed: " << e.what() << "\n";
    return 1;
  }
}
