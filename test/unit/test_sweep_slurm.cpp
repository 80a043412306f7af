// Sweeps on Slurm and the kinds of plan (src/tools/sweep_slurm.cpp,
// study.cpp, stability.cpp): the job-array scripts, their blocks below
// MaxArraySize, kept cases left out, Slurm's options checked, and the study
// and the stability matrix as plans. A real submission is tested against a
// one-node Slurm in test/slurm/test_slurm_sweep.cpp.
#ifdef CWS_WIRE_SIM_EXE

#include <gtest/gtest.h>

#include "cli_test_support.hpp"
#include "stability.hpp"
#include "study.hpp"
#include "sweep.hpp"
#include "sweep_slurm.hpp"

namespace {

using namespace cli_test;
using cws_tools::SlurmOptions;
using cws_tools::SweepError;
using cws_tools::SweepPlan;

// The package's default scene: the paper's winding case.
const std::string kDefaultScene = std::string(CWS_SOURCE_DIR) + "/config/scenes/default.yaml";

TEST(SweepSlurm, ArrayListsCompressRuns) {
  EXPECT_EQ(cws_tools::arrayList({0, 1, 2, 3, 4, 7, 9, 10, 11, 12}), "0-4,7,9-12");
  EXPECT_EQ(cws_tools::arrayList({5}), "5");
  EXPECT_EQ(cws_tools::arrayList({2, 4}), "2,4");
}

TEST(SweepSlurm, ArrayScriptRunsOneCasePerTask) {
  SlurmOptions o;
  o.partition = "short";
  o.account = "lab42";
  o.time_limit = "0-01:30:00";
  o.memory = "2G";
  o.max_running = 8;
  const std::string s =
      cws_tools::slurmArrayScript(o, "/opt/ws/wire_sim", "/shared/sweep dir", 1000, "0-4,7");
  EXPECT_EQ(s.rfind("#!/bin/bash\n", 0), 0u) << s;
  for (const char* line :
       {"#SBATCH --partition=short\n", "#SBATCH --account=lab42\n", "#SBATCH --array=0-4,7%8\n",
        "#SBATCH --time=0-01:30:00\n", "#SBATCH --mem=2G\n", "#SBATCH --cpus-per-task=1\n",
        "#SBATCH --output=/shared/sweep dir/slurm/logs/case_%A_%a.log\n",
        // The case is the block's first plus the task's index; paths quoted.
        "exec \"/opt/ws/wire_sim\" sweep-run \"/shared/sweep dir\" \"$((1000 + "
        "SLURM_ARRAY_TASK_ID))\"\n"}) {
    EXPECT_TRUE(contains(s, line)) << line << " not in\n" << s;
  }
  // Without options, Slurm's defaults: no partition, time or memory lines.
  const std::string d = cws_tools::slurmArrayScript(SlurmOptions(), "/w", "/d", 0, "0-1");
  EXPECT_FALSE(contains(d, "--partition") || contains(d, "--time") || contains(d, "--mem") ||
               !contains(d, "#SBATCH --array=0-1\n"))
      << d;
  const std::string g = cws_tools::slurmGatherScript(o, "/opt/ws/wire_sim", "/shared/d");
  EXPECT_TRUE(contains(g, "exec \"/opt/ws/wire_sim\" sweep-gather \"/shared/d\"\n")) << g;
  EXPECT_TRUE(contains(g, "#SBATCH --partition=short\n")) << g;
}

TEST(SweepSlurm, OptionsSlurmWouldRefuseAreNamed) {
  const std::vector<std::pair<std::string, std::string>> bad{
      {"--time", "1h"},       {"--time", "90 min"},   {"--mem", "2GB"},
      {"--mem", "-1"},        {"--partition", "a b"}, {"--account", "x;rm"},
      {"--max-running", "0"}, {"--max-running", "x"}, {"--max-array-size", "1"}};
  for (const auto& [opt, value] : bad) {
    SlurmOptions o;
    const std::string problem = cws_tools::setSlurmOption(o, opt, value);
    EXPECT_TRUE(contains(problem, opt) && contains(problem, value))
        << opt << " " << value << ": '" << problem << "'";
  }
  SlurmOptions o;
  EXPECT_EQ(cws_tools::setSlurmOption(o, "--time", "2-00:00:00"), "");
  EXPECT_EQ(cws_tools::setSlurmOption(o, "--time", "90"), "");
  EXPECT_EQ(cws_tools::setSlurmOption(o, "--mem", "500M"), "");
  EXPECT_EQ(cws_tools::setSlurmOption(o, "--max-array-size", "40001"), "");
  EXPECT_EQ(o.max_array_size, 40001);
}

TEST(SweepPlanKinds, KindNamesAndOptionsSurviveThePlanFile) {
  SweepPlan p = cws_tools::studyPlan(kDefaultScene, {"wire.segment_length=2e-3"});
  p.options = {{"budget_s", "12.5"}};
  const SweepPlan q = cws_tools::parsePlanText(cws_tools::planText(p), "plan");
  EXPECT_EQ(q.kind, "study");
  EXPECT_EQ(q.names, p.names);
  EXPECT_EQ(q.cases, p.cases);
  EXPECT_EQ(q.option("budget_s", ""), "12.5");
  EXPECT_EQ(q.caseDir(3), "1200rpm_70N");
  EXPECT_THROW(cws_tools::parsePlanText("kind\tsweeps\nscene\t\nkeys\ta\n", "plan"), SweepError);
}

TEST(SweepPlanKinds, StudyIsThePapersFourCases) {
  const SweepPlan p = cws_tools::studyPlan(kDefaultScene, {});
  ASSERT_EQ(p.cases.size(), 4u);
  EXPECT_EQ(p.keys, (std::vector<std::string>{"process.core_speed_rpm", "process.tension"}));
  EXPECT_EQ(p.cases[1], (std::vector<std::string>{"600", "70"}));
  EXPECT_EQ(p.names[1], "600rpm_70N");
  // 1 3/4 turns, the duration from the turns.
  const std::vector<std::string> o = p.caseOverrides(2);
  EXPECT_NE(std::find(o.begin(), o.end(), "process.turns=1.75"), o.end());
  EXPECT_EQ(o.back(), "process.tension=30");
  // A scene that does not wind is refused, naming why.
  try {
    cws_tools::studyPlan(kDefaultScene, {"physics.supply=false"});
    ADD_FAILURE() << "no error";
  } catch (const cws::SceneError& e) {
    EXPECT_TRUE(contains(e.what(), "winding scene")) << e.what();
  }
}

TEST(SweepPlanKinds, StabilityMatrixRunsTheLastCaseFirst) {
  cws_tools::StabilityOptions o;
  o.only = "segment_5mm_core_r5mm";
  const SweepPlan p = cws_tools::stabilityPlan("", {}, o);
  ASSERT_EQ(p.cases.size(), cws::integrators().size());
  EXPECT_EQ(p.cases.front()[1], cws::integrators().back().name);
  EXPECT_EQ(p.names.front(), "runs/" + p.cases.front()[0] + "." + p.cases.front()[1]);
  // Identities differ between methods and are stable.
  EXPECT_NE(cws_tools::stabilityCaseIdentity(p, 0), cws_tools::stabilityCaseIdentity(p, 1));
  EXPECT_EQ(cws_tools::stabilityCaseIdentity(p, 0), cws_tools::stabilityCaseIdentity(p, 0));
  o.only = "no_such_case";
  EXPECT_THROW(cws_tools::stabilityPlan("", {}, o), SweepError);
}

class WireSimSlurmScripts : public WireSimCli {};

// A dry run writes the scripts and submits nothing (no sbatch is needed):
// blocks of max-array-size - 1 cases, indices counted from each block's
// first case, and cases kept from an earlier sweep left out.
TEST_F(WireSimSlurmScripts, DryRunSplitsBlocksAndLeavesKeptCasesOut) {
  const fs::path out = dir_ / "sweep";
  const std::vector<std::string> base{
      "sweep", "--set",     "process.turns=0.02", "--set", "solver.integrator=bdf2",
      "--out", out.string()};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> a = base;
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  };
  // Cases 0 and 1 run here first and are kept.
  const RunResult local = run(with({"--grid", "process.tension=20:21:2"}));
  ASSERT_EQ(local.status, 0) << local.err;
  const RunResult dry = run(with({"--grid", "process.tension=20:44:25", "--slurm", "--dry-run",
                                  "--max-array-size", "11", "--max-running", "3"}));
  ASSERT_EQ(dry.status, 0) << dry.err;
  EXPECT_TRUE(contains(dry.err, "2 kept from an earlier sweep, 23 to run on Slurm")) << dry.err;
  const std::string b0 = readAll(out / "slurm" / "cases_0.sbatch");
  const std::string b10 = readAll(out / "slurm" / "cases_10.sbatch");
  const std::string b20 = readAll(out / "slurm" / "cases_20.sbatch");
  EXPECT_TRUE(contains(b0, "#SBATCH --array=2-9%3\n")) << b0;
  EXPECT_TRUE(contains(b10, "#SBATCH --array=0-9%3\n")) << b10;
  EXPECT_TRUE(contains(b20, "#SBATCH --array=0-4%3\n")) << b20;
  EXPECT_TRUE(contains(b20, "$((20 + SLURM_ARRAY_TASK_ID))")) << b20;
  EXPECT_TRUE(fs::exists(out / "slurm" / "gather.sbatch"));
  EXPECT_FALSE(fs::exists(out / "slurm" / "jobs.txt"));
  // The kept cases' results are untouched, the others not run.
  EXPECT_TRUE(contains(readAll(out / "case_0001" / "status.txt"), "status ok"));
  EXPECT_FALSE(fs::exists(out / "case_0002" / "status.txt"));
}

TEST_F(WireSimSlurmScripts, SlurmOptionsNeedSlurmAndExcludeJobs) {
  const fs::path out = dir_ / "sweep";
  const RunResult a =
      run({"sweep", "--grid", "process.tension=20,30", "--time", "10", "--out", out.string()});
  EXPECT_EQ(a.status, 2);
  EXPECT_TRUE(contains(a.err, "--time is an option of --slurm")) << a.err;
  const RunResult b = run({"sweep", "--grid", "process.tension=20,30", "--slurm", "--jobs", "2",
                           "--out", out.string()});
  EXPECT_EQ(b.status, 2);
  EXPECT_TRUE(contains(b.err, "--max-running")) << b.err;
  const RunResult c = run({"sweep", "--grid", "process.tension=20,30", "--slurm", "--mem", "2GB",
                           "--out", out.string()});
  EXPECT_EQ(c.status, 2);
  EXPECT_TRUE(contains(c.err, "--mem '2GB'")) << c.err;
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace

#endif  // CWS_WIRE_SIM_EXE
