// Parameter sweeps (wire_sim sweep, src/tools/sweep*.cpp): grids and cases
// files, bad keys refused before anything runs, a failed case as a row,
// resuming, and the table against runs of the same cases made by hand.
#ifdef CWS_WIRE_SIM_EXE

#include <gtest/gtest.h>

#include <cmath>

#include "cli_test_support.hpp"
#include "coil_winding_sim/core/base/text_format.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"
#include "sweep.hpp"
#include "sweep_plan.hpp"

namespace {

using namespace cli_test;
using cws_tools::GridAxis;
using cws_tools::parseGridAxis;
using cws_tools::SweepError;
using cws_tools::SweepPlan;

// ---------------------------------------------------------------------------
// Grids and cases files.

TEST(SweepGrid, RangeHasBothEndsAndEvenSpacing) {
  const GridAxis a = parseGridAxis("process.tension=20:80:7");
  EXPECT_EQ(a.key, "process.tension");
  ASSERT_EQ(a.values.size(), 7u);
  for (int i = 0; i < 7; ++i) EXPECT_DOUBLE_EQ(std::stod(a.values[i]), 20.0 + 10.0 * i);
  // A range that does not divide evenly still ends on its end, exactly.
  const GridAxis b = parseGridAxis("wire.bend.yield_curvature=0.1:0.3:4");
  ASSERT_EQ(b.values.size(), 4u);
  EXPECT_EQ(b.values.back(), "0.3");
  EXPECT_NEAR(std::stod(b.values[1]), 0.1 + 0.2 / 3.0, 1e-12);
}

TEST(SweepGrid, ListsAndSingleValues) {
  const GridAxis a = parseGridAxis("process.core_speed_rpm=600,900, 1200 ,1500");
  EXPECT_EQ(a.values, (std::vector<std::string>{"600", "900", "1200", "1500"}));
  EXPECT_EQ(parseGridAxis("solver.integrator=bdf2").values, std::vector<std::string>{"bdf2"});
  EXPECT_EQ(parseGridAxis("process.tension=30:30:1").values, std::vector<std::string>{"30"});
}

TEST(SweepGrid, MalformedAxesNameTheirFault) {
  auto fault = [](const std::string& arg) {
    try {
      parseGridAxis(arg);
    } catch (const SweepError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_TRUE(contains(fault("process.tension"), "KEY=VALUES"));
  EXPECT_TRUE(contains(fault("=1,2"), "no key"));
  EXPECT_TRUE(contains(fault("process.tension="), "no values"));
  EXPECT_TRUE(contains(fault("process.tension=1:2"), "FROM:TO:COUNT"));
  EXPECT_TRUE(contains(fault("process.tension=a:2:3"), "start 'a'"));
  EXPECT_TRUE(contains(fault("process.tension=1:2:0"), "COUNT '0'"));
  EXPECT_TRUE(contains(fault("process.tension=1:2:2.5"), "COUNT '2.5'"));
  EXPECT_TRUE(contains(fault("process.tension=1:2:1"), "ambiguous"));
  EXPECT_TRUE(contains(fault("process.tension=1,,2"), "empty value"));
}

TEST(SweepGrid, ProductRunsTheLastAxisFastest) {
  const SweepPlan p = cws_tools::gridPlan(
      "", {"process.turns=1"},
      {parseGridAxis("process.tension=20,70"), parseGridAxis("process.core_speed_rpm=600:1800:3")});
  ASSERT_EQ(p.cases.size(), 6u);
  EXPECT_EQ(p.cases[0], (std::vector<std::string>{"20", "600"}));
  EXPECT_EQ(p.cases[2], (std::vector<std::string>{"20", "1800"}));
  EXPECT_EQ(p.cases[3], (std::vector<std::string>{"70", "600"}));
  EXPECT_EQ(p.caseOverrides(4), (std::vector<std::string>{"process.turns=1", "process.tension=70",
                                                          "process.core_speed_rpm=1200"}));
  EXPECT_EQ(SweepPlan().caseDir(4), "case_0004");
  EXPECT_THROW(
      cws_tools::gridPlan(
          "", {}, {parseGridAxis("process.tension=1,2"), parseGridAxis("process.tension=3")}),
      SweepError);
}

TEST(SweepGrid, CasesFileRowsWithQuotedValues) {
  const SweepPlan p = cws_tools::casesPlan("", {},
                                           "# two cases\n"
                                           "process.tension, end.load\n"
                                           "20, \"[{time: 0, force: [0, 1, 0]}]\"\n"
                                           "\n"
                                           "70, []\n",
                                           "cases.csv");
  EXPECT_EQ(p.keys, (std::vector<std::string>{"process.tension", "end.load"}));
  ASSERT_EQ(p.cases.size(), 2u);
  EXPECT_EQ(p.cases[0][1], "[{time: 0, force: [0, 1, 0]}]");
  try {
    cws_tools::casesPlan("", {}, "process.tension,process.turns\n20,1\n30\n", "cases.csv");
    ADD_FAILURE() << "a short row was accepted";
  } catch (const SweepError& e) {
    EXPECT_TRUE(contains(e.what(), "cases.csv line 3: 1 values for 2 keys")) << e.what();
  }
  EXPECT_THROW(cws_tools::casesPlan("", {}, "\n# nothing\n", "cases.csv"), SweepError);
}

TEST(SweepGrid, BadKeysAndValuesAreNamedBeforeAnythingRuns) {
  const SweepPlan bad_key = cws_tools::gridPlan("", {}, {parseGridAxis("process.tensio=20,30")});
  try {
    cws_tools::checkPlan(bad_key);
    ADD_FAILURE() << "an unknown key was accepted";
  } catch (const cws::SceneError& e) {
    EXPECT_EQ(e.key(), "process.tensio");
    EXPECT_TRUE(contains(e.what(), "sweep case 0")) << e.what();
  }
  const SweepPlan bad_value = cws_tools::gridPlan("", {}, {parseGridAxis("process.tension=30,-5")});
  try {
    cws_tools::checkPlan(bad_value);
    ADD_FAILURE() << "a negative tension was accepted";
  } catch (const cws::SceneError& e) {
    EXPECT_EQ(e.key(), "process.tension");
    EXPECT_TRUE(contains(e.what(), "sweep case 1: process.tension=-5")) << e.what();
  }
  EXPECT_THROW(cws_tools::checkPlan(cws_tools::gridPlan("", {}, {})), SweepError);
}

// The tables' text: a CSV field is quoted (RFC 4180) when it holds a comma,
// a quote or a line break; a Markdown cell escapes its bars and keeps its
// row on one line (an error message may hold either).
TEST(SweepTables, CsvFieldsAndMarkdownCellsKeepTheirText) {
  EXPECT_EQ(cws::csvField("plain"), "plain");
  EXPECT_EQ(cws::csvField("a,b"), "\"a,b\"");
  EXPECT_EQ(cws::csvField("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(cws::csvField("two\nlines"), "\"two\nlines\"");
  EXPECT_EQ(cws::markdownCell("plain"), "plain");
  EXPECT_EQ(cws::markdownCell("a | b\nc\r\n"), "a \\| b c  ");
}

TEST(SweepGrid, PlanTextRoundTrip) {
  SweepPlan p = cws_tools::casesPlan("/a/scene.yaml", {"process.turns=0.5", "x.y=[1, 2]"},
                                     "process.tension,end.load\n20,\"[{time: 0}]\"\n", "c.csv");
  const SweepPlan q = cws_tools::parsePlanText(cws_tools::planText(p), "plan");
  EXPECT_EQ(q.scene, p.scene);
  EXPECT_EQ(q.overrides, p.overrides);
  EXPECT_EQ(q.keys, p.keys);
  EXPECT_EQ(q.cases, p.cases);
  EXPECT_THROW(cws_tools::parsePlanText("scene\tx\nkeys\ta\ncase\t1\t2\n", "plan"), SweepError);
}

// ---------------------------------------------------------------------------
// Sweeps through the tool.

// The small quiet wire of the CLI tests, and an end load that makes rkf45
// need steps below solver.min_step: that case fails, the other runs.
const char* kLoads =
    "end.load\n"
    "\"[{time: 0}]\"\n"
    "\"[{time: 0}, {time: 1e-4}, {time: 1.001e-4, force: [0, 1e3, 0]}]\"\n";

class WireSimSweep : public WireSimCli {
 protected:
  RunResult sweep(const std::vector<std::string>& extra) {
    std::vector<std::string> args{"sweep", "--scene", write("quiet.yaml", kQuietScene)};
    args.insert(args.end(), kSmallRun.begin(), kSmallRun.end());
    args.insert(args.end(), extra.begin(), extra.end());
    return run(args);
  }
  static std::vector<std::vector<std::string>> table(const fs::path& csv) {
    std::vector<std::vector<std::string>> rows;
    for (const std::string& line : splitLines(readAll(csv))) {
      std::vector<std::string> f(1);
      bool quoted = false;
      for (char c : line) {
        if (c == '"') {
          quoted = !quoted;
        } else if (c == ',' && !quoted) {
          f.emplace_back();
        } else {
          f.back() += c;
        }
      }
      rows.push_back(f);
    }
    return rows;
  }
  static std::string column(const std::vector<std::vector<std::string>>& t, std::size_t row,
                            const std::string& name) {
    for (std::size_t c = 0; c < t[0].size(); ++c) {
      if (t[0][c] == name) return c < t[row].size() ? t[row][c] : "";
    }
    return "<no column " + name + ">";
  }
};

// Each case's row holds what a run of the same keys by hand gives.
TEST_F(WireSimSweep, TableRowsMatchRunsByHand) {
  const fs::path out = dir_ / "sweep";
  const RunResult r =
      sweep({"--set", "solver.integrator=rkf45", "--grid", "solver.rtol=1e-4,1e-6", "--grid",
             "wire.length=0.01:0.014:2", "--out", out.string(), "--jobs", "2"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "4 cases")) << r.err;
  const auto t = table(out / "results.csv");
  ASSERT_EQ(t.size(), 5u);
  for (std::size_t row = 1; row <= 4; ++row) {
    EXPECT_EQ(column(t, row, "status"), "ok");
    const fs::path by_hand = dir_ / ("by_hand_" + std::to_string(row));
    const RunResult h =
        runSmall(by_hand.string(), {"--set", "solver.integrator=rkf45", "--set",
                                    "solver.rtol=" + column(t, row, "solver.rtol"), "--set",
                                    "wire.length=" + column(t, row, "wire.length")});
    ASSERT_EQ(h.status, 0) << h.err;
    const std::string summary = readAll(by_hand / "summary.json");
    EXPECT_EQ(std::stod(column(t, row, "steps_accepted")), jsonNumber(summary, "steps_accepted"));
    EXPECT_EQ(std::stod(column(t, row, "nodes")), jsonNumber(summary, "nodes"));
    // (The table keeps 10 significant digits of the summary's 12.)
    const double kinetic_J = jsonNumber(summary, "kinetic_energy_J");
    EXPECT_NEAR(std::stod(column(t, row, "kinetic_energy_J")), kinetic_J,
                1e-9 * std::abs(kinetic_J));
  }
  // The grid's cases differ: 6 and 8 nodes (0.01 and 0.014 m in 2 mm segments).
  EXPECT_EQ(column(t, 1, "nodes"), "6");
  EXPECT_EQ(column(t, 2, "nodes"), "8");
  EXPECT_EQ(column(t, 3, "solver.rtol"), "1e-6");
}

// A failing case is a row with its error; a second sweep keeps the case
// that ran and runs the failed one again; a case without a result is named
// by the gather step.
TEST_F(WireSimSweep, FailedCaseIsARowAndKeptCasesAreReused) {
  const fs::path out = dir_ / "sweep";
  const std::vector<std::string> args{
      "--set",   "solver.integrator=rkf45",  "--set", "process.duration=4e-4",
      "--set",   "solver.min_step=1e-8",     "--set", "solver.initial_step=1e-6",
      "--cases", write("loads.csv", kLoads), "--out", out.string()};
  const RunResult first = sweep(args);
  EXPECT_EQ(first.status, 1) << first.err;
  auto t = table(out / "results.csv");
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(column(t, 1, "status"), "ok");
  EXPECT_EQ(column(t, 2, "status"), "failed");
  EXPECT_TRUE(contains(column(t, 2, "error"), "min_step")) << column(t, 2, "error");
  EXPECT_TRUE(contains(readAll(out / "results.md"), "| failed: ")) << readAll(out / "results.md");
  const auto written = fs::last_write_time(out / "case_0000" / "summary.json");

  const RunResult second = sweep(args);
  EXPECT_EQ(second.status, 1) << second.err;
  EXPECT_TRUE(contains(second.err, "1 kept from an earlier sweep, 1 to run")) << second.err;
  EXPECT_EQ(fs::last_write_time(out / "case_0000" / "summary.json"), written);

  // A changed scene is not the kept case: both run again.
  std::vector<std::string> changed = args;
  changed[3] = "process.duration=5e-4";
  const RunResult third = sweep(changed);
  EXPECT_TRUE(contains(third.err, "0 kept from an earlier sweep, 2 to run")) << third.err;

  // A case whose status is gone (a task that never ran) is pending.
  fs::remove(out / "case_0000" / "status.txt");
  const RunResult gather = run({"sweep-gather", out.string()});
  EXPECT_EQ(gather.status, 1);
  EXPECT_TRUE(contains(gather.err, "not finished: case_0000")) << gather.err;
  t = table(out / "results.csv");
  EXPECT_EQ(column(t, 1, "status"), "pending");
}

// A case that runs out of its wall-time budget is a row marked budget with
// the figures of the part it ran; the same budget keeps it, a larger one
// runs it again. (The long case: 20 s of the quiet wire at the explicit
// method's step, some 10^8 steps: far beyond 0.3 s of wall time.)
TEST_F(WireSimSweep, ACaseOutOfBudgetIsARowWithWhatItRan) {
  const fs::path out = dir_ / "sweep";
  const std::vector<std::string> args{"--set",    "solver.integrator=symplectic_euler",
                                      "--grid",   "process.duration=2e-4,20",
                                      "--budget", "0.3",
                                      "--out",    out.string()};
  const RunResult first = sweep(args);
  EXPECT_EQ(first.status, 1) << first.err;
  auto t = table(out / "results.csv");
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(column(t, 1, "status"), "ok");
  EXPECT_EQ(column(t, 2, "status"), "budget");
  EXPECT_TRUE(contains(column(t, 2, "error"), "budget of 0.3 s")) << column(t, 2, "error");
  const double reached_s = std::stod(column(t, 2, "sim_time_s"));
  EXPECT_GT(reached_s, 0.0);
  EXPECT_LT(reached_s, 20.0);
  EXPECT_GT(std::stod(column(t, 2, "steps_accepted")), 0.0);
  EXPECT_TRUE(contains(readAll(out / "results.md"), "| budget: ")) << readAll(out / "results.md");

  const RunResult again = sweep(args);
  EXPECT_TRUE(contains(again.err, "2 kept from an earlier sweep, 0 to run")) << again.err;
  std::vector<std::string> larger = args;
  larger[5] = "0.4";
  const RunResult third = sweep(larger);
  EXPECT_TRUE(contains(third.err, "1 kept from an earlier sweep, 1 to run")) << third.err;
  const RunResult bad = sweep({"--grid", "process.tension=1", "--budget", "-1"});
  EXPECT_EQ(bad.status, 2);
  EXPECT_TRUE(contains(bad.err, "--budget needs a positive number")) << bad.err;
}

TEST_F(WireSimSweep, BadKeyStopsTheSweepBeforeAnyCase) {
  const fs::path out = dir_ / "sweep";
  const RunResult r = sweep({"--grid", "process.tension=20,30", "--grid", "wire.lenght=0.01,0.02",
                             "--out", out.string()});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.err, "wire.lenght")) << r.err;
  EXPECT_FALSE(fs::exists(out));
  const RunResult none = sweep({"--out", out.string()});
  EXPECT_EQ(none.status, 2);
  EXPECT_TRUE(contains(none.err, "no cases")) << none.err;
  const RunResult both = sweep({"--grid", "process.tension=1", "--cases", "x.csv"});
  EXPECT_EQ(both.status, 2);
  EXPECT_TRUE(contains(both.err, "exclude each other")) << both.err;
}

}  // namespace

#endif  // CWS_WIRE_SIM_EXE
