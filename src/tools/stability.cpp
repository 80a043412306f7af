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
#include <mutex>
#include <sstream>
#include <thread>

#include "coil_winding_sim/core/command_schedule.hpp"
#include "coil_winding_sim/core/output.hpp"
#include "coil_winding_sim/core/run_checks.hpp"
#include "coil_winding_sim/core/scene.hpp"
#include "coil_winding_sim/core/simulation.hpp"
#include "coil_winding_sim/core/stability_cases.hpp"
#include "coil_winding_sim/core/time_steppers/integrators.hpp"
#include "parallel.hpp"
#include "run_store.hpp"

namespace cws_tools {

namespace fs = std::filesystem;

namespace {

using Case = cws::StabilityCase;

// How a run ended.
enum class Outcome { kStable, kViolated, kStopped, kRefused, kBudget, kPending };

const char* outcomeName(Outcome o) {
  switch (o) {
    case Outcome::kStable:
      return "stable";
    case Outcome::kViolated:
      return "CRITERIA BROKEN";
    case Outcome::kStopped:
      return "stopped";
    case Outcome::kRefused:
      return "refused";
    case Outcome::kBudget:
      return "BUDGET";
    case Outcome::kPending:
      return "PENDING";
  }
  return "?";
}

struct Run {
  const Case* c = nullptr;
  std::string method;
  Outcome outcome = Outcome::kStopped;
  std::string message;  // why it stopped, was refused, or which criteria it broke
  cws::RunMeasures m;
  bool measured = false;
  double wall_s = 0.0, sim_s = 0.0, end_s = 0.0, step_s = 0.0;
  bool kept = false;         // taken from an earlier study's result file
  bool interrupted = false;  // stopped by a signal: checkpointed, no result
};

// What every run of one study shares.
struct Study {
  std::string scene_path;
  std::vector<std::string> base;
  double budget_s = 0.0;
  double checkpoint_s = 0.0;
  fs::path runs_dir;
  std::function<bool()> stop;
  bool report_only = false;
  std::mutex log;
};

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

// Bumped when the way a run is set up or measured changes, so that results
// and checkpoints of the earlier way are not reused.
constexpr int kRunProtocol = 1;

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

void execute(Study& st, Run& r) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  double wall_before = 0.0;  // of earlier studies, for a resumed run [s]
  auto wall = [&] {
    return wall_before + std::chrono::duration<double>(Clock::now() - start).count();
  };
  const std::string key = r.c->name + "." + r.method;
  const std::string result_path = (st.runs_dir / (key + ".result")).string();
  const std::string checkpoint_path = (st.runs_dir / (key + ".checkpoint")).string();
  const uint64_t id = identity(st, r);
  // A result of this run from an earlier study with the same core build is
  // kept; one that ran out of its budget continues from its checkpoint.
  if (readResult(result_path, id, r) && r.outcome != Outcome::kBudget) {
    r.kept = true;
    std::lock_guard<std::mutex> lock(st.log);
    std::cerr << "stability: " << key << ": " << outcomeName(r.outcome)
              << " (kept from an earlier study of this build)\n";
    return;
  }
  // Report only: what the kept files say, nothing run.
  if (st.report_only) {
    r.kept = true;
    if (r.outcome == Outcome::kBudget) return;  // its result was read above
    r.outcome = Outcome::kPending;
    Checkpoint c;
    std::ostringstream msg;
    if (readCheckpoint(checkpoint_path, c) && c.identity == id) {
      r.wall_s = c.wall_s;
      r.sim_s = c.state.time_s;
      msg << "not finished: checkpoint at t = " << c.state.time_s << " s after " << c.wall_s
          << " s of wall time; `make stability` continues it";
    } else {
      msg << "not run yet";
    }
    r.message = msg.str();
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
    std::lock_guard<std::mutex> lock(st.log);
    std::cerr << "stability: " << key << ": refused: " << e.what() << "\n";
    return;
  }
  // The case's speed events from the first not yet applied on.
  const std::vector<cws::SpeedEvent>& events = r.c->events;
  cws::CommandSchedule schedule;
  auto scheduleFrom = [&](std::size_t first) {
    schedule.clear();
    for (std::size_t i = first; i < events.size(); ++i) {
      schedule.add(events[i].time_s, {cws::Command::Kind::kCoreSpeed, events[i].speed_rad_s});
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
        std::lock_guard<std::mutex> lock(st.log);
        std::cerr << "stability: " << key << ": resumed at t = " << sim->time() << " s after "
                  << c.wall_s << " s of wall time\n";
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> lock(st.log);
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
      schedule.takeDue(sim->time(),
                       [&](double, const cws::Command& c) { cws::applyCommand(*sim, c); });
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
        std::lock_guard<std::mutex> lock(st.log);
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
            << fmt("%.0f", w * sim->endTime() / sim->time())
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
  std::lock_guard<std::mutex> lock(st.log);
  std::cerr << "stability: " << key << ": " << outcomeName(r.outcome) << " in " << r.wall_s << " s"
            << (r.message.empty() ? "" : ": ") << r.message << "\n";
}

// One line of the machine's CPU, for the record.
std::string machine() {
  std::ifstream f("/proc/cpuinfo");
  std::string line;
  while (std::getline(f, line)) {
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) {
        return line.substr(colon + 2) + ", " + std::to_string(std::thread::hardware_concurrency()) +
               " cores";
      }
    }
  }
  return std::to_string(std::thread::hardware_concurrency()) + " cores";
}

std::string cell(std::string s) {
  for (char& ch : s) {
    if (ch == '|' || ch == '\n') ch = ' ';
  }
  return s;
}

const char* kPreamble = R"(# Numerical stability on stiff and extreme cases

Generated by `make stability` (`wire_sim stability`); do not edit by hand.
Every case runs with every integrator; each run is checked against the
criteria below, in `cws::stabilityViolations` (core/run_checks), which the
GoogleTest cases in test/unit/test_stability.cpp assert as well.

## Criteria

A run counts as **stable** when it reaches its end time and

- **no non-finite number** appears: the simulation checks the state after
  every accepted step and stops with "the state became non-finite at t = ..."
  otherwise;
- **energy balance**: |kinetic + elastic + dissipated - work done| is at most
  1 % of max(|work done|, kinetic + elastic + dissipated) (the table's
  "energy error", with its sign: negative is energy lost). For the
  numerically dissipative methods (`implicit_euler`, `bdf2`: L-stable, they
  remove the energy of motion their step does not resolve) energy lost is
  their numerical dissipation, reported as its own term
  (`numerical_dissipation_J` in summary.json), and only energy created
  counts against the 1 %. Each term is
  computed independently (kinetic and elastic from the state, plastic work
  from the hysteresis loops, friction and viscous losses and the work of the
  core, supply and loads integrated from their power). The paper's case
  balances to about 1e-4; 1 % is far below what a diverging or
  energy-creating run shows;
- **constraint residual** (a segment off its frame's tangent, or a
  quaternion off unit length) at most 1e-3 rad at every accepted step:
  below the joint angle at first bending yield, kappa_y l = 1.6e-3 rad per
  mm of segment, so the constraint error cannot pass for plastic bending.
  A step that takes it past 0.1 stops the run as diverged ("at t = ... the
  wire diverged: a segment is ... rad off its frame's tangent ...", naming
  the method, its step and the remedy) while its numbers are still finite;
- **penetration** into the core at most half the wire radius at every
  accepted step: beyond it the penalty contact no longer holds the wire on
  the core's surface;
- **no step-size collapse**: an error-controlled method stops with a message
  naming the cause when its step falls below `solver.min_step`, or when it
  stays far below the explicit stability limit l / c (where an explicit or
  implicit method has lost its purpose; see the messages below).

A run that cannot meet them must **stop with a message that names the
cause** (outcome *stopped*), or be **refused** at validation with a message
naming the key (outcome *refused*). *CRITERIA BROKEN* would be a defect;
*BUDGET* means the run did not finish within the study's wall-time budget
(its criteria are then checked on the part run, and the message gives the
time it would need). *PENDING* (`wire_sim stability --report`) marks a run
not finished yet: the table shows a study in progress.

## Set-up

)";

}  // namespace

