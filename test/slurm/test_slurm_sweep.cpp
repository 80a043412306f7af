// A sweep through a real one-node Slurm (munged, slurmctld and slurmd on
// localhost, started by test/slurm/local_slurm.sh as root and stopped
// after the test): a 2 x 3 sweep goes through `wire_sim sweep --slurm` as a
// job array with a gather job, and its table equals that of the same sweep
// run locally; so does a calibration's result. If the daemons cannot start,
// the test fails with the script's message naming why.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "../unit/cli_test_support.hpp"

namespace {

namespace fs = std::filesystem;
using cli_test::contains;
using cli_test::readAll;
using cli_test::splitLines;

// Runs a shell command; its exit status, stdout in `out`, stderr in `err`.
int shell(const std::string& cmd, const fs::path& scratch, std::string& out, std::string& err) {
  const fs::path o = scratch / "shell_out.txt", e = scratch / "shell_err.txt";
  const int raw = std::system(
      (cmd + " >" + cli_test::shellQuote(o.string()) + " 2>" + cli_test::shellQuote(e.string()))
          .c_str());
  out = readAll(o);
  err = readAll(e);
  return raw != -1 && WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
}

// Splits a CSV line (no quoted commas in these tables' compared columns).
std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> c(1);
  for (char ch : line) {
    if (ch == ',') {
      c.emplace_back();
    } else {
      c.back() += ch;
    }
  }
  return c;
}

// A results table without the columns that measure this machine's speed
// (the slowest stretch is where this run went slowest on this machine).
std::vector<std::string> figures(const std::string& csv) {
  std::vector<std::string> lines = splitLines(csv);
  if (lines.empty()) return lines;
  const std::vector<std::string> header = cells(lines[0]);
  std::vector<std::string> rows;
  for (const std::string& line : lines) {
    const std::vector<std::string> c = cells(line);
    std::string row;
    for (std::size_t k = 0; k < c.size() && k < header.size(); ++k) {
      if (header[k] == "wall_time_s" || header[k] == "real_time_factor" ||
          header[k].rfind("slowest_stretch.", 0) == 0)
        continue;
      row += header[k] + "=" + c[k] + ";";
    }
    rows.push_back(row);
  }
  return rows;
}

class OneNodeSlurm : public cli_test::WireSimCli {
 protected:
  void SetUp() override {
    WireSimCli::SetUp();
    script_ = std::string(CWS_SOURCE_DIR) + "/test/slurm/local_slurm.sh";
    state_ = dir_ / "slurm_state";
    // A start that fails is tried once more (the script has stopped what it
    // started); both messages are kept for the failure.
    std::string out, err, first_err;
    int rc = -1;
    for (int attempt = 0; attempt < 2 && rc != 0; ++attempt) {
      rc = shell("bash " + cli_test::shellQuote(script_) + " start " +
                     cli_test::shellQuote(state_.string()),
                 dir_, out, err);
      if (attempt == 0 && rc != 0) first_err = err;
    }
    started_ = true;
    if (!first_err.empty()) std::cerr << "the first start failed:\n" << first_err;
    ASSERT_EQ(rc, 0) << "the one-node Slurm did not start (it needs root, and Debian's "
                        "slurm-wlm and munge, which `make deps` installs):\n"
                     << first_err << "\nagain:\n"
                     << err;
    // The client side: sbatch, squeue (and wire_sim's sbatch) use this
    // cluster's configuration.
    ASSERT_EQ(setenv("SLURM_CONF", (state_ / "slurm.conf").string().c_str(), 1), 0);
  }
  void TearDown() override {
    if (started_) {
      std::string out, err;
      const int rc = shell("bash " + cli_test::shellQuote(script_) + " stop " +
                               cli_test::shellQuote(state_.string()),
                           dir_, out, err);
      EXPECT_EQ(rc, 0) << err;
      unsetenv("SLURM_CONF");
    }
    WireSimCli::TearDown();
  }
  // The tails of the daemons' logs, for a failure message.
  std::string logs() const {
    std::string all;
    for (const char* name : {"slurmctld.log", "slurmd.log"}) {
      const std::vector<std::string> lines = splitLines(readAll(state_ / name));
      all += std::string("--- tail of ") + name + " ---\n";
      for (std::size_t i = lines.size() > 20 ? lines.size() - 20 : 0; i < lines.size(); ++i)
        all += lines[i] + "\n";
    }
    return all;
  }
  std::string script_;
  fs::path state_;
  bool started_ = false;
};

