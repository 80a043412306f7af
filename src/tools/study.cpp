#include "study.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include "coil_winding_sim/core/run/output.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"
#include "sweep.hpp"

namespace cws_tools {

namespace fs = std::filesystem;

namespace {

// The study's tables in DIR.
const char* const kTables[] = {"study.csv", "study.md", "core_cylinders.csv"};

}  // namespace

SweepPlan studyPlan(const std::string& scene_path, const std::vector<std::string>& overrides) {
  const cws::Scene scene = cws::loadScene(scene_path, overrides);
  if (!scene.physics.supply || !scene.physics.contact) {
    throw cws::SceneError("physics.supply", "the study needs a winding scene (supply and contact)");
  }
  SweepPlan p;
  p.kind = "study";
  p.scene = scene_path.empty() ? "" : fs::absolute(scene_path).string();
  p.overrides = overrides;
  p.overrides.push_back("process.turns=1.75");
  p.overrides.push_back("process.duration=~");
  p.keys = {"process.core_speed_rpm", "process.tension"};
  for (const char* rpm : {"600", "1200"}) {
    for (const char* tension : {"30", "70"}) {
      p.cases.push_back({rpm, tension});
      p.names.push_back(std::string(rpm) + "rpm_" + tension + "N");
    }
  }
  return p;
}

int runStudy(const std::string& scene_path, const std::vector<std::string>& overrides,
             const std::string& dir, int jobs, const SlurmOptions* slurm, const std::string& exe,
             const std::function<bool()>& stop) {
  // Refuse a bad scene before anything runs.
  const SweepPlan plan = studyPlan(scene_path, overrides);
  checkPlan(plan);
  // An earlier study's tables go first: a study that fails or is stopped
  // must not leave them looking current.
  for (const char* t : kTables) {
    std::error_code ec;
    fs::remove(fs::path(dir) / t, ec);
    if (ec) throw std::runtime_error("cannot remove '" + (fs::path(dir) / t).string() + "'");
  }
  if (slurm) return runSweepSlurm(plan, dir, *slurm, exe);
  return runSweepLocal(plan, dir, jobs, exe, stop);
}

int writeStudyTables(const SweepPlan& plan, const std::string& dir) {
  std::ostringstream csv, md, cyl;
  csv << "case,core_speed_rpm,tension_N,core_turns,bulging_height_mm,bulging_arc_length_mm,"
         "fed_length_mm,points,max_penetration_ratio,steps_accepted,steps_rejected,sim_time_s,"
         "wall_time_s,real_time_factor,energy_imbalance_rel\n";
  md << "| core speed [rpm] | tension [N] | bulging height [mm] | at arc length [mm] | "
        "fed [mm] | max penetration / r | steps | wall time [s] | real-time factor |\n"
     << "|---|---|---|---|---|---|---|---|---|\n";
  bool all_ok = true;
  for (std::size_t i = 0; i < plan.cases.size(); ++i) {
    const std::string rpm = plan.cases[i][0], tension = plan.cases[i][1];
    const SweepCaseStatus s = readCaseStatus(plan, dir, i);
    std::map<std::string, double> v;
    std::string problem = !s.present         ? "pending (not run yet)"
                          : s.status != "ok" ? "failed: " + s.error
                                             : "";
    if (problem.empty()) {
      try {
        v = readSummaryNumbers((fs::path(dir) / plan.caseDir(i) / "summary.json").string());
      } catch (const std::exception& e) {
        problem = std::string("failed: its summary.json cannot be read: ") + e.what();
      }
    }
    if (!problem.empty()) {
      all_ok = false;
      md << "| " << rpm << " | " << tension << " | " << problem << " | | | | | | |\n";
      continue;
    }
    // A figure the summary lacks reads as NaN, never as a plausible 0.
    auto at = [&](const char* key) {
      const auto it = v.find(key);
      return it == v.end() ? std::nan("") : it->second;
    };
    const double imbalance_rel =
        std::abs(at("energy_imbalance_J")) / std::max(1e-300, std::abs(at("work_done_J")));
    char line[512];
    std::snprintf(
        line, sizeof line, "%s,%s,%s,%.4f,%.4f,%.2f,%.2f,%.0f,%.4f,%.0f,%.0f,%.6f,%.2f,%.3g,%.2e\n",
        plan.caseDir(i).c_str(), rpm.c_str(), tension.c_str(), at("core_turns"),
        1e3 * at("bulging_height_m"), 1e3 * at("bulging_arc_length_m"), 1e3 * at("fed_length_m"),
        at("nodes"), at("max_penetration_ratio"), at("steps_accepted"), at("steps_rejected"),
        at("sim_time_s"), at("wall_time_s"), at("real_time_factor"), imbalance_rel);
    csv << line;
    std::snprintf(line, sizeof line,
                  "| %s | %s | %.3f | %.1f | %.1f | %.3f | %.0f | %.1f | %.3g |\n", rpm.c_str(),
                  tension.c_str(), 1e3 * at("bulging_height_m"), 1e3 * at("bulging_arc_length_m"),
                  1e3 * at("fed_length_m"), at("max_penetration_ratio"), at("steps_accepted"),
                  at("wall_time_s"), at("real_time_factor"));
    md << line;
  }
  const cws::Scene scene = cws::loadScene(plan.scene, plan.overrides);
  cyl << "x_core,y_core,radius\n" << std::setprecision(12);
  for (const cws::CylinderParams& c : scene.core.cylinders) {
    cyl << c.center_core.x() << ',' << c.center_core.y() << ',' << c.radius << '\n';
  }
  cws::writeFileAtomically((fs::path(dir) / "study.csv").string(), csv.str());
  cws::writeFileAtomically((fs::path(dir) / "study.md").string(), md.str());
  cws::writeFileAtomically((fs::path(dir) / "core_cylinders.csv").string(), cyl.str());
  std::cout << md.str();
  return all_ok ? 0 : 1;
}

// The study's kind of sweep plan: plain runs whose table gains the study's.
const bool kStudyKind = registerPlanKind("study", [] {
  PlanKind k;
  k.add_to_table = writeStudyTables;
  return k;
}());

}  // namespace cws_tools