int runStability(const std::string& scene_path, const std::vector<std::string>& overrides,
                 const std::string& dir, const StabilityOptions& opt) {
  Study st;
  st.scene_path = scene_path;
  // The base: the given scene with the study's segment length and speed.
  st.base = {"wire.segment_length=2e-3", "process.core_speed_rpm=1200"};
  st.base.insert(st.base.end(), overrides.begin(), overrides.end());
  cws::loadScene(scene_path, st.base);  // refuse a bad base scene first
  cws::checkOutputDir(dir);
  st.budget_s = opt.budget_s;
  st.checkpoint_s = opt.checkpoint_s;
  st.stop = opt.stop ? opt.stop : [] { return false; };
  st.report_only = opt.report_only;
  st.runs_dir = fs::path(dir) / "runs";
  if (opt.fresh) fs::remove_all(st.runs_dir);
  fs::create_directories(st.runs_dir);

  const std::vector<Case>& cases = cws::stabilityCases();
  std::vector<Run> runs;
  for (const Case& c : cases) {
    if (!opt.only.empty() && c.name.find(opt.only) == std::string::npos) continue;
    // Every registered integrator.
    for (const cws::IntegratorInfo& m : cws::integrators()) {
      if (!opt.method.empty() && opt.method != m.name) continue;
      Run r;
      r.c = &c;
      r.method = m.name;
      runs.push_back(r);
    }
  }
  if (runs.empty()) {
    std::cerr << "stability: no case name contains '" << opt.only << "'\n";
    return 2;
  }
  // Last case first: the long run starts at once and the short ones fill in.
  const auto study_start = std::chrono::steady_clock::now();
  forEachParallel(runs.size(), opt.jobs, [&](std::size_t i) {
    if (!st.stop()) execute(st, runs[runs.size() - 1 - i]);
  });
  const double study_min =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - study_start).count() / 60.0;
  // Stopped by a signal: no tables; what is done stays for the next study.
  if (st.stop()) {
    std::cerr << "stability: stopped; finished runs and checkpoints of unfinished ones are kept "
                 "in "
              << st.runs_dir.string() << " (the same command continues the study)\n";
    return -1;
  }
  int kept = 0;
  double run_wall_s = 0.0;
  for (const Run& r : runs) {
    kept += r.kept;
    run_wall_s += r.wall_s;
  }

  std::ostringstream csv, md;
  csv << "case,method,outcome,energy_error_signed_rel,max_residual,max_penetration_rel_radius,"
         "steps,"
         "rejected,mean_step_s,sim_time_s,end_time_s,wall_time_s,message\n";
  md << kPreamble
     << "Base scene: the package's default scene (the paper's case in its planar form, 30 N) "
        "with 2 mm segments at 1200 rpm (`--set wire.segment_length=2e-3 --set "
        "process.core_speed_rpm=1200`), carried wire on. Each case changes what its column "
        "says. symplectic_euler steps at a quarter of the case's l / c; rkf45 and rosenbrock2 "
        "use the scene's tolerances (rtol 1e-6, atol 1e-11); implicit_euler and bdf2 take "
        "Newton steps of solver.implicit_step (1e-4 s), the first ones smaller (a run starts "
        "at 1/64 of it). Wall-time budget per run: "
     << opt.budget_s << " s. Machine: " << machine() << "; " << opt.jobs
     << " runs in parallel.\n\n"
        "| case | method | outcome | energy error | max residual | max penetration / r | "
        "steps | mean step [s] | wall [s] | message |\n"
        "|---|---|---|---|---|---|---|---|---|---|\n";
  int bad = 0;
  for (const Run& r : runs) {
    if (r.outcome == Outcome::kViolated || r.outcome == Outcome::kBudget ||
        r.outcome == Outcome::kPending) {
      ++bad;
    }
    std::string msg = r.message;
    for (char& ch : msg) {
      if (ch == '"') ch = '\'';
    }
    csv << r.c->name << ',' << r.method << ',' << outcomeName(r.outcome) << ',';
    if (r.measured) {
      csv << r.m.energy_signed_rel << ',' << r.m.residual << ',' << r.m.penetration_ratio << ','
          << r.m.steps << ',' << r.m.rejected << ',' << r.m.mean_step_s << ',';
    } else {
      csv << ",,,,,,";
    }
    csv << r.sim_s << ',' << r.end_s << ',' << r.wall_s << ",\"" << msg << "\"\n";
    md << "| " << r.c->name << " (" << r.c->what << ") | " << r.method << " | "
       << outcomeName(r.outcome) << " | ";
    if (r.measured) {
      md << fmt("%+.2e", r.m.energy_signed_rel) << " | " << fmt("%.2e", r.m.residual) << " | "
         << fmt("%.3f", r.m.penetration_ratio) << " | " << r.m.steps << " | "
         << fmt("%.2e", r.m.mean_step_s);
    } else {
      md << "- | - | - | - | -";
    }
    md << " | " << fmt("%.1f", r.wall_s) << " | " << cell(r.message) << " |\n";
  }
  md << "\nRegenerate: `make stability` (this file and docs/stability/stability.csv). The runs "
        "took "
     << fmt("%.0f", run_wall_s / 60.0) << " minutes of wall time in all";
  if (opt.report_only) {
    md << "; this table was written by `wire_sim stability --report` from the results kept so "
          "far, while the study was in progress";
  } else {
    md << "; this study took " << fmt("%.0f", study_min) << " minutes on the machine above";
    if (kept > 0) md << ", and kept " << kept << " results of an earlier study of the same build";
  }
  md << ". A study stopped with Ctrl-C keeps its finished runs and a checkpoint of each "
        "unfinished one, and the same command continues it. One case: `wire_sim stability "
        "--only NAME --out DIR`.\n";
  cws::writeFileAtomically((fs::path(dir) / "stability.csv").string(), csv.str());
  cws::writeFileAtomically((fs::path(dir) / "STABILITY.md").string(), md.str());
  std::cout << csv.str();
  if (bad > 0) {
    std::cerr << "stability: " << bad
              << " run(s) broke the criteria or the budget, or are pending\n";
    return 1;
  }
  return 0;
}

}  // namespace cws_tools
