#include "stability.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <iterator>
#include <sstream>

#include "coil_winding_sim/core/base/text_format.hpp"
#include "coil_winding_sim/core/run/command_schedule.hpp"
#include "coil_winding_sim/core/run/output.hpp"
#include "coil_winding_sim/core/run/run_checks.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"
#include "coil_winding_sim/core/scene/integrators.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"
#include "coil_winding_sim/core/scene/stability_cases.hpp"
#include "run_store.hpp"
#include "stability_report.hpp"
#include "sweep.hpp"

namespace cws_tools {

namespace fs = std::filesystem;

namespace {

using Case = cws::StabilityCase;
using Run = StabilityRun;

// What a run needs besides its case and method: the scene and base
// overrides, its budget, where its files go, and when to stop.
struct Study {
  std::string scene_path;
  std::vector<std::string> base;
  double budget_s = 0.0;
  double checkpoint_s = 0.0;
  fs::path run_dir;  // the run's folder: its result, checkpoint and status
  std::function<bool()> stop;
};

// Bumped when the way a run is set up or measured changes, so that results
// and checkpoints of the earlier way are not reused.
constexpr int kRunProtocol = 1;

const char* const kResultFile = "result.txt";
const char* const kCheckpointFile = "checkpoint";

// The run's identity: the core build, the scene file, every override, the
// method and the speed events.
uint64_t identity(const Study& st, const Run& r) {
  std::ostringstream id;
  id << "protocol " << kRunProtocol << "\ncore " << coreBuildHash() << "\nmethod " << r.method
     << "\n";
  // (Read to a string first: streaming an empty or unreadable file's
  // buffer would fail `id` and drop the rest.)
  std::ifstream f(st.scene_path, std::ios::binary);
  const std::string scene((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  id << "scene " << scene << "\n";
  for (const std::string& o : st.base) id << "set " << o << "\n";
  for (const std::string& o : r.c->overrides) id << "set " << o << "\n";
  id << std::setprecision(17);
  for (const cws::SpeedEvent& e : r.c->events)
    id << "event " << e.time_s << " " << e.speed_rad_s << "\n";
  return fnv1a(id.str());
}

// A finished run's result: one `key value` line per field, the message last.
void writeResult(const std::string& path, uint64_t id, const Run& r) {
  std::ostringstream f;
  f << std::setprecision(17) << "cws-stability-result/2\nidentity " << id << "\noutcome "
    << static_cast<int>(r.outcome) << "\nmeasured " << r.measured << "\nfinite " << r.m.finite
    << "\nenergy_signed_rel " << r.m.energy_signed_rel << "\nenergy_scale_J " << r.m.energy_scale_J
    << "\nresidual " << r.m.residual << "\npenetration_ratio " << r.m.penetration_ratio
    << "\nsteps " << r.m.steps << "\nrejected " << r.m.rejected << "\nmean_step_s "
    << r.m.mean_step_s << "\nwall_s " << r.wall_s << "\nsim_s " << r.sim_s << "\nend_s " << r.end_s
    << "\nstep_s " << r.step_s << "\nmessage ";
  for (const char ch : r.message) f << (ch == '\n' ? ' ' : ch);
  f << "\n";
  cws::writeFileAtomically(path, f.str());
}

// False unless the file holds a complete result of this very run.
bool readResult(const std::string& path, uint64_t id, Run& r) {
  std::ifstream f(path);
  std::string magic, key;
  if (!std::getline(f, magic) || magic != "cws-stability-result/2") return false;
  uint64_t file_id = 0;
  int outcome = 0;
  Run x = r;
  if (!(f >> key >> file_id) || key != "identity" || file_id != id) return false;
  const auto field = [&](const char* name, auto& v) {
    return static_cast<bool>(f >> key >> v) && key == name;
  };
  if (!(field("outcome", outcome) && field("measured", x.measured) && field("finite", x.m.finite) &&
        field("energy_signed_rel", x.m.energy_signed_rel) &&
        field("energy_scale_J", x.m.energy_scale_J) && field("residual", x.m.residual) &&
        field("penetration_ratio", x.m.penetration_ratio) && field("steps", x.m.steps) &&
        field("rejected", x.m.rejected) && field("mean_step_s", x.m.mean_step_s) &&
        field("wall_s", x.wall_s) && field("sim_s", x.sim_s) && field("end_s", x.end_s) &&
        field("step_s", x.step_s))) {
    return false;
  }
  if (!(f >> key) || key != "message") return false;
  std::getline(f >> std::ws, x.message);
  x.m.energy_rel = std::abs(x.m.energy_signed_rel);
  const cws::IntegratorInfo* info = cws::findIntegrator(x.method);
  x.m.dissipative_method = info && info->numerically_dissipative;
  if (outcome < 0 || outcome > static_cast<int>(Outcome::kBudget)) return false;
  x.outcome = static_cast<Outcome>(outcome);
  r = x;
  return true;
}

// A run without a result: PENDING, with where its checkpoint is.
void pendingRun(const Study& st, Run& r) {
  r.outcome = Outcome::kPending;
  Checkpoint c;
  std::ostringstream msg;
  if (readCheckpoint((st.run_dir / kCheckpointFile).string(), c) && c.identity == identity(st, r)) {
    r.wall_s = c.wall_s;
    r.sim_s = c.state.time_s;
    msg << "not finished: checkpoint at t = " << c.state.time_s << " s after " << c.wall_s
        << " s of wall time; `make stability` continues it";
  } else {
    msg << "not run yet";
  }
  r.message = msg.str();
}

void execute(const Study& st, Run& r) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  double wall_before = 0.0;  // of earlier studies, for a resumed run [s]
  auto wall = [&] {
    return wall_before + std::chrono::duration<double>(Clock::now() - start).count();
  };
  const std::string key = r.c->name + "." + r.method;
  const std::string result_path = (st.run_dir / kResultFile).string();
  const std::string checkpoint_path = (st.run_dir / kCheckpointFile).string();
  const uint64_t id = identity(st, r);
  // A result of this run from an earlier study with the same core build is
  // kept; one that ran out of its budget continues from its checkpoint.
  if (readResult(result_path, id, r) && r.outcome != Outcome::kBudget) {
    r.kept = true;
    std::cerr << "stability: " << key << ": " << outcomeName(r.outcome)
              << " (kept from an earlier study of this build)\n";
    return;
  }
  r.message.clear();
  std::unique_ptr<cws::Simulation> sim;
  try {
    std::vector<std::string> o = st.base;
    o.insert(o.end(), r.c->overrides.begin(), r.c->overrides.end());
    o.push_back("solver.integrator=" + r.method);
    // The fixed-step method at a quarter of its stability limit (auto), as
    // the default scene is.
    if (r.method == "symplectic_euler") o.push_back("solver.fixed_step=auto");
    cws::Scene scene = cws::loadScene(st.scene_path, o);
    r.step_s = cws::fixedStep(scene);
    sim = std::make_unique<cws::Simulation>(scene);
  } catch (const cws::SceneError& e) {
    r.outcome = Outcome::kRefused;
    r.message = e.what();
    r.wall_s = wall();
    writeResult(result_path, id, r);
    std::cerr << "stability: " << key << ": refused: " << e.what() << "\n";
    return;
  }
  // The case's speed events from the first not yet applied on.
  const std::vector<cws::SpeedEvent>& events = r.c->events;
  cws::CommandSchedule schedule;
  auto scheduleFrom = [&](std::size_t first) {
    schedule.clear();
    for (std::size_t i = first; i < events.size(); ++i) {
      schedule.add(events[i].time_s, cws::Setpoint::coreSpeed(events[i].speed_rad_s));
    }
  };
  scheduleFrom(0);
  // An unfinished run of this build continues where its checkpoint is.
  {
    Checkpoint c;
    if (readCheckpoint(checkpoint_path, c) && c.identity == id) {
      try {
        sim = cws::Simulation::fromState(c.state);
        wall_before = c.wall_s;
        scheduleFrom(c.next_event);
        std::cerr << "stability: " << key << ": resumed at t = " << sim->time() << " s after "
                  << c.wall_s << " s of wall time\n";
      } catch (const std::exception& e) {
        std::cerr << "stability: " << key << ": checkpoint not usable (" << e.what()
                  << "), starting afresh\n";
      }
    }
  }
  auto checkpoint = [&] {
    Checkpoint c;
    c.identity = id;
    c.wall_s = wall();
    c.next_event = events.size() - schedule.size();
    c.state = sim->saveState();
    writeCheckpoint(checkpoint_path, c);
  };
  r.end_s = sim->endTime();
  try {
    long k = 0;
    const double resumed_at_s = wall_before;
    double next_report_s = resumed_at_s + 60.0;
    double next_checkpoint_s = resumed_at_s + st.checkpoint_s;
    while (sim->time() < sim->endTime()) {
      schedule.takeDue(sim->time(), [&](double, const cws::Setpoint& c) { sim->apply(c); });
      sim->step(std::min(sim->endTime(), schedule.nextTime()));
      if (++k % 1000 != 0) continue;
      // Ctrl-C: keep the run's state for the next study and stop.
      if (st.stop()) {
        checkpoint();
        r.interrupted = true;
        return;
      }
      const double w = wall();
      if (w > next_report_s) {
        std::cerr << "  " << key << ": t = " << sim->time() << " s of " << sim->endTime()
                  << " s, step " << sim->stepper().lastStep() << " s\n";
        next_report_s += 60.0;
      }
      if (w > next_checkpoint_s) {
        checkpoint();
        next_checkpoint_s = w + st.checkpoint_s;
      }
      if (w > st.budget_s) {
        std::ostringstream msg;
        msg << "not finished within the budget of " << st.budget_s
            << " s of wall time (t = " << sim->time() << " s of " << sim->endTime() << " s, about "
            << cws::formatNumber(w * sim->endTime() / sim->time(), "%.0f")
            << " s in all at this pace; a study with a larger --budget continues it); the "
               "criteria are checked on the part run";
        r.outcome = Outcome::kBudget;
        r.message = msg.str();
        checkpoint();
        break;
      }
    }
    if (r.message.empty()) {
      r.outcome = Outcome::kStable;
    }
  } catch (const std::exception& e) {
    // A detected failure: the message must name its cause.
    r.outcome = Outcome::kStopped;
    r.message = e.what();
  }
  r.m = cws::measureRun(*sim);
  r.measured = true;
  r.wall_s = wall();
  r.sim_s = sim->time();
  if (r.outcome == Outcome::kStable || r.outcome == Outcome::kBudget) {
    const std::vector<std::string> v = cws::stabilityViolations(r.m);
    if (!v.empty()) {
      r.outcome = Outcome::kViolated;
      for (const std::string& s : v) r.message += (r.message.empty() ? "" : "; ") + s;
    }
  }
  writeResult(result_path, id, r);
  if (r.outcome != Outcome::kBudget) fs::remove(checkpoint_path);
  std::cerr << "stability: " << key << ": " << outcomeName(r.outcome) << " in " << r.wall_s << " s"
            << (r.message.empty() ? "" : ": ") << r.message << "\n";
}

const Case& caseNamed(const std::string& name) {
  for (const Case& c : cws::stabilityCases()) {
    if (c.name == name) return c;
  }
  throw SweepError("no stability case named '" + name + "'");
}

// Run i of the plan: its case and method (in `r`) and its settings.
Study studyOf(const SweepPlan& plan, const std::string& dir, std::size_t i, Run& r) {
  r.c = &caseNamed(plan.cases.at(i).at(0));
  r.method = plan.cases.at(i).at(1);
  Study st;
  st.scene_path = plan.scene;
  st.base = plan.overrides;
  st.budget_s = std::stod(plan.option("budget_s", "18000"));
  st.checkpoint_s = std::stod(plan.option("checkpoint_s", "300"));
  st.run_dir = fs::path(dir) / plan.caseDir(i);
  st.stop = [] { return false; };
  return st;
}

std::string hex(uint64_t v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

}  // namespace

SweepPlan stabilityPlan(const std::string& scene_path, const std::vector<std::string>& overrides,
                        const StabilityOptions& opt) {
  SweepPlan p;
  p.kind = "stability";
  p.scene = scene_path.empty() ? "" : fs::absolute(scene_path).string();
  // The base: the given scene with the study's segment length and speed.
  p.overrides = {"wire.segment_length=2e-3", "process.core_speed_rpm=1200"};
  p.overrides.insert(p.overrides.end(), overrides.begin(), overrides.end());
  cws::loadScene(p.scene, p.overrides);  // refuse a bad base scene first
  p.keys = {"case", "method"};
  // The last case and method first: the long run starts at once and the
  // short ones fill in (the report lists them in the registry's order).
  const std::vector<Case>& cases = cws::stabilityCases();
  const std::vector<cws::IntegratorInfo>& methods = cws::integrators();
  for (auto c = cases.rbegin(); c != cases.rend(); ++c) {
    if (!opt.only.empty() && c->name.find(opt.only) == std::string::npos) continue;
    for (auto m = methods.rbegin(); m != methods.rend(); ++m) {
      if (!opt.method.empty() && opt.method != m->name) continue;
      p.cases.push_back({c->name, m->name});
      p.names.push_back("runs/" + c->name + "." + m->name);
    }
  }
  if (p.cases.empty()) throw SweepError("stability: no case name contains '" + opt.only + "'");
  std::ostringstream budget, checkpoint;
  budget << std::setprecision(17) << opt.budget_s;
  checkpoint << std::setprecision(17) << opt.checkpoint_s;
  p.options = {{"budget_s", budget.str()},
               {"checkpoint_s", checkpoint.str()},
               {"jobs", std::to_string(opt.jobs)}};
  return p;
}

std::string stabilityCaseIdentity(const SweepPlan& plan, std::size_t i) {
  Run r;
  const Study st = studyOf(plan, "", i, r);
  return hex(identity(st, r));
}

int runStabilityCase(const SweepPlan& plan, const std::string& dir, std::size_t i,
                     const std::function<bool()>& stop) {
  Run r;
  Study st = studyOf(plan, dir, i, r);
  if (stop) st.stop = stop;
  fs::create_directories(st.run_dir);
  clearCaseStatus(plan, dir, i);
  execute(st, r);
  // Stopped by a signal: the checkpoint is kept, and no status (pending).
  if (r.interrupted) return -1;
  SweepCaseStatus s;
  s.identity = hex(identity(st, r));
  s.wall_s = r.wall_s;
  // A run out of its budget runs on (from its checkpoint) in the next study.
  s.status = r.outcome == Outcome::kBudget ? "failed" : "ok";
  if (r.outcome != Outcome::kStable) {
    s.error = std::string(outcomeName(r.outcome)) + (r.message.empty() ? "" : ": " + r.message);
  }
  writeCaseStatus(plan, dir, i, s);
  return s.status == "ok" ? 0 : 1;
}

int writeStabilityTables(const SweepPlan& plan, const std::string& dir, bool report_only) {
  const fs::path plan_file = fs::path(dir) / kSweepPlanFile;
  const fs::file_time_type planned = fs::last_write_time(plan_file);
  std::vector<Run> runs;
  for (std::size_t k = plan.cases.size(); k-- > 0;) {
    Run r;
    const Study st = studyOf(plan, dir, k, r);
    const SweepCaseStatus s = readCaseStatus(plan, dir, k);
    if (s.present && readResult((st.run_dir / kResultFile).string(), identity(st, r), r)) {
      // Kept: its result is older than this study's plan.
      std::error_code ec;
      const fs::file_time_type t = fs::last_write_time(st.run_dir / kSweepStatusFile, ec);
      r.kept = !ec && t < planned;
    } else if (s.present) {
      // Its process ended without a result (a crash, a signal).
      r.outcome = Outcome::kStopped;
      r.message = s.error;
      r.wall_s = s.wall_s;
    } else {
      pendingRun(st, r);
    }
    runs.push_back(r);
  }
  ReportInfo info;
  info.budget_s = std::stod(plan.option("budget_s", "18000"));
  info.jobs = std::stoi(plan.option("jobs", "0"));
  info.study_min =
      std::chrono::duration<double>(fs::file_time_type::clock::now() - planned).count() / 60.0;
  info.report_only = report_only;
  int bad = 0;
  const std::string csv = writeStabilityReport(dir, runs, info, bad);
  std::cout << csv;
  if (bad > 0) {
    std::cerr << "stability: " << bad
              << " run(s) broke the criteria or the budget, or are pending\n";
    return 1;
  }
  return 0;
}

int runStability(const std::string& scene_path, const std::vector<std::string>& overrides,
                 const std::string& dir, const StabilityOptions& opt, const SlurmOptions* slurm,
                 const std::string& exe) {
  StabilityOptions o = opt;
  if (slurm) o.jobs = 0;  // the report says: tasks of a job array
  const SweepPlan plan = stabilityPlan(scene_path, overrides, o);
  if (opt.fresh) fs::remove_all(fs::path(dir) / "runs");
  if (opt.report_only) {
    writePlan(plan, dir);
    return writeStabilityTables(plan, dir, true);
  }
  if (slurm) return runSweepSlurm(plan, dir, *slurm, exe);
  const int rc = runSweepLocal(plan, dir, opt.jobs, exe, opt.stop);
  if (rc < 0) {
    std::cerr << "stability: stopped; finished runs and checkpoints of unfinished ones are kept "
                 "in "
              << (fs::path(dir) / "runs").string() << " (the same command continues the study)\n";
  }
  return rc;
}

// The stability matrix's kind of sweep plan: its own runs, identities and
// report; a refused scene is one of its results.
const bool kStabilityKind = registerPlanKind("stability", [] {
  PlanKind k;
  k.case_identity = stabilityCaseIdentity;
  k.run_case = runStabilityCase;
  k.gather = [](const SweepPlan& plan, const std::string& dir) {
    return writeStabilityTables(plan, dir, false);
  };
  k.check_scenes = false;
  return k;
}());

}  // namespace cws_tools
