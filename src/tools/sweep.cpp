#include "sweep.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include "coil_winding_sim/core/base/text_format.hpp"
#include "coil_winding_sim/core/run/output.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"
#include "run_store.hpp"

namespace cws_tools {

namespace fs = std::filesystem;

const char* const kSweepPlanFile = "sweep_plan.tsv";
const char* const kSweepStatusFile = "status.txt";
const char* const kSweepResultsCsv = "results.csv";
const char* const kSweepResultsMd = "results.md";

namespace {

using CaseStatus = SweepCaseStatus;

std::string oneLine(std::string s) {
  for (char& c : s) {
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  }
  return s;
}

std::string casePath(const SweepPlan& plan, const std::string& dir, std::size_t i) {
  return (fs::path(dir) / plan.caseDir(i)).string();
}

void writeStatus(const std::string& case_dir, const CaseStatus& s) {
  std::ostringstream out;
  out << "identity " << s.identity << "\nstatus " << s.status << "\nwall_s " << s.wall_s
      << "\nbudget_s " << s.budget_s << "\nerror " << oneLine(s.error) << "\n";
  cws::writeFileAtomically((fs::path(case_dir) / kSweepStatusFile).string(), out.str());
}

CaseStatus readStatus(const std::string& case_dir) {
  CaseStatus s;
  std::ifstream in(fs::path(case_dir) / kSweepStatusFile);
  if (!in) return s;
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t sp = line.find(' ');
    const std::string key = line.substr(0, sp);
    const std::string value = sp == std::string::npos ? "" : line.substr(sp + 1);
    if (key == "identity") s.identity = value;
    if (key == "status") s.status = value;
    if (key == "error") s.error = value;
    if (key == "wall_s") s.wall_s = std::atof(value.c_str());
    if (key == "budget_s") s.budget_s = std::atof(value.c_str());
  }
  s.present = s.status == "ok" || s.status == "failed" || s.status == "budget";
  return s;
}

// The plan's wall-time budget per case [s] (wire_sim sweep --budget; 0: none).
double caseBudget(const SweepPlan& plan) { return std::atof(plan.option("budget", "0").c_str()); }

std::string readText(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw SweepError("cannot read '" + path + "'");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The numbers of a case's summary.json: its top-level scalars, and those of
// its objects as "object.key" (lists are left out).
void summaryNumbers(const std::string& path, std::vector<std::pair<std::string, double>>& out) {
  const YAML::Node root = YAML::LoadFile(path);
  auto take = [&](const std::string& name, const YAML::Node& v) {
    if (!v.IsScalar()) return;
    try {
      out.emplace_back(name, v.as<double>());
    } catch (const YAML::Exception&) {
    }
  };
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    if (kv.second.IsMap()) {
      for (const auto& inner : kv.second)
        take(key + "." + inner.first.as<std::string>(), inner.second);
    } else {
      take(key, kv.second);
    }
  }
}

}  // namespace

void writeCaseStatus(const SweepPlan& plan, const std::string& dir, std::size_t i,
                     const SweepCaseStatus& s) {
  writeStatus(casePath(plan, dir, i), s);
}

SweepCaseStatus readCaseStatus(const SweepPlan& plan, const std::string& dir, std::size_t i) {
  return readStatus(casePath(plan, dir, i));
}

std::map<std::string, double> readSummaryNumbers(const std::string& path) {
  std::vector<std::pair<std::string, double>> numbers;
  summaryNumbers(path, numbers);
  return std::map<std::string, double>(numbers.begin(), numbers.end());
}

SweepPlan readCasesFile(const std::string& scene, const std::vector<std::string>& overrides,
                        const std::string& path) {
  return casesPlan(scene, overrides, readText(path), path);
}

void writePlan(const SweepPlan& plan, const std::string& dir) {
  fs::create_directories(dir);
  cws::writeFileAtomically((fs::path(dir) / kSweepPlanFile).string(), planText(plan));
}

SweepPlan readPlan(const std::string& dir) {
  const std::string path = (fs::path(dir) / kSweepPlanFile).string();
  if (!fs::exists(path)) {
    throw SweepError("'" + dir + "' holds no sweep plan (" + kSweepPlanFile +
                     "): run wire_sim sweep with --out " + dir + " first");
  }
  return parsePlanText(readText(path), path);
}

