// Tests of the wire_sim command-line tool (see test_cli.cpp): runs that fail
// or are stopped part way leave no results; studies remove or resume theirs.
#ifdef CWS_WIRE_SIM_EXE

#include "cli_test_support.hpp"

namespace {

using namespace cli_test;

// ---------------------------------------------------------------------------
// Runs that fail or are stopped part way leave the results of the state
// they reached, marked "stopped" with the cause, never an unmarked summary.

// A run that integrates for a while and then fails: a 1 kN end force applied
// at t = 1 ms to a small wire makes rkf45 need steps below solver.min_step
// (1e-8 s) soon after; until then it steps normally.
TEST_F(WireSimCli, RunFailingMidwayLeavesAStoppedSummary) {
  const fs::path out = dir_ / "out";
  ASSERT_EQ(runSmall(out.string()).status, 0);
  ASSERT_TRUE(fs::exists(out / "summary.json"));
  const RunResult r = runSmall(
      out.string(), {"--set", "process.duration=2e-3", "--set", "solver.integrator=rkf45", "--set",
                     "end.load=[{time: 0}, {time: 1e-3}, {time: 1.001e-3, force: [0, 1e3, 0]}]",
                     "--set", "solver.min_step=1e-8", "--set", "solver.initial_step=1e-6"});
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_TRUE(contains(r.err, "run failed")) << r.err;
  EXPECT_TRUE(contains(r.err, "min_step")) << r.err;
  // It failed where the load came on, not at the start (the step that
  // fails reaches into the load and may start just before 1e-3 s).
  const std::size_t at = r.err.find("at t = ");
  ASSERT_NE(at, std::string::npos) << r.err;
  EXPECT_GE(std::strtod(r.err.c_str() + at + 7, nullptr), 0.99e-3) << r.err;
  const std::string summary = readAll(out / "summary.json");
  EXPECT_TRUE(contains(summary, "\"stopped\": {\"cause\": \"error\", \"message\": \"")) << summary;
  EXPECT_TRUE(contains(summary, "min_step")) << summary;
  EXPECT_TRUE(contains(r.err, "partial results up to")) << r.err;
  EXPECT_TRUE(fs::exists(out / "wire.csv"));
}

// SIGINT (Ctrl-C) and SIGTERM stop a run after its current step: exit
// 128 + signal, a message saying so, and the results of the state it
// reached, marked "stopped" with the signal (an earlier run's complete
// summary is replaced, so nothing looks finished). Without a handler the
// process would die of the signal instead of exiting.
TEST_F(WireSimCli, StoppedRunWritesItsPartialResults) {
  const fs::path out = dir_ / "out";
  const std::string scene = write("quiet.yaml", kQuietScene);
  for (const int sig : {SIGINT, SIGTERM}) {
    ASSERT_EQ(runSmall(out.string()).status, 0);
    ASSERT_TRUE(fs::exists(out / "summary.json"));
    // A run of 1000 s of simulated time: far longer than this test.
    const fs::path err = dir_ / "stopped_stderr.txt";
    std::vector<std::string> args{"run", "--scene", scene};
    args.insert(args.end(), kSmallRun.begin(), kSmallRun.end());
    for (const std::string& a : {std::string("--set"), std::string("process.duration=1000"),
                                 std::string("--out"), out.string()}) {
      args.push_back(a);
    }
    const pid_t pid = spawn(args, err);
    ASSERT_GT(pid, 0);
    // Wait until it is running (it prints its size first); a guard, not a
    // timing assertion: it gives up after 10 minutes.
    bool started = false;
    for (int i = 0; i < 60000 && !started; ++i) {
      started = contains(readAll(err), " points, ");
      if (!started) usleep(10000);
    }
    EXPECT_TRUE(started) << readAll(err);
    ASSERT_EQ(kill(pid, sig), 0);
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    const std::string text = readAll(err);
    ASSERT_TRUE(WIFEXITED(status))
        << "signal " << sig << ": ended by a signal, not an exit; " << text;
    EXPECT_EQ(WEXITSTATUS(status), 128 + sig) << text;
    EXPECT_TRUE(contains(text, sig == SIGINT ? "stopped by SIGINT" : "stopped by SIGTERM")) << text;
    EXPECT_TRUE(contains(text, "the partial results are in")) << text;
    const std::string summary = readAll(out / "summary.json");
    EXPECT_TRUE(contains(summary, std::string("\"stopped\": {\"cause\": \"") +
                                      (sig == SIGINT ? "SIGINT" : "SIGTERM") + "\""))
        << summary;
    EXPECT_TRUE(contains(summary, "\"end_time_s\": 1000")) << summary;
    EXPECT_TRUE(fs::exists(out / "wire.csv"));
    EXPECT_FALSE(fs::exists(out / "wire.csv.partial"));
  }
}

// study removes an earlier study's results before it runs: a case that now
// fails leaves no summary of the earlier one. Every case fails at its first
// step here (a 0.1 ms step floor), so this runs in well under a second.
TEST_F(WireSimCli, StudyRemovesEarlierResultsFirst) {
  const fs::path out = dir_ / "study";
  for (const char* c : {"600rpm_30N", "600rpm_70N", "1200rpm_30N", "1200rpm_70N"}) {
    fs::create_directories(out / c);
    std::ofstream(out / c / "summary.json") << "{\"sim_time_s\": 0.175}\n";
  }
  std::ofstream(out / "study.csv") << "case,earlier\n";
  const RunResult r =
      run({"study", "--jobs", "1", "--out", out.string(), "--set", "solver.integrator=rkf45",
           "--set", "solver.min_step=1e-4", "--set", "solver.initial_step=1e-4"});
  EXPECT_EQ(r.status, 1) << r.err;
  for (const char* c : {"600rpm_30N", "600rpm_70N", "1200rpm_30N", "1200rpm_70N"}) {
    expectNoSummary(out / c, c);
  }
  // The new table has the header only: no case succeeded.
  const std::vector<std::string> lines = splitLines(readAll(out / "study.csv"));
  ASSERT_EQ(lines.size(), 1u) << readAll(out / "study.csv");
  EXPECT_TRUE(contains(lines[0], "bulging_height_mm")) << lines[0];
  EXPECT_TRUE(contains(readAll(out / "study.md"), "failed")) << readAll(out / "study.md");
}

// The stability study stopped with Ctrl-C in the middle of a run keeps its
// finished runs and a checkpoint of the unfinished one; the same command
// continues it, and every figure equals those of a study never stopped. A
// third call keeps every result; other inputs reuse none. --report
// shows the study in progress. Each run is a case of a sweep, a process of
// its own in runs/CASE.METHOD; the stop reaches it through the sweep. One case of 5 mm segments
// (about 9 s a study; the runs go in reverse registry order: bdf2, implicit_euler,
// symplectic_euler, then rkf45).
TEST_F(WireSimCli, StabilityStudyResumesWhereItWasStopped) {
  const std::vector<std::string> study{
      "stability", "--only", "segment_5mm_core_r5mm", "--jobs", "1", "--checkpoint", "0.05"};
  auto with_out = [&](const fs::path& out, std::vector<std::string> extra = {}) {
    std::vector<std::string> a = study;
    a.insert(a.end(), extra.begin(), extra.end());
    a.push_back("--out");
    a.push_back(out.string());
    return a;
  };
  // Every cell but the wall time.
  auto figures = [](const fs::path& csv) {
    std::vector<std::string> rows;
    for (const std::string& line : splitLines(readAll(csv))) {
      std::vector<std::string> cells = splitCsv(line);
      if (cells.size() > 11) cells[11].clear();
      std::string row;
      for (const std::string& c : cells) row += c + ",";
      rows.push_back(row);
    }
    return rows;
  };
  const fs::path straight = dir_ / "straight", resumed = dir_ / "resumed";
  const RunResult a = run(with_out(straight));
  ASSERT_EQ(a.status, 0) << a.err;
  const std::vector<std::string> expected = figures(straight / "stability.csv");
  ASSERT_EQ(expected.size(), 1u + cws::integrators().size()) << readAll(straight / "stability.csv");

  // Stopped once the unfinished run has a checkpoint.
  const fs::path err = dir_ / "stopped_stderr.txt";
  const pid_t pid = spawn(with_out(resumed), err);
  ASSERT_GT(pid, 0);
  const fs::path checkpoint = resumed / "runs" / "segment_5mm_core_r5mm.rkf45" / "checkpoint";
  // (A guard, not a timing assertion: it gives up after 10 minutes.)
  for (int i = 0; i < 60000 && !fs::exists(checkpoint); ++i) usleep(10000);
  ASSERT_TRUE(fs::exists(checkpoint)) << readAll(err);
  ASSERT_EQ(kill(pid, SIGINT), 0);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << readAll(err);
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGINT) << readAll(err);
  EXPECT_TRUE(contains(readAll(err), "the same command continues the study")) << readAll(err);
  EXPECT_FALSE(fs::exists(resumed / "stability.csv"));
  EXPECT_TRUE(fs::exists(checkpoint));
  EXPECT_TRUE(fs::exists(resumed / "runs" / "segment_5mm_core_r5mm.implicit_euler" / "result.txt"));

