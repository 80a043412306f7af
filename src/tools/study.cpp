#include "study.hpp"

#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <mutex>
#include <sstream>

#include "coil_winding_sim/core/output.hpp"
#include "coil_winding_sim/core/scene.hpp"
#include "coil_winding_sim/core/simulation.hpp"
#include "parallel.hpp"

namespace cws_tools {

namespace fs = std::filesystem;

namespace {

struct Case {
  double rpm = 0.0;
  double tension_N = 0.0;
  std::string name;
  // Results.
  bool ok = false;
  std::string error;
  double bulging_m = 0.0, bulging_arc_m = 0.0, fed_m = 0.0, penetration_ratio = 0.0;
  double wall_s = 0.0, sim_s = 0.0, rtf = 0.0, imbalance_rel = 0.0, turns = 0.0;
  long steps = 0, rejected = 0;
  int points = 0;
};

void runCase(const std::string& scene_path, const std::vector<std::string>& overrides,
             const std::string& dir, Case& c, std::mutex& log) {
  try {
    std::vector<std::string> o = overrides;
    std::ostringstream rpm, tension;
    rpm << std::setprecision(10) << c.rpm;
    tension << std::setprecision(10) << c.tension_N;
    o.push_back("process.core_speed_rpm=" + rpm.str());
    o.push_back("process.tension=" + tension.str());
    o.push_back("process.turns=1.75");
    o.push_back("process.duration=~");
    cws::Simulation sim(cws::loadScene(scene_path, o));
    {
      std::lock_guard<std::mutex> lock(log);
      std::cerr << "study: " << c.name << " started (until t = " << sim.endTime() << " s)\n";
    }
    sim.run();
    const std::string out = (fs::path(dir) / c.name).string();
    cws::writeOutputs(sim, out);
    const cws::BulgeReport b = sim.model().bulging();
    const cws::EnergyReport e = sim.energy();
    c.bulging_m = b.valid ? b.height_m : 0.0;
    c.bulging_arc_m = b.valid ? b.arc_length_m : 0.0;
    c.fed_m = sim.model().fedLength();
    c.penetration_ratio = sim.maxPenetration() / sim.model().constants().radius;
    c.wall_s = sim.wallTime();
    c.sim_s = sim.time();
    c.rtf = sim.realTimeFactor();
    c.turns = sim.coreTurns();
    c.imbalance_rel = std::abs(e.imbalance()) / std::max(1e-300, std::abs(e.work_done));
    c.steps = sim.stepper().counts().accepted;
    c.rejected = sim.stepper().counts().rejected;
    c.points = sim.model().constants().n;
    c.ok = true;
    std::lock_guard<std::mutex> lock(log);
    std::cerr << "study: " << c.name << " done in " << c.wall_s << " s, bulging "
              << 1e3 * c.bulging_m << " mm\n";
  } catch (const std::exception& e) {
    c.error = e.what();
    std::lock_guard<std::mutex> lock(log);
    std::cerr << "study: " << c.name << " failed: " << e.what() << "\n";
  }
}

// The study's tables in DIR.
const char* const kTables[] = {"study.csv", "study.md", "core_cylinders.csv"};
}  // namespace

int runStudy(const std::string& scene_path, const std::vector<std::string>& overrides,
             const std::string& dir, int jobs) {
  // Refuse a bad scene or directory before anything runs.
  const cws::Scene scene = cws::loadScene(scene_path, overrides);
  if (!scene.physics.supply || !scene.physics.contact) {
    throw cws::SceneError("physics.supply", "the study needs a winding scene (supply and contact)");
  }
  cws::checkOutputDir(dir);

  std::vector<Case> cases;
  for (double rpm : {600.0, 1200.0}) {
    for (double tension : {30.0, 70.0}) {
      Case c;
      c.rpm = rpm;
      c.tension_N = tension;
      c.name = std::to_string(static_cast<int>(rpm)) + "rpm_" +
               std::to_string(static_cast<int>(tension)) + "N";
      cases.push_back(c);
    }
  }
  // Results of an earlier study go first: a case that fails now, or a study
  // that is stopped, must not leave an earlier case's summary or table.
  for (const Case& c : cases) cws::removeOutputs((fs::path(dir) / c.name).string());
  for (const char* t : kTables) {
    std::error_code ec;
    fs::remove(fs::path(dir) / t, ec);
    if (ec) throw std::runtime_error("cannot remove '" + (fs::path(dir) / t).string() + "'");
  }
  std::mutex log;
  forEachParallel(cases.size(), jobs,
                  [&](std::size_t i) { runCase(scene_path, overrides, dir, cases[i], log); });

  std::ostringstream csv, md, cyl;
  csv << "case,core_speed_rpm,tension_N,core_turns,bulging_height_mm,bulging_arc_length_mm,"
         "fed_length_mm,points,max_penetration_ratio,steps_accepted,steps_rejected,sim_time_s,"
         "wall_time_s,real_time_factor,energy_imbalance_rel\n";
  md << "| core speed [rpm] | tension [N] | bulging height [mm] | at arc length [mm] | "
        "fed [mm] | max penetration / r | steps | wall time [s] | real-time factor |\n"
     << "|---|---|---|---|---|---|---|---|---|\n";
  bool all_ok = true;
  for (const Case& c : cases) {
    if (!c.ok) {
      all_ok = false;
      md << "| " << c.rpm << " | " << c.tension_N << " | failed: " << c.error << " | | | | | | |\n";
      continue;
    }
    char line[512];
    std::snprintf(line, sizeof line,
                  "%s,%.0f,%.0f,%.4f,%.4f,%.2f,%.2f,%d,%.4f,%ld,%ld,%.6f,%.2f,%.3g,%.2e\n",
                  c.name.c_str(), c.rpm, c.tension_N, c.turns, 1e3 * c.bulging_m,
                  1e3 * c.bulging_arc_m, 1e3 * c.fed_m, c.points, c.penetration_ratio, c.steps,
                  c.rejected, c.sim_s, c.wall_s, c.rtf, c.imbalance_rel);
    csv << line;
    std::snprintf(line, sizeof line,
                  "| %.0f | %.0f | %.3f | %.1f | %.1f | %.3f | %ld | %.1f | %.3g |\n", c.rpm,
                  c.tension_N, 1e3 * c.bulging_m, 1e3 * c.bulging_arc_m, 1e3 * c.fed_m,
                  c.penetration_ratio, c.steps, c.wall_s, c.rtf);
    md << line;
  }
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

}  // namespace cws_tools