std::string caseIdentity(const SweepPlan& plan, std::size_t index) {
  const PlanKind* kind = findPlanKind(plan.kind);
  if (kind && kind->case_identity) return kind->case_identity(plan, index);
  const cws::Scene scene = cws::loadScene(plan.scene, plan.caseOverrides(index));
  char buf[40];
  std::snprintf(buf, sizeof buf, "%016llx",
                static_cast<unsigned long long>(
                    fnv1a(std::to_string(coreBuildHash()) + "\n" + cws::sceneToYamlText(scene))));
  return buf;
}

int runSweepCase(const std::string& dir, std::size_t index, const std::function<bool()>& stop) {
  SweepPlan plan;
  try {
    plan = readPlan(dir);
  } catch (const std::exception& e) {
    std::cerr << "wire_sim: sweep-run: " << e.what() << "\n";
    return 2;
  }
  if (index >= plan.cases.size()) {
    std::cerr << "wire_sim: sweep-run: case " << index << " is not in the sweep (it has "
              << plan.cases.size() << " cases, 0 to " << plan.cases.size() - 1 << ")\n";
    return 2;
  }
  const PlanKind* kind = findPlanKind(plan.kind);
  if (kind && kind->run_case) return kind->run_case(plan, dir, index, stop);
  const std::string case_dir = casePath(plan, dir, index);
  fs::create_directories(case_dir);
  std::error_code ec;
  fs::remove(fs::path(case_dir) / kSweepStatusFile, ec);
  cws::removeOutputs(case_dir);
  CaseStatus s;
  const auto start = std::chrono::steady_clock::now();
  s.budget_s = caseBudget(plan);
  bool out_of_budget = false;
  const auto within = [&] {
    if (stop && stop()) return true;
    if (s.budget_s <= 0.0) return false;
    out_of_budget =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >
        s.budget_s;
    return out_of_budget;
  };
  try {
    s.identity = caseIdentity(plan, index);
    cws::Simulation sim(cws::loadScene(plan.scene, plan.caseOverrides(index)));
    std::cerr << "sweep-run: case " << index << " (" << plan.caseLabel(index)
              << "), until t = " << sim.endTime() << " s\n";
    sim.run({}, within);
    // Stopped: no result and no status, so the case reads as pending.
    if (stop && stop()) {
      std::cerr << "sweep-run: case " << index << " stopped at t = " << sim.time() << " s\n";
      return -1;
    }
    // Out of budget: the figures of the part it ran, marked as such.
    cws::writeOutputs(sim, case_dir);
    s.status = out_of_budget ? "budget" : "ok";
    if (out_of_budget) {
      s.error = "not finished within the budget of " + cws::formatNumber(s.budget_s) +
                " s of wall time: at t = " + cws::formatNumber(sim.time()) + " s of " +
                cws::formatNumber(sim.endTime()) + " s (real-time factor " +
                cws::formatNumber(sim.realTimeFactor(), "%.3g") + ")";
      std::cerr << "sweep-run: case " << index << ": " << s.error << "\n";
    }
  } catch (const std::exception& e) {
    s.status = "failed";
    s.error = e.what();
    std::cerr << "sweep-run: case " << index << " failed: " << e.what() << "\n";
  }
  s.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  writeStatus(case_dir, s);
  return s.status == "ok" ? 0 : 1;
}

std::vector<std::size_t> casesToRun(const SweepPlan& plan, const std::string& dir,
                                    std::size_t& kept) {
  std::vector<std::size_t> todo;
  kept = 0;
  for (std::size_t i = 0; i < plan.cases.size(); ++i) {
    const CaseStatus s = readStatus(casePath(plan, dir, i));
    // A case that ran out of its budget is kept while the budget is not
    // raised (it would run out again).
    const bool kept_budget = s.status == "budget" && s.budget_s >= caseBudget(plan);
    if (s.present && (s.status == "ok" || kept_budget) && s.identity == caseIdentity(plan, i)) {
      ++kept;
    } else {
      todo.push_back(i);
    }
  }
  return todo;
}

void clearCaseStatus(const SweepPlan& plan, const std::string& dir, std::size_t i) {
  std::error_code ec;
  fs::remove(fs::path(casePath(plan, dir, i)) / kSweepStatusFile, ec);
  if (ec)
    throw SweepError("cannot remove '" + casePath(plan, dir, i) + "/" + kSweepStatusFile + "'");
}