  // --report: the tables of the study so far, nothing run (exit 1: a run is
  // pending).
  const RunResult report = run(with_out(resumed, {"--report"}));
  EXPECT_EQ(report.status, 1) << report.err;
  const std::string table = readAll(resumed / "stability.csv");
  EXPECT_TRUE(contains(table, "rkf45,PENDING")) << table;
  EXPECT_TRUE(contains(table, "not finished: checkpoint at t = ")) << table;
  EXPECT_TRUE(contains(table, "symplectic_euler,stable")) << table;
  EXPECT_TRUE(contains(table, "bdf2,stable")) << table;
  EXPECT_TRUE(contains(table, "implicit_euler,stable")) << table;
  EXPECT_TRUE(fs::exists(checkpoint));

  // Continued: the same figures as the study never stopped.
  const RunResult b = run(with_out(resumed));
  ASSERT_EQ(b.status, 0) << b.err;
  const std::string methods = std::to_string(cws::integrators().size());
  const std::string others = std::to_string(cws::integrators().size() - 1);
  EXPECT_TRUE(contains(b.err, others + " kept from an earlier sweep, 1 to run")) << b.err;
  const std::string rkf45_log =
      readAll(resumed / "runs" / "segment_5mm_core_r5mm.rkf45" / "log.txt");
  EXPECT_TRUE(contains(rkf45_log, "segment_5mm_core_r5mm.rkf45: resumed at t = ")) << rkf45_log;
  EXPECT_EQ(figures(resumed / "stability.csv"), expected);
  EXPECT_FALSE(fs::exists(checkpoint)) << "a finished run keeps no checkpoint";

  // Again: every method's run kept, the same table.
  const RunResult c = run(with_out(resumed));
  ASSERT_EQ(c.status, 0) << c.err;
  EXPECT_TRUE(contains(c.err, methods + " kept from an earlier sweep, 0 to run")) << c.err;
  EXPECT_EQ(figures(resumed / "stability.csv"), expected);
  EXPECT_TRUE(contains(readAll(resumed / "STABILITY.md"), "kept " + methods + " results")) << c.err;

  // Another input (the tension), or --fresh: nothing kept. (A short budget
  // keeps this quick: the runs end as BUDGET, exit 1.)
  for (const std::vector<std::string>& extra :
       {std::vector<std::string>{"--set", "process.tension=31", "--budget", "0.2"},
        std::vector<std::string>{"--fresh", "--budget", "0.2"}}) {
    const RunResult d = run(with_out(resumed, extra));
    EXPECT_EQ(d.status, 1) << d.err;
    EXPECT_TRUE(contains(d.err, "0 kept from an earlier sweep")) << d.err;
    EXPECT_TRUE(contains(d.err, "BUDGET")) << d.err;
  }
}

}  // namespace

#endif  // CWS_WIRE_SIM_EXE
