#include "sweep_slurm.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <regex>
#include <sstream>

#include "coil_winding_sim/core/run/output.hpp"
#include "sweep.hpp"

namespace cws_tools {

namespace fs = std::filesystem;

namespace {

// A path inside double quotes in a bash script.
std::string quoted(const std::string& s) {
  std::string q = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\' || c == '$' || c == '`') q += '\\';
    q += c;
  }
  return q + "\"";
}

// The #SBATCH lines every job of the sweep shares.
std::string commonHeader(const SlurmOptions& o, const std::string& dir) {
  std::ostringstream s;
  s << "#!/bin/bash\n";
  if (!o.partition.empty()) s << "#SBATCH --partition=" << o.partition << "\n";
  if (!o.account.empty()) s << "#SBATCH --account=" << o.account << "\n";
  s << "#SBATCH --ntasks=1\n#SBATCH --cpus-per-task=1\n";
  s << "#SBATCH --chdir=" << dir << "\n";
  return s.str();
}

// Runs argv, returning its exit status and what it printed (stdout, stderr
// in `err`); -1 when it could not be started.
int capture(const std::vector<std::string>& argv, std::string& out, std::string& err) {
  int pout[2], perr[2];
  if (pipe(pout) != 0) return -1;
  if (pipe(perr) != 0) {
    close(pout[0]);
    close(pout[1]);
    return -1;
  }
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(pout[1], STDOUT_FILENO);
    dup2(perr[1], STDERR_FILENO);
    close(pout[0]);
    close(perr[0]);
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execvp(args[0], args.data());
    std::fprintf(stderr, "cannot run %s: %s\n", args[0], std::strerror(errno));
    _exit(127);
  }
  close(pout[1]);
  close(perr[1]);
  if (pid < 0) {
    close(pout[0]);
    close(perr[0]);
    return -1;
  }
  // Both pipes are read to their end (sbatch prints little).
  auto drain = [](int fd, std::string& to) {
    char buf[4096];
    ssize_t n;
    while ((n = read(fd, buf, sizeof buf)) > 0) to.append(buf, static_cast<std::size_t>(n));
    close(fd);
  };
  drain(pout[0], out);
  drain(perr[0], err);
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// `sbatch --parsable [extra] script`: the job id, or throws naming the script
// and sbatch's message.
std::string submit(const std::string& script, const std::vector<std::string>& extra) {
  std::vector<std::string> argv{"sbatch", "--parsable"};
  argv.insert(argv.end(), extra.begin(), extra.end());
  argv.push_back(script);
  std::string out, err;
  const int rc = capture(argv, out, err);
  // --parsable prints "jobid" or "jobid;cluster".
  const std::string id = out.substr(0, out.find_first_of(";\n"));
  const bool numeric = !id.empty() && std::all_of(id.begin(), id.end(), [](unsigned char c) {
    return std::isdigit(c) != 0;
  });
  if (rc != 0 || !numeric) {
    std::string why = err.empty() ? out : err;
    while (!why.empty() && std::isspace(static_cast<unsigned char>(why.back()))) why.pop_back();
    throw std::runtime_error("sbatch " + script + " failed" +
                             (rc == 127 || rc < 0 ? " (is sbatch on PATH?)" : "") +
                             (why.empty() ? "" : ": " + why));
  }
  return id;
}

}  // namespace

bool isSlurmValueOption(const std::string& opt) {
  return opt == "--partition" || opt == "--time" || opt == "--mem" || opt == "--account" ||
         opt == "--max-running" || opt == "--max-array-size";
}

std::string setSlurmOption(SlurmOptions& o, const std::string& opt, const std::string& value) {
  if (opt == "--max-running" || opt == "--max-array-size") {
    int n = -1;
    try {
      std::size_t used = 0;
      n = std::stoi(value, &used);
      if (used != value.size()) n = -1;
    } catch (const std::exception&) {
      n = -1;
    }
    if (n < (opt == "--max-running" ? 1 : 2) || n > 10000000) {
      return opt + " needs a whole number " + (opt == "--max-running" ? "from 1" : "from 2") +
             ", got '" + value + "'";
    }
    (opt == "--max-running" ? o.max_running : o.max_array_size) = n;
  } else {
    (opt == "--partition" ? o.partition
     : opt == "--time"    ? o.time_limit
     : opt == "--mem"     ? o.memory
                          : o.account) = value;
  }
  try {
    checkSlurmOptions(o);
  } catch (const SweepError& e) {
    return e.what();
  }
  return "";
}

void checkSlurmOptions(const SlurmOptions& o) {
  static const std::regex name("[A-Za-z0-9_.,-]+");
  static const std::regex time("([0-9]+-)?[0-9]+(:[0-9]+){0,2}");
  static const std::regex memory("[0-9]+[KMGT]?");
  if (!o.partition.empty() && !std::regex_match(o.partition, name)) {
    throw SweepError("--partition '" + o.partition + "': not a partition name");
  }
  if (!o.account.empty() && !std::regex_match(o.account, name)) {
    throw SweepError("--account '" + o.account + "': not an account name");
  }
  if (!o.time_limit.empty() && !std::regex_match(o.time_limit, time)) {
    throw SweepError("--time '" + o.time_limit +
                     "': not a Slurm time limit (minutes, MM:SS, HH:MM:SS or D-HH:MM:SS)");
  }
  if (!o.memory.empty() && !std::regex_match(o.memory, memory)) {
    throw SweepError("--mem '" + o.memory + "': not a Slurm memory size (e.g. 500M, 2G)");
  }
  if (o.max_running < 0) throw SweepError("--max-running must be 0 (no limit) or more");
  if (o.max_array_size < 2) throw SweepError("--max-array-size must be 2 or more");
}

std::string arrayList(const std::vector<std::size_t>& indices) {
  std::ostringstream s;
  for (std::size_t k = 0; k < indices.size();) {
    std::size_t end = k;
    while (end + 1 < indices.size() && indices[end + 1] == indices[end] + 1) ++end;
    s << (k ? "," : "") << indices[k];
    if (end > k) s << "-" << indices[end];
    k = end + 1;
  }
  return s.str();
}

std::string slurmArrayScript(const SlurmOptions& o, const std::string& exe, const std::string& dir,
                             std::size_t first, const std::string& array) {
  std::ostringstream s;
  s << commonHeader(o, dir);
  s << "#SBATCH --job-name=cws_sweep\n";
  s << "#SBATCH --array=" << array;
  if (o.max_running > 0) s << "%" << o.max_running;
  s << "\n";
  if (!o.time_limit.empty()) s << "#SBATCH --time=" << o.time_limit << "\n";
  if (!o.memory.empty()) s << "#SBATCH --mem=" << o.memory << "\n";
  s << "#SBATCH --output=" << (fs::path(dir) / "slurm" / "logs" / "case_%A_%a.log").string()
    << "\n";
  s << "# One case of the sweep per task: case " << first
    << " + the task's index. It writes its outputs\n"
       "# and status.txt into its case_NNNN folder; a task that Slurm stops leaves the\n"
       "# case pending, and the next `wire_sim sweep` with the same --out runs it again.\n";
  s << "exec " << quoted(exe) << " sweep-run " << quoted(dir) << " \"$((" << first
    << " + SLURM_ARRAY_TASK_ID))\"\n";
  return s.str();
}

std::string slurmGatherScript(const SlurmOptions& o, const std::string& exe,
                              const std::string& dir) {
  std::ostringstream s;
  s << commonHeader(o, dir);
  s << "#SBATCH --job-name=cws_sweep_gather\n#SBATCH --time=10\n";
  s << "#SBATCH --output=" << (fs::path(dir) / "slurm" / "logs" / "gather_%j.log").string() << "\n";
  s << "# The sweep's table, once every case task has ended (afterany).\n";
  s << "exec " << quoted(exe) << " sweep-gather " << quoted(dir) << "\n";
  return s.str();
}

int runSweepSlurm(const SweepPlan& plan, const std::string& dir_arg, const SlurmOptions& o,
                  const std::string& exe) {
  checkSlurmOptions(o);
  const std::string dir = fs::absolute(dir_arg).lexically_normal().string();
  writePlan(plan, dir);
  const fs::path slurm = fs::path(dir) / "slurm";
  fs::create_directories(slurm / "logs");
  std::size_t kept = 0;
  const std::vector<std::size_t> todo = casesToRun(plan, dir, kept);
  std::cerr << "sweep: " << plan.cases.size() << " cases in " << dir << ", " << kept
            << " kept from an earlier sweep, " << todo.size() << " to run on Slurm\n";

  // One array per block of max_array_size - 1 case indices: Slurm's array
  // indices stay below MaxArraySize.
  const std::size_t block = static_cast<std::size_t>(o.max_array_size) - 1;
  std::vector<std::pair<std::string, std::string>> arrays;  // script, array spec
  for (std::size_t k = 0; k < todo.size();) {
    const std::size_t first = todo[k] / block * block;
    std::vector<std::size_t> local;
    for (; k < todo.size() && todo[k] < first + block; ++k) local.push_back(todo[k] - first);
    const std::string script = (slurm / ("cases_" + std::to_string(first) + ".sbatch")).string();
    cws::writeFileAtomically(script, slurmArrayScript(o, exe, dir, first, arrayList(local)));
    arrays.emplace_back(script, std::to_string(first));
  }
  const std::string gather = (slurm / "gather.sbatch").string();
  cws::writeFileAtomically(gather, slurmGatherScript(o, exe, dir));
  if (o.dry_run) {
    std::cerr << "sweep: dry run: scripts in " << slurm.string() << ", nothing submitted\n";
    for (const auto& a : arrays) std::cout << "sbatch --parsable " << a.first << "\n";
    std::cout << "sbatch --dependency=afterany:<the arrays' job ids> " << gather << "\n";
    return 0;
  }
  try {
    // A case to run again reads as pending until its task has run.
    for (std::size_t i : todo) clearCaseStatus(plan, dir, i);
    std::string dependency;
    std::ostringstream jobs;
    for (const auto& a : arrays) {
      const std::string id = submit(a.first, {});
      dependency += ":" + id;
      jobs << "cases " << id << " " << a.first << "\n";
      std::cerr << "sweep: submitted job array " << id << " (" << a.first << ")\n";
    }
    const std::string gid =
        submit(gather, dependency.empty()
                           ? std::vector<std::string>{}
                           : std::vector<std::string>{"--dependency=afterany" + dependency});
    jobs << "gather " << gid << " " << gather << "\n";
    cws::writeFileAtomically((slurm / "jobs.txt").string(), jobs.str());
    std::cerr << "sweep: submitted gather job " << gid << "; the table will be in "
              << (fs::path(dir) / kSweepResultsCsv).string() << " (wire_sim sweep-gather " << dir
              << " shows the progress)\n";
    std::cout << gid << "\n";
  } catch (const std::exception& e) {
    std::cerr << "wire_sim: sweep: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace cws_tools