int runSweepLocal(const SweepPlan& plan, const std::string& dir, int jobs, const std::string& exe,
                  const std::function<bool()>& stop) {
  writePlan(plan, dir);
  const std::size_t n = plan.cases.size();
  std::size_t kept = 0;
  const std::vector<std::size_t> todo = casesToRun(plan, dir, kept);
  const PlanKind* kind = findPlanKind(plan.kind);
  const bool quiet = kind && kind->quiet;
  if (!quiet)
    std::cerr << "sweep: " << n << " cases in " << dir << ", " << kept
              << " kept from an earlier sweep, " << todo.size() << " to run, " << jobs
              << " at once\n";
  std::map<pid_t, std::size_t> running;
  std::size_t next = 0, finished = 0;
  auto start = [&](std::size_t i) {
    const std::string case_dir = casePath(plan, dir, i);
    fs::create_directories(case_dir);
    const std::string log = (fs::path(case_dir) / "log.txt").string();
    const std::string index = std::to_string(i);
    const pid_t pid = fork();
    if (pid == 0) {
      // A process group of its own: a Ctrl-C reaches the sweep, which
      // passes it on once (a second SIGINT would end a run unsaved).
      setpgid(0, 0);
      const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (fd >= 0) {
        dup2(fd, STDOUT_FILENO);
        dup2(fd, STDERR_FILENO);
        close(fd);
      }
      execl(exe.c_str(), exe.c_str(), "sweep-run", dir.c_str(), index.c_str(),
            static_cast<char*>(nullptr));
      std::perror("exec");
      _exit(127);
    }
    if (pid < 0) throw std::runtime_error("sweep: cannot start a process for case " + index);
    running[pid] = i;
  };
  while (next < todo.size() || !running.empty()) {
    // Stopped: the running cases stop too (a run of the stability study
    // keeps a checkpoint), and what has finished is kept.
    if (stop && stop()) {
      for (const auto& r : running) kill(r.first, SIGINT);
      for (const auto& r : running) waitpid(r.first, nullptr, 0);
      if (!quiet)
        std::cerr << "sweep: stopped; " << finished << " of " << todo.size()
                  << " cases had finished, the others are pending (the same command goes on)\n";
      return -1;
    }
    while (next < todo.size() && static_cast<int>(running.size()) < jobs) start(todo[next++]);
    // Polled, so that a stop is seen within 50 ms whenever it comes.
    int wstatus = 0;
    const pid_t pid = waitpid(-1, &wstatus, WNOHANG);
    if (pid == 0 || (pid < 0 && errno == EINTR)) {
      usleep(50000);
      continue;
    }
    if (pid < 0) break;
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const std::size_t i = it->second;
    running.erase(it);
    ++finished;
    const std::string case_dir = casePath(plan, dir, i);
    CaseStatus s = readStatus(case_dir);
    if (!s.present) {
      // The process ended without a result (a crash, a signal).
      s.identity = caseIdentity(plan, i);
      s.status = "failed";
      s.error = WIFSIGNALED(wstatus)
                    ? "the case's process ended by signal " + std::to_string(WTERMSIG(wstatus))
                    : "the case's process ended with status " +
                          std::to_string(WEXITSTATUS(wstatus)) + " and no result";
      writeStatus(case_dir, s);
    }
    if (quiet) continue;
    char wall[32];
    std::snprintf(wall, sizeof wall, "%.3g", s.wall_s);
    std::cerr << "sweep: [" << finished << "/" << todo.size() << "] " << plan.caseDir(i) << " ("
              << plan.caseLabel(i) << "): "
              << (s.status == "ok" ? std::string("ok in ") + wall + " s" +
                                         (s.error.empty() ? "" : ": " + s.error)
                                   : s.status + ": " + s.error)
              << "\n";
  }
  return gatherSweep(dir);
}

