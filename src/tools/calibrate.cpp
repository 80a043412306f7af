// wire_sim calibrate: the command line, the checks before anything runs,
// and the outputs (calibrate.hpp; the numerics: calibration_solver.cpp).
#include "calibrate.hpp"

#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "calibration_solver.hpp"
#include "coil_winding_sim/core/base/text_format.hpp"
#include "coil_winding_sim/core/run/output.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"
#include "coil_winding_sim/core/scene/scene_keys.hpp"
#include "coil_winding_sim/ros/machine_bag.hpp"
#include "coil_winding_sim/ros/offline_replay.hpp"
#include "run_store.hpp"
#include "sweep.hpp"

#ifndef CWS_TOOLS_DIR
#error "CWS_TOOLS_DIR must be defined"
#endif

namespace cws_tools {

namespace fs = std::filesystem;

namespace {

const char* const kUsage =
    "usage: wire_sim calibrate MACHINE.bag --fit KEY[=LO:HI] [--fit ...] [--out DIR]\n"
    "         [--scene FILE] [--set key=value ...] [--jobs N | --slurm [Slurm options]]\n"
    "         [--weight-tension W] [--weight-profile W] [--weight-bulging W]\n"
    "         [--keep-profile-offset] [--spindle-rate HZ] [--profile-rate HZ]\n"
    "         [--profile-turns N] [--evaluations N] [--design N] [--batch N]\n"
    "         [--step FRACTION]\n";

struct BadInput : std::runtime_error {
  using std::runtime_error::runtime_error;
};

double parseNumber(const std::string& opt, const std::string& text) {
  try {
    std::size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size() && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  throw BadInput(opt + ": '" + text + "' is not a number");
}

// --fit KEY[=LO:HI]: a number key of the table; without bounds, half to
// twice its value (from 0 for a key that may be 0).
FitParameter parseFit(const std::string& arg, const cws::Scene& scene) {
  FitParameter f;
  const std::size_t eq = arg.find('=');
  f.key = arg.substr(0, eq);
  const cws::SceneKey* key = cws::findSceneKey(f.key);
  if (!key) throw BadInput("--fit: no scene key '" + f.key + "'");
  const auto* field = std::get_if<cws::KeyField<double>>(&key->access);
  const cws::KeyRange::Kind kind = key->range.kind;
  if (!field || (kind != cws::KeyRange::kAny && kind != cws::KeyRange::kPositive &&
                 kind != cws::KeyRange::kNonNegative)) {
    throw BadInput("--fit " + f.key + ": only a number key can be fitted; this one is a " +
                   key->type());
  }
  f.start = field->get(scene);
  if (eq == std::string::npos) {
    if (f.start == 0.0 && kind != cws::KeyRange::kNonNegative) {
      throw BadInput("--fit " + f.key + ": its value is 0; give the range as " + f.key + "=LO:HI");
    }
    f.lo = kind == cws::KeyRange::kNonNegative ? 0.0 : f.start - std::abs(f.start) / 2;
    f.hi = f.start == 0.0 ? 1.0 : f.start + std::abs(f.start);
    if (kind == cws::KeyRange::kPositive) f.lo = f.start / 2;
  } else {
    const std::string range = arg.substr(eq + 1);
    const std::size_t colon = range.find(':');
    if (colon == std::string::npos) throw BadInput("--fit " + arg + ": give the range as LO:HI");
    f.lo = parseNumber("--fit " + f.key, range.substr(0, colon));
    f.hi = parseNumber("--fit " + f.key, range.substr(colon + 1));
  }
  if (!(f.lo < f.hi)) throw BadInput("--fit " + f.key + ": LO must be below HI");
  if (kind == cws::KeyRange::kPositive && !(f.lo > 0.0))
    throw BadInput("--fit " + f.key + ": the key must stay positive, so LO must be above 0");
  if (kind == cws::KeyRange::kNonNegative && f.lo < 0.0)
    throw BadInput("--fit " + f.key + ": the key cannot be negative, so LO must be 0 or more");
  if (f.start < f.lo || f.start > f.hi) {
    std::cerr << "calibrate: " << f.key << " = " << cws::formatNumber(f.start) << " lies outside "
              << cws::formatNumber(f.lo) << ":" << cws::formatNumber(f.hi)
              << "; starting from the nearer bound\n";
    f.start = std::clamp(f.start, f.lo, f.hi);
  }
  return f;
}

// Every corner of the box, with the keys' order kept (keepKeyOrder), must
// be a scene the simulation takes.
void checkCorners(const CalibrationOptions& o) {
  const std::size_t n = o.fit.size();
  if (n > 10) return;
  const cws::Scene base = cws::loadScene(o.scene, o.overrides);
  for (std::size_t c = 0; c < (std::size_t(1) << n); ++c) {
    Eigen::VectorXd x(n);
    for (std::size_t k = 0; k < n; ++k) x[k] = (c >> k) & 1 ? o.fit[k].hi : o.fit[k].lo;
    x = keepKeyOrder(fitKeys(o), base, x);
    std::vector<std::string> ov = o.overrides;
    std::string label;
    for (std::size_t k = 0; k < n; ++k) {
      ov.push_back(o.fit[k].key + "=" + cws::formatNumber(x[k], "%.17g"));
      label += (k ? ", " : "") + o.fit[k].key + "=" + cws::formatNumber(x[k]);
    }
    try {
      cws::loadScene(o.scene, ov);
    } catch (const std::exception& e) {
      throw BadInput("the fitted ranges reach a scene the simulation refuses, at " + label + ": " +
                     e.what() + "; narrow the ranges");
    }
  }
}

CalibrationOptions parseArgs(const std::vector<std::string>& args, const std::string& default_scene,
                             std::vector<std::string>& fits) {
  CalibrationOptions o;
  o.scene = default_scene;
  for (std::size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> const std::string& {
      if (i + 1 >= args.size()) throw BadInput(a + " needs a value");
      return args[++i];
    };
    if (a == "--fit") {
      fits.push_back(value());
    } else if (a == "--out") {
      o.out = value();
    } else if (a == "--scene") {
      o.scene = value();
    } else if (a == "--set") {
      o.overrides.push_back(value());
    } else if (a == "--jobs") {
      const double j = parseNumber(a, value());
      if (j < 1 || j != std::floor(j)) throw BadInput("--jobs must be a whole number of 1 or more");
      o.jobs = static_cast<int>(j);
    } else if (a == "--slurm") {
      o.slurm = true;
    } else if (a == "--dry-run") {
      throw BadInput("--dry-run: a calibration needs each batch's results before the next");
    } else if (isSlurmValueOption(a)) {
      const std::string problem = setSlurmOption(o.slurm_options, a, value());
      if (!problem.empty()) throw BadInput(problem);
    } else if (a == "--weight-tension" || a == "--weight-profile" || a == "--weight-bulging") {
      const double w = parseNumber(a, value());
      if (w < 0) throw BadInput(a + " must be 0 or more");
      (a == "--weight-tension"   ? o.weights.tension
       : a == "--weight-profile" ? o.weights.profile
                                 : o.weights.bulging) = w;
    } else if (a == "--keep-profile-offset") {
      o.weights.remove_profile_offset = false;
    } else if (a == "--spindle-rate" || a == "--profile-rate") {
      const double hz = parseNumber(a, value());
      if (!(hz > 0)) throw BadInput(a + " must be positive [Hz]");
      (a == "--spindle-rate" ? o.spindle_rate_hz : o.profile_rate_hz) = hz;
    } else if (a == "--profile-turns") {
      o.profile_turns = parseNumber(a, value());
      if (o.profile_turns < 0) throw BadInput("--profile-turns must be 0 or more");
    } else if (a == "--evaluations" || a == "--batch") {
      const double n = parseNumber(a, value());
      if (n < 1 || n != std::floor(n)) throw BadInput(a + " must be a whole number of 1 or more");
      (a == "--evaluations" ? o.max_evaluations : o.batch) = static_cast<int>(n);
    } else if (a == "--step") {
      o.step = parseNumber(a, value());
      if (!(o.step > 0 && o.step <= 0.25))
        throw BadInput("--step must be above 0 and at most 0.25");
    } else if (a == "--design") {
      const double n = parseNumber(a, value());
      if (n < 0 || n != std::floor(n))
        throw BadInput("--design must be a whole number of 0 or more");
      o.design_points = static_cast<int>(n);
    } else if (!a.empty() && a[0] == '-') {
      throw BadInput("unknown option " + a);
    } else if (o.machine_bag.empty()) {
      o.machine_bag = a;
    } else {
      throw BadInput("one machine bag, not also '" + a + "'");
    }
  }
  if (o.machine_bag.empty()) throw BadInput("give the machine bag");
  if (fits.empty()) throw BadInput("give at least one --fit KEY[=LO:HI]");
  return o;
}

// A replay at the given values into DIR/replay.bag (for the plots).
void replayTo(const CalibrationOptions& o, const std::vector<std::string>& overrides,
              const std::string& dir) {
  std::vector<std::string> args = {"replay", o.machine_bag, "--out", dir};
  if (!o.scene.empty()) args.insert(args.end(), {"--scene", o.scene});
  for (const std::string& s : overrides) args.insert(args.end(), {"--set", s});
  args.insert(args.end(), {"--spindle-rate", cws::formatNumber(o.spindle_rate_hz, "%.17g"),
                           "--profile-rate", cws::formatNumber(o.profile_rate_hz, "%.17g"),
                           "--profile-turns", cws::formatNumber(o.profile_turns, "%.17g")});
  if (cws_ros::replayMain(args, o.scene) != 0)
    throw std::runtime_error("the replay into " + dir + " failed");
}

// A file's bytes, hashed.
std::string fileHash(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  char buf[40];
  std::snprintf(buf, sizeof buf, "%016" PRIx64, fnv1a(bytes.str()));
  return buf;
}

std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string jsonNumber(double v) {
  return std::isfinite(v) ? cws::formatNumber(v, "%.10g") : "null";
}

std::string misfitJson(const Evaluation& e) {
  return "{\"misfit\": " + jsonNumber(e.misfit) +
         ", \"tension_rms_N\": " + jsonNumber(e.tension_rms_N) +
         ", \"profile_rms_mm\": " + jsonNumber(e.profile_rms_mm) +
         ", \"bulging_rms_mm\": " + jsonNumber(e.bulging_rms_mm) +
         ", \"profile_offset_mm\": " + jsonNumber(e.profile_offset_mm) + "}";
}

}  // namespace

int calibrateMain(const std::vector<std::string>& args, const std::string& default_scene,
                  const std::string& exe, const std::function<bool()>& stop) {
  const auto t0 = std::chrono::steady_clock::now();
  CalibrationOptions o;
  try {
    std::vector<std::string> fits;
    o = parseArgs(args, default_scene, fits);
    if (!o.scene.empty()) o.scene = fs::absolute(o.scene).string();
    o.machine_bag = fs::absolute(o.machine_bag).string();
    const cws::Scene scene = cws::loadScene(o.scene, o.overrides);
    for (const std::string& f : fits) {
      o.fit.push_back(parseFit(f, scene));
      for (std::size_t k = 0; k + 1 < o.fit.size(); ++k) {
        if (o.fit[k].key == o.fit.back().key)
          throw BadInput("--fit " + f + ": the key is fitted twice");
      }
    }
    // The bag checked once here, with compare_bags.py's messages.
    cws_ros::readMachineBag(o.machine_bag, cws::SetpointLimits::of(scene.process),
                            cws_ros::Frames());
    checkCorners(o);
    if (o.design_points < 0) o.design_points = 8 * static_cast<int>(o.fit.size());
    if (o.max_evaluations < 0) o.max_evaluations = 80 * static_cast<int>(o.fit.size());
    o.max_evaluations = std::max(o.max_evaluations, o.design_points + 1);
    o.machine_bag_hash = fileHash(o.machine_bag);
    if (o.slurm) checkSlurmOptions(o.slurm_options);
    cws::checkOutputDir(o.out);
    o.out = fs::absolute(o.out).string();
  } catch (const cws_ros::MachineBagError& e) {
    std::cerr << "wire_sim calibrate: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "wire_sim calibrate: " << e.what() << "\n" << kUsage;
    return 2;
  }
  for (const char* f : {"calibration.json", "calibration.md", "fitted_scene.yaml"}) {
    std::error_code ec;
    fs::remove(fs::path(o.out) / f, ec);
  }

  Evaluator ev(o, exe, stop);
  Eigen::VectorXd u0(o.fit.size());
  for (std::size_t k = 0; k < o.fit.size(); ++k) {
    u0[k] = (o.fit[k].start - o.fit[k].lo) / (o.fit[k].hi - o.fit[k].lo);
  }
  std::cerr << "calibrate: " << o.machine_bag << ", fitting " << o.fit.size() << " keys from "
            << ev.describe(u0) << "\n";
  FitOutcome fit;
  std::vector<ParameterVerdict> verdicts(o.fit.size());
  Evaluation start;
  try {
    fit = fitGlobal(ev, u0);
    if (!ev.history().empty()) start = ev.history().front().second;
    // The verdicts at the best point; the lines they scan may find a better
    // one, where they are taken again (at most three times).
    for (int round = 0; round < 3 && !fit.stopped && ev.haveBest(); ++round) {
      fit.u = ev.bestU();
      verdicts = judgeParameters(ev, fit.u);
      if (ev.bestU() == fit.u) break;
    }
  } catch (const CalibrationStopped&) {
    fit.stopped = true;
  } catch (const std::exception& e) {
    std::cerr << "wire_sim calibrate: " << e.what() << "\n";
    return 1;
  }
  if (!ev.haveBest()) {
    std::cerr << "calibrate: stopped before any evaluation finished; nothing to report\n";
    return -1;
  }
  if (fit.stopped) fit.u = ev.bestU();
  // The evaluation at the point reported (the best, unless a third round
  // of verdicts found a better one still: then the point judged).
  Evaluation best = ev.best();
  for (const auto& [uh, eh] : ev.history()) {
    if (uh == fit.u && eh.ok) best = eh;
  }
  const Eigen::VectorXd x = ev.values(fit.u);
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // The fitted scene: every fitted key at its best value.
  std::vector<std::string> fitted = o.overrides;
  for (std::size_t k = 0; k < o.fit.size(); ++k)
    fitted.push_back(o.fit[k].key + "=" + cws::formatNumber(x[k], "%.17g"));
  std::ostringstream yaml;
  yaml << "# Fitted by wire_sim calibrate to " << o.machine_bag << "\n# ("
       << (fit.stopped ? "stopped early: the best so far" : "converged")
       << "; see calibration.md)\n"
       << cws::sceneToYamlText(cws::loadScene(o.scene, fitted));
  cws::writeFileAtomically((fs::path(o.out) / "fitted_scene.yaml").string(), yaml.str());

  // The report.
  std::ostringstream md, js;
  md << "# Calibration to " << o.machine_bag << "\n\n"
     << (fit.stopped ? "**Stopped** (Ctrl-C): the best so far, without uncertainties.\n\n" : "")
     << "| key | start | fitted | 1 sigma | range | identifiable |\n|---|---|---|---|---|---|\n";
  js << "{\n  \"machine_bag\": " << jsonString(o.machine_bag)
     << ",\n  \"scene\": " << jsonString(o.scene)
     << ",\n  \"stopped\": " << (fit.stopped ? "true" : "false") << ",\n  \"parameters\": [\n";
  for (std::size_t k = 0; k < o.fit.size(); ++k) {
    const FitParameter& f = o.fit[k];
    const ParameterVerdict& v = verdicts[k];
    const bool known = !fit.stopped && v.identifiable;
    md << "| " << f.key << " | " << cws::formatNumber(f.start) << " | "
       << (known         ? cws::formatNumber(x[k])
           : fit.stopped ? cws::formatNumber(x[k]) + " (so far)"
                         : "not identifiable")
       << " | " << (known ? cws::formatNumber(v.sigma, "%.2g") : "-") << " | "
       << cws::formatNumber(f.lo) << " .. " << cws::formatNumber(f.hi) << " | "
       << (fit.stopped      ? "?"
           : v.identifiable ? "yes"
                            : "no")
       << (v.note.empty() ? "" : ": " + v.note) << " |\n";
    js << "    {\"key\": " << jsonString(f.key) << ", \"lo\": " << jsonNumber(f.lo)
       << ", \"hi\": " << jsonNumber(f.hi) << ", \"start\": " << jsonNumber(f.start)
       << ", \"value\": " << (known ? jsonNumber(x[k]) : "null")
       << ", \"scene_value\": " << jsonNumber(x[k])
       << ", \"sigma\": " << (known ? jsonNumber(v.sigma) : "null") << ", \"identifiable\": "
       << (fit.stopped      ? "null"
           : v.identifiable ? "true"
                            : "false")
       << ", \"note\": " << jsonString(v.note) << "}" << (k + 1 < o.fit.size() ? "," : "") << "\n";
  }
  md << "\n| misfit | start | fitted |\n|---|---|---|\n"
     << "| total (weighted) | " << cws::formatNumber(start.misfit) << " | "
     << cws::formatNumber(best.misfit) << " |\n"
     << "| tension RMS [N] | " << cws::formatNumber(start.tension_rms_N) << " | "
     << cws::formatNumber(best.tension_rms_N) << " |\n"
     << "| profile RMS [mm] | " << cws::formatNumber(start.profile_rms_mm) << " | "
     << cws::formatNumber(best.profile_rms_mm) << " |\n"
     << "| bulging RMS [mm] | " << cws::formatNumber(start.bulging_rms_mm) << " | "
     << cws::formatNumber(best.bulging_rms_mm) << " |\n"
     << "| profile offset removed [mm] | " << cws::formatNumber(start.profile_offset_mm) << " | "
     << cws::formatNumber(best.profile_offset_mm) << " |\n\n"
     << "Weights: tension " << cws::formatNumber(o.weights.tension) << " /N^2, profile "
     << cws::formatNumber(o.weights.profile) << " /mm^2, bulging "
     << cws::formatNumber(o.weights.bulging) << " /mm^2. " << ev.evaluations() << " evaluations ("
     << ev.kept() << " kept from an earlier run) in " << cws::formatNumber(wall_s, "%.3g")
     << " s of wall time. " << fit.termination << "\n";
  js << "  ],\n  \"misfit_start\": " << misfitJson(start)
     << ",\n  \"misfit_fitted\": " << misfitJson(best)
     << ",\n  \"weights\": {\"tension_per_N2\": " << jsonNumber(o.weights.tension)
     << ", \"profile_per_mm2\": " << jsonNumber(o.weights.profile)
     << ", \"bulging_per_mm2\": " << jsonNumber(o.weights.bulging)
     << ", \"remove_profile_offset\": " << (o.weights.remove_profile_offset ? "true" : "false")
     << "},\n  \"evaluations\": " << ev.evaluations() << ",\n  \"kept\": " << ev.kept()
     << ",\n  \"wall_time_s\": " << jsonNumber(wall_s)
     << ",\n  \"termination\": " << jsonString(fit.termination) << "\n}\n";

  // Plots of tension and profile before and after (not when stopped).
  if (!fit.stopped) {
    try {
      std::vector<std::string> before = o.overrides;
      for (const FitParameter& f : o.fit)
        before.push_back(f.key + "=" + cws::formatNumber(f.start, "%.17g"));
      replayTo(o, before, (fs::path(o.out) / "before").string());
      replayTo(o, fitted, (fs::path(o.out) / "after").string());
      const std::string cmd =
          "/usr/bin/python3 " + std::string(CWS_TOOLS_DIR) + "/plot_calibration.py " +
          o.machine_bag + " " + o.out + "/before/replay.bag " + o.out + "/after/replay.bag " +
          o.out + " " + cws::formatNumber(start.profile_offset_mm, "%.9g") + " " +
          cws::formatNumber(best.profile_offset_mm, "%.9g") + " > " + o.out + "/plot.log 2>&1";
      if (std::system(cmd.c_str()) != 0) {
        md << "\nThe plots failed: see plot.log.\n";
      } else {
        md << "\n![tension and profile before and after](calibration.png)\n";
      }
    } catch (const std::exception& e) {
      md << "\nNo plots: " << e.what() << "\n";
    }
  }
  cws::writeFileAtomically((fs::path(o.out) / "calibration.md").string(), md.str());
  cws::writeFileAtomically((fs::path(o.out) / "calibration.json").string(), js.str());
  std::cout << md.str();
  return fit.stopped ? -1 : 0;
}

}  // namespace cws_tools
