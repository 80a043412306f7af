// wire_sim: command-line front end of the simulation core.
//
//   wire_sim run [--scene FILE] [--set key.path=value ...] [--out DIR]
//   wire_sim print-scene [--scene FILE] [--set key.path=value ...]
//   wire_sim study [--scene FILE] [--set key.path=value ...] [--out DIR] [--jobs N]
//   wire_sim work-precision [--scene FILE] [--set key.path=value ...] [--out DIR] [--jobs N]
//   wire_sim stability [--scene FILE] [--set ...] [--out DIR] [--jobs N] [--only NAME]
//                      [--budget SECONDS]
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "coil_winding_sim/core/output.hpp"
#include "coil_winding_sim/core/scene.hpp"
#include "coil_winding_sim/core/simulation.hpp"
#include "stability.hpp"
#include "study.hpp"
#include "work_precision.hpp"

#ifndef CWS_DEFAULT_SCENE
#define CWS_DEFAULT_SCENE ""
#endif

namespace {

const char* kUsage =
    "usage: wire_sim run [--scene FILE] [--set key.path=value ...] [--out DIR]\n"
    "       wire_sim print-scene [--scene FILE] [--set key.path=value ...]\n"
    "       wire_sim study [--scene FILE] [--set key.path=value ...] [--out DIR] [--jobs N]\n"
    "       wire_sim work-precision [--scene FILE] [--set ...] [--out DIR] [--jobs N]\n"
    "       wire_sim stability [--scene FILE] [--set ...] [--out DIR] [--jobs N] [--only NAME]\n"
    "                          [--budget SECONDS]\n"
    "Without --scene the package's default scene is used; --out defaults to out/run\n"
    "(out/study for study). study runs the paper's 2 x 2 case study (600/1200 rpm x\n"
    "30/70 N, 1 3/4 turns) on N threads (default 2) and writes tables of the results.\n"
    "work-precision runs the scene with every integrator over a range of tolerances or\n"
    "steps against a tight reference and writes the errors and wall times (CSV).\n"
    "stability runs the extreme cases of docs/STABILITY.md (those whose name contains\n"
    "NAME) with every integrator, checks each run against the stability criteria and\n"
    "writes DIR/STABILITY.md and DIR/stability.csv (default out/stability); a run\n"
    "longer than SECONDS of wall time (default 1800) is stopped and reported.\n";

struct Args {
  std::string command;
  std::string scene;
  std::vector<std::string> overrides;
  std::string out;
  int jobs = 2;
  std::string only;         // stability: cases whose name contains this
  double budget_s = 1800.0;  // stability: wall time per run [s]
};

// Exit codes: 0 success, 1 the run failed, 2 bad command line or scene.
int usageError(const std::string& msg) {
  std::cerr << "wire_sim: " << msg << "\n" << kUsage;
  return 2;
}

std::string defaultScene() {
  // Installed or source-tree default scene; empty means built-in defaults.
  const std::string path = CWS_DEFAULT_SCENE;
  if (!path.empty() && std::filesystem::exists(path)) return path;
  return "";
}

int run(const Args& a) {
  const std::string scene_path = a.scene.empty() ? defaultScene() : a.scene;
  if (a.command == "work-precision") {
    return cws_tools::runWorkPrecision(scene_path, a.overrides,
                                       a.out.empty() ? "out/work_precision" : a.out, a.jobs);
  }
  if (a.command == "stability") {
    return cws_tools::runStability(scene_path, a.overrides,
                                   a.out.empty() ? "out/stability" : a.out, a.jobs, a.only,
                                   a.budget_s);
  }
  if (a.command == "study") {
    return cws_tools::runStudy(scene_path, a.overrides, a.out.empty() ? "out/study" : a.out,
                               a.jobs);
  }
  const cws::Scene scene = cws::loadScene(scene_path, a.overrides);
  if (a.command == "print-scene") {
    std::cout << cws::sceneToYamlText(scene);
    return 0;
  }
  // Refuse an unusable output directory before running, and remove results
  // of an earlier run so that a failed run leaves no valid-looking summary.
  const std::string out = a.out.empty() ? "out/run" : a.out;
  cws::checkOutputDir(out);
  for (const char* f : {"summary.json", "wire.csv", "shape_core.csv"}) {
    std::filesystem::remove(std::filesystem::path(out) / f);
  }

  cws::Simulation sim(scene);
  std::cerr << "wire_sim: " << sim.model().constants().n << " points, " << sim.stepper().name()
            << ", until t = " << sim.endTime() << " s\n";
  sim.run([](const cws::Simulation& s) {
    const double rtf = s.realTimeFactor();
    const double remaining = rtf > 0.0 ? (s.endTime() - s.time()) / rtf : 0.0;
    std::fprintf(stderr,
                 "  t = %.6f s of %.6f s, real-time factor %.3g, ~%.0f s left, step %.3g s\n",
                 s.time(), s.endTime(), rtf, remaining, s.stepper().lastStep());
  });
  cws::writeOutputs(sim, out);
  const cws::EnergyReport e = sim.energy();
  std::printf(
      "done: t = %.6g s in %.3g s wall (real-time factor %.3g), %ld steps (%ld rejected)\n"
      "      max constraint residual %.3g, max axial force %.4g N, energy imbalance %.3g J\n"
      "      results in %s/summary.json and %s/wire.csv\n",
      sim.time(), sim.wallTime(), sim.realTimeFactor(), sim.stepper().counts().accepted,
      sim.stepper().counts().rejected, sim.maxConstraintResidual(), sim.maxAxialForce(),
      e.imbalance(), out.c_str(), out.c_str());
  const cws::BulgeReport b = sim.model().bulging();
  if (b.valid) {
    std::printf(
        "      bulging height %.4f mm at point %d (%.1f mm from the fixed end), "
        "%.3f core turns, %.1f mm of wire fed\n",
        1e3 * b.height_m, b.index, 1e3 * b.arc_length_m, sim.coreTurns(),
        1e3 * sim.model().fedLength());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    std::cout << kUsage;
    return args.empty() ? 2 : 0;
  }
  Args a;
  a.command = args[0];
  if (a.command != "run" && a.command != "print-scene" && a.command != "study" &&
      a.command != "work-precision" && a.command != "stability") {
    return usageError("unknown command '" + a.command + "'");
  }
  for (std::size_t i = 1; i < args.size(); ++i) {
    const std::string& opt = args[i];
    auto value = [&](std::string& dst) -> bool {
      if (i + 1 >= args.size()) return false;
      dst = args[++i];
      return true;
    };
    if (opt == "--scene") {
      if (!value(a.scene)) return usageError("--scene needs a file");
    } else if (opt == "--set") {
      std::string kv;
      if (!value(kv)) return usageError("--set needs key.path=value");
      a.overrides.push_back(kv);
    } else if (opt == "--out" && a.command != "print-scene") {
      if (!value(a.out)) return usageError("--out needs a directory");
    } else if (opt == "--only" && a.command == "stability") {
      if (!value(a.only)) return usageError("--only needs a case name");
    } else if (opt == "--budget" && a.command == "stability") {
      std::string b;
      if (!value(b)) return usageError("--budget needs seconds");
      try {
        std::size_t used = 0;
        a.budget_s = std::stod(b, &used);
        if (used != b.size() || !(a.budget_s > 0.0) || !std::isfinite(a.budget_s)) {
          throw std::invalid_argument(b);
        }
      } catch (const std::exception&) {
        return usageError("--budget needs a positive number of seconds, got '" + b + "'");
      }
    } else if (opt == "--jobs" && (a.command == "study" || a.command == "work-precision" ||
                                   a.command == "stability")) {
      std::string j;
      if (!value(j)) return usageError("--jobs needs a number");
      try {
        std::size_t used = 0;
        a.jobs = std::stoi(j, &used);
        if (used != j.size() || a.jobs < 1 || a.jobs > 64) throw std::invalid_argument(j);
      } catch (const std::exception&) {
        return usageError("--jobs needs a whole number from 1 to 64, got '" + j + "'");
      }
    } else {
      return usageError("unknown option '" + opt + "'");
    }
  }
  try {
    return run(a);
  } catch (const cws::SceneError& e) {
    std::cerr << "wire_sim: bad scene: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "wire_sim: run failed: " << e.what() << "\n";
    return 1;
  }
}