TEST_F(OneNodeSlurm, JobArraySweepEqualsTheLocalSweep) {
  const std::vector<std::string> sweep{"sweep",
                                       "--grid",
                                       "process.core_speed_rpm=600,1200",
                                       "--grid",
                                       "process.tension=20:80:3",
                                       "--set",
                                       "process.turns=0.05",
                                       "--set",
                                       "solver.integrator=bdf2"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> a = sweep;
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  };
  const fs::path on_slurm = dir_ / "on_slurm", local = dir_ / "local";
  const cli_test::RunResult submitted =
      run(with({"--slurm", "--max-running", "2", "--time", "5", "--out", on_slurm.string()}));
  ASSERT_EQ(submitted.status, 0) << submitted.err << logs();
  EXPECT_TRUE(contains(submitted.err, "6 to run on Slurm")) << submitted.err;
  const std::string jobs = readAll(on_slurm / "slurm" / "jobs.txt");
  ASSERT_TRUE(contains(jobs, "cases ") && contains(jobs, "gather ")) << jobs;

  // Wait for the gather job: the table is written and the queue is empty.
  // (A guard, not a timing assertion: it gives up after 5 minutes.)
  std::string queue, err;
  for (int i = 0; i < 1500; ++i) {
    ASSERT_EQ(shell("squeue -h -o '%i %T'", dir_, queue, err), 0) << err;
    if (queue.empty() && fs::exists(on_slurm / "results.csv")) break;
    usleep(200000);
  }
  ASSERT_TRUE(queue.empty()) << "jobs still queued after 5 minutes:\n" << queue;
  if (!fs::exists(on_slurm / "results.csv")) {
    std::string logs;
    for (const auto& e : fs::directory_iterator(on_slurm / "slurm" / "logs")) {
      logs += e.path().string() + ":\n" + readAll(e.path());
    }
    FAIL() << "the gather job wrote no table; the jobs' logs:\n" << logs;
  }

  // Every case ran as a task of the array, each with its log.
  int task_logs = 0;
  for (const auto& e : fs::directory_iterator(on_slurm / "slurm" / "logs")) {
    task_logs += e.path().filename().string().rfind("case_", 0) == 0;
  }
  EXPECT_EQ(task_logs, 6);

  // The same sweep here, two processes at once: the same table, but for the
  // wall times.
  const cli_test::RunResult here = run(with({"--jobs", "2", "--out", local.string()}));
  ASSERT_EQ(here.status, 0) << here.err;
  const std::vector<std::string> a = figures(readAll(on_slurm / "results.csv"));
  const std::vector<std::string> b = figures(readAll(local / "results.csv"));
  ASSERT_EQ(a.size(), 7u) << readAll(on_slurm / "results.csv");
  EXPECT_EQ(a, b);
  for (std::size_t i = 1; i < a.size(); ++i) EXPECT_TRUE(contains(a[i], "status=ok;")) << a[i];

  // Submitted again: every case is kept, none is submitted, and the gather
  // job alone rewrites the table.
  const cli_test::RunResult again = run(with({"--slurm", "--out", on_slurm.string()}));
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_TRUE(contains(again.err, "6 kept from an earlier sweep, 0 to run")) << again.err;
}

// A calibration's evaluations as job arrays (wire_sim calibrate --slurm):
// the same search as on this machine with as many at once (--batch 4 on
// Slurm, --jobs 4 here), so the same evaluations and the same result.
TEST_F(OneNodeSlurm, CalibrationOnSlurmEqualsTheLocalOne) {
  // A machine bag: commands (1200 rpm, 70 N) replayed with known values.
  const std::string tools = std::string(CWS_SOURCE_DIR) + "/src/tools/";
  const fs::path commands = dir_ / "commands.bag", machine = dir_ / "machine.bag";
  std::string out, err;
  ASSERT_EQ(shell("/usr/bin/python3 " + tools + "make_synthetic_bags.py --machine-bag " +
                      commands.string() +
                      " --duration 0.3 --rate 100 --record-delay 0 --tension-command 70"
                      " --drop-topic port/command --drop-topic port/position --drop-topic profile",
                  dir_, out, err),
            0)
      << err;
  const std::string scene = std::string(CWS_SOURCE_DIR) + "/config/scenes/winding_cell.yaml";
  const cli_test::RunResult truth =
      run({"replay", commands.string(), "--scene", scene, "--set", "wire.bend.yield_curvature=2",
           "--profile-rate", "20", "--out", (dir_ / "truth").string()});
  ASSERT_EQ(truth.status, 0) << truth.err;
  ASSERT_EQ(shell("/usr/bin/python3 " + tools + "make_synthetic_bags.py --from-sim-bag " +
                      (dir_ / "truth" / "replay.bag").string() + " --machine-bag " +
                      machine.string() + " --profile-noise-mm 0.002 --seed 2",
                  dir_, out, err),
            0)
      << err;
  const std::vector<std::string> calibrate{"calibrate",      machine.string(),
                                           "--scene",        scene,
                                           "--fit",          "wire.bend.yield_curvature=1:3",
                                           "--design",       "2",
                                           "--evaluations",  "8",
                                           "--profile-rate", "20"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> a = calibrate;
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  };
  const fs::path on_slurm = dir_ / "cal_slurm", local = dir_ / "cal_local";
  const cli_test::RunResult a =
      run(with({"--slurm", "--batch", "4", "--time", "5", "--out", on_slurm.string()}));
  ASSERT_EQ(a.status, 0) << a.err << logs();
  EXPECT_TRUE(contains(a.err, "to run on Slurm")) << a.err;
  const cli_test::RunResult b = run(with({"--jobs", "4", "--out", local.string()}));
  ASSERT_EQ(b.status, 0) << b.err;
  // The same numbers, but for the wall time.
  auto figures = [](const std::string& json) {
    std::string kept;
    for (const std::string& line : splitLines(json)) {
      if (!contains(line, "wall_time_s") && !contains(line, "machine_bag")) kept += line + "\n";
    }
    return kept;
  };
  EXPECT_EQ(figures(readAll(on_slurm / "calibration.json")),
            figures(readAll(local / "calibration.json")));
  EXPECT_TRUE(contains(readAll(local / "calibration.json"), "\"identifiable\": true"));
}

// sbatch refusing the job (an unknown partition) is reported with Slurm's
// own message, and the sweep exits 1.
TEST_F(OneNodeSlurm, RefusedSubmissionNamesSlurmsReason) {
  const cli_test::RunResult r =
      run({"sweep", "--grid", "process.tension=20,30", "--set", "process.turns=0.05", "--slurm",
           "--partition", "no_such_partition", "--out", (dir_ / "refused").string()});
  EXPECT_EQ(r.status, 1) << r.err << logs();
  EXPECT_TRUE(contains(r.err, "sbatch")) << r.err << logs();
  EXPECT_TRUE(contains(r.err, "partition")) << r.err << logs();
}

}  // namespace
