// One evaluation of a calibration, as a case of a sweep (the plan kind
// "calibration"): the machine bag replayed with the case's values of the
// fitted keys, and its misfit with the residuals written to the case's
// folder (evaluation.txt), where the calibration reads them.
#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "calibrate.hpp"
#include "coil_winding_sim/core/base/text_format.hpp"
#include "coil_winding_sim/core/run/output.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"
#include "coil_winding_sim/ros/node_options.hpp"
#include "coil_winding_sim/ros/offline_replay.hpp"
#include "run_store.hpp"
#include "sweep.hpp"

namespace cws_tools {

namespace fs = std::filesystem;

namespace {

const char* const kEvaluationFile = "evaluation.txt";

double optionNumber(const SweepPlan& plan, const std::string& key) {
  return std::stod(plan.option(key, "nan"));
}

cws::MisfitWeights weightsOf(const SweepPlan& plan) {
  cws::MisfitWeights w;
  w.tension = optionNumber(plan, "weight_tension");
  w.profile = optionNumber(plan, "weight_profile");
  w.bulging = optionNumber(plan, "weight_bulging");
  w.remove_profile_offset = plan.option("remove_profile_offset", "true") == "true";
  return w;
}

// A case's identity: the core build, the resolved scene, the machine bag's
// bytes and every option of the misfit and the replay.
std::string identity(const SweepPlan& plan, std::size_t i) {
  const cws::Scene scene = cws::loadScene(plan.scene, plan.caseOverrides(i));
  std::string text = std::to_string(coreBuildHash()) + "\n" + cws::sceneToYamlText(scene);
  for (const auto& [k, v] : plan.options) text += k + "=" + v + "\n";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%016" PRIx64, fnv1a(text));
  return buf;
}

int runCase(const SweepPlan& plan, const std::string& dir, std::size_t i,
            const std::function<bool()>& stop) {
  const fs::path case_dir = fs::path(dir) / plan.caseDir(i);
  fs::create_directories(case_dir);
  clearCaseStatus(plan, dir, i);
  std::error_code ec;
  fs::remove(case_dir / kEvaluationFile, ec);
  SweepCaseStatus s;
  s.present = true;
  const auto start = std::chrono::steady_clock::now();
  try {
    s.identity = identity(plan, i);
    cws::Scene scene;
    cws_ros::MachineRecording rec;
    cws_ros::ReplayRates rates;
    cws_ros::loadReplay(plan.scene, plan.caseOverrides(i), plan.option("machine_bag", ""),
                        rates.frames, scene, rec);
    rates.spindle_hz = optionNumber(plan, "spindle_rate_hz");
    rates.profile_hz = optionNumber(plan, "profile_rate_hz");
    rates.profile_turns = optionNumber(plan, "profile_turns");
    rates.frames_hz = cws_ros::frameRateHz(cws_ros::NodeOptions(), scene);
    cws::Simulation sim(scene);
    cws::RecordedSeries series;
    cws_ros::SeriesSink sink(rates, series);
    sink.setStart(rec.start);
    std::vector<std::string> refused;
    if (!cws_ros::replayRecording(sim, rec, rates, sink, refused, stop)) return -1;
    const cws::MisfitWeights w = weightsOf(plan);
    const cws::Misfit m = cws::recordingMisfit(rec.measured, series, w);
    const Eigen::VectorXd r = m.weighted(w);
    std::ostringstream out;
    out << "misfit " << cws::formatNumber(m.value(w), "%.17g") << "\ntension_rms_N "
        << cws::formatNumber(m.tensionRms(), "%.17g") << "\nprofile_rms_mm "
        << cws::formatNumber(m.profileRms(), "%.17g") << "\nbulging_rms_mm "
        << cws::formatNumber(m.bulgingRms(), "%.17g") << "\nprofile_offset_mm "
        << cws::formatNumber(m.profile_offset_mm, "%.17g") << "\ntension_samples "
        << m.tension_N.size() << "\nprofile_points " << m.profile_mm.size() << "\nprofile_pairs "
        << m.profile_pairs << "\nresiduals " << r.size() << "\n";
    for (Eigen::Index k = 0; k < r.size(); ++k) out << cws::formatNumber(r[k], "%.17g") << "\n";
    cws::writeFileAtomically((case_dir / kEvaluationFile).string(), out.str());
    s.status = "ok";
  } catch (const std::exception& e) {
    s.status = "failed";
    s.error = e.what();
    std::cerr << "calibration case " << i << " failed: " << e.what() << "\n";
  }
  s.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  writeCaseStatus(plan, dir, i, s);
  return s.status == "ok" ? 0 : 1;
}

const bool kCalibrationKind = registerPlanKind("calibration", [] {
  PlanKind k;
  k.case_identity = identity;
  k.run_case = runCase;
  // No table: the calibration reads each case's evaluation.txt.
  k.gather = [](const SweepPlan&, const std::string&) { return 0; };
  k.check_scenes = false;
  k.quiet = true;
  return k;
}());

}  // namespace

std::vector<std::string> fitKeys(const CalibrationOptions& o) {
  std::vector<std::string> keys;
  for (const FitParameter& f : o.fit) keys.push_back(f.key);
  return keys;
}

SweepPlan calibrationPlan(const CalibrationOptions& o, const std::vector<Eigen::VectorXd>& points) {
  SweepPlan p;
  p.kind = "calibration";
  p.scene = o.scene;
  p.overrides = o.overrides;
  p.keys = fitKeys(o);
  for (const Eigen::VectorXd& x : points) {
    std::vector<std::string> values;
    for (Eigen::Index k = 0; k < x.size(); ++k) values.push_back(cws::formatNumber(x[k], "%.17g"));
    p.cases.push_back(values);
  }
  p.options = {{"machine_bag", o.machine_bag},
               {"machine_bag_hash", o.machine_bag_hash},
               {"weight_tension", cws::formatNumber(o.weights.tension, "%.17g")},
               {"weight_profile", cws::formatNumber(o.weights.profile, "%.17g")},
               {"weight_bulging", cws::formatNumber(o.weights.bulging, "%.17g")},
               {"remove_profile_offset", o.weights.remove_profile_offset ? "true" : "false"},
               {"spindle_rate_hz", cws::formatNumber(o.spindle_rate_hz, "%.17g")},
               {"profile_rate_hz", cws::formatNumber(o.profile_rate_hz, "%.17g")},
               {"profile_turns", cws::formatNumber(o.profile_turns, "%.17g")}};
  return p;
}

Evaluation readEvaluation(const SweepPlan& plan, const std::string& dir, std::size_t i) {
  Evaluation e;
  const SweepCaseStatus s = readCaseStatus(plan, dir, i);
  if (!s.present) {
    e.error = "not run";
    return e;
  }
  if (s.status != "ok") {
    e.error = s.error;
    return e;
  }
  const fs::path path = fs::path(dir) / plan.caseDir(i) / kEvaluationFile;
  std::ifstream in(path);
  std::string word;
  long count = -1;
  while (in >> word) {
    if (word == "residuals") {
      in >> count;
      break;
    }
    double v = 0.0;
    in >> v;
    if (word == "misfit") e.misfit = v;
    if (word == "tension_rms_N") e.tension_rms_N = v;
    if (word == "profile_rms_mm") e.profile_rms_mm = v;
    if (word == "bulging_rms_mm") e.bulging_rms_mm = v;
    if (word == "profile_offset_mm") e.profile_offset_mm = v;
    if (word == "tension_samples") e.tension_samples = static_cast<int>(v);
    if (word == "profile_points") e.profile_points = static_cast<int>(v);
    if (word == "profile_pairs") e.profile_pairs = static_cast<int>(v);
  }
  if (count < 0) {
    e.error = "its evaluation " + path.string() + " cannot be read";
    return e;
  }
  e.residuals.resize(count);
  for (long k = 0; k < count; ++k) {
    if (!(in >> e.residuals[k])) {
      e.error = "its evaluation " + path.string() + " is cut short";
      return e;
    }
  }
  e.ok = true;
  return e;
}

}  // namespace cws_tools