int gatherSweep(const std::string& dir) {
  const SweepPlan plan = readPlan(dir);
  // A kind with a table of its own (the stability study's report).
  const PlanKind* kind = findPlanKind(plan.kind);
  if (kind && kind->gather) return kind->gather(plan, dir);
  const std::size_t n = plan.cases.size();
  std::vector<CaseStatus> status(n);
  std::vector<std::vector<std::pair<std::string, double>>> numbers(n);
  std::vector<std::string> columns;
  std::map<std::string, bool> known;
  std::vector<std::size_t> pending;
  std::size_t failed = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::string case_dir = casePath(plan, dir, i);
    status[i] = readStatus(case_dir);
    if (!status[i].present) {
      pending.push_back(i);
      continue;
    }
    if (status[i].status == "failed") {
      ++failed;
      continue;
    }
    // Out of budget: a row with the figures of the part it ran.
    if (status[i].status == "budget") ++failed;
    try {
      summaryNumbers((fs::path(case_dir) / "summary.json").string(), numbers[i]);
    } catch (const std::exception& e) {
      status[i].status = "failed";
      status[i].error = std::string("its summary.json cannot be read: ") + e.what();
      ++failed;
      continue;
    }
    for (const auto& kv : numbers[i]) {
      if (!known[kv.first]) {
        known[kv.first] = true;
        columns.push_back(kv.first);
      }
    }
  }
  // results.csv: every figure; results.md: the ones an engineer reads first.
  std::ostringstream csv, md;
  csv << "case";
  for (const std::string& k : plan.keys) csv << "," << cws::csvField(k);
  csv << ",status,error";
  for (const std::string& c : columns) csv << "," << c;
  csv << "\n";
  md << "| case |";
  for (const std::string& k : plan.keys) md << " " << cws::markdownCell(k) << " |";
  md << " status | bulging height [mm] | max penetration / r | real-time factor | wall time [s] "
        "|\n|---|";
  for (std::size_t k = 0; k < plan.keys.size(); ++k) md << "---|";
  md << "---|---|---|---|---|\n";
  char buf[64];
  for (std::size_t i = 0; i < n; ++i) {
    const CaseStatus& s = status[i];
    const std::string state = s.present ? s.status : "pending";
    csv << plan.caseDir(i);
    for (const std::string& v : plan.cases[i]) csv << "," << cws::csvField(v);
    csv << "," << state << "," << cws::csvField(s.error);
    std::map<std::string, double> values(numbers[i].begin(), numbers[i].end());
    for (const std::string& c : columns) {
      csv << ",";
      const auto it = values.find(c);
      if (it != values.end()) {
        std::snprintf(buf, sizeof buf, "%.10g", it->second);
        csv << buf;
      }
    }
    csv << "\n";
    md << "| " << plan.caseDir(i) << " |";
    for (const std::string& v : plan.cases[i]) md << " " << cws::markdownCell(v) << " |";
    if (state != "ok" && state != "budget") {
      md << " " << state << (s.error.empty() ? "" : ": " + cws::markdownCell(s.error))
         << " | | | | |\n";
      continue;
    }
    auto cell = [&](const char* key, double scale, const char* format) {
      const auto it = values.find(key);
      if (it == values.end()) return std::string(" |");
      std::snprintf(buf, sizeof buf, format, scale * it->second);
      return std::string(" ") + buf + " |";
    };
    md << " " << (state == "ok" ? state : state + ": " + cws::markdownCell(s.error)) << " |"
       << cell("bulging_height_m", 1e3, "%.4f") << cell("max_penetration_ratio", 1.0, "%.3f")
       << cell("real_time_factor", 1.0, "%.3g") << cell("wall_time_s", 1.0, "%.2f") << "\n";
  }
  cws::writeFileAtomically((fs::path(dir) / kSweepResultsCsv).string(), csv.str());
  cws::writeFileAtomically((fs::path(dir) / kSweepResultsMd).string(), md.str());
  std::cerr << "sweep: " << n - pending.size() - failed << " of " << n << " cases ok, " << failed
            << " failed or out of budget, " << pending.size() << " not finished; table in "
            << (fs::path(dir) / kSweepResultsCsv).string() << "\n";
  if (!pending.empty()) {
    std::cerr << "sweep: not finished:";
    for (std::size_t i : pending) std::cerr << " " << plan.caseDir(i);
    std::cerr << "\n";
  }
  int rc = pending.empty() && failed == 0 ? 0 : 1;
  // What the plan's kind adds to the table.
  if (kind && kind->add_to_table) rc = std::max(rc, kind->add_to_table(plan, dir));
  return rc;
}

}  // namespace cws_tools
