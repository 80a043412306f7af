// Tests of the wire_sim command-line tool: exit codes, messages and outputs.
//
// The tool's path comes from the compile definition CWS_WIRE_SIM_EXE (a
// string literal); without it this file compiles to nothing. Every run uses
// its own scene file and --set values for what is asserted, so the package's
// default scene (config/scenes/default.yaml) cannot change the outcome.
#ifdef CWS_WIRE_SIM_EXE

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "coil_winding_sim/core/scene.hpp"
#include "temp_dir_test.hpp"

namespace {

namespace fs = std::filesystem;

std::string shellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'') {
      q += "'\\''";
    } else {
      q += c;
    }
  }
  return q + "'";
}

std::string readAll(const fs::path& p) {
  std::ifstream f(p);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

struct RunResult {
  int status = -1;  // exit status, or -1 if the tool did not exit normally
  std::string out;
  std::string err;
};

// A line-oriented scene for a short, quiet run: nothing acts on the wire.
const char* kQuietScene =
    "physics:\n"
    "  gravity: false\n"
    "  damping: false\n"
    "end:\n"
    "  load:\n"
    "    - {time: 0.0, force: [0, 0, 0], moment: [0, 0, 0]}\n";

// Small wire: 0.01 m in segments of 2 mm is 5 segments, 6 nodes.
const std::vector<std::string> kSmallRun{"--set", "wire.length=0.01",
                                         "--set", "wire.segment_length=0.002",
                                         "--set", "process.duration=2e-4"};

class WireSimCli : public cws_test::TempDirTest {
 protected:
  void SetUp() override {
    cws_test::TempDirTest::SetUp();
    ASSERT_TRUE(fs::exists(CWS_WIRE_SIM_EXE)) << "wire_sim not found at " << CWS_WIRE_SIM_EXE;
  }

  // Runs wire_sim with `args`, stdout and stderr captured to files in dir_.
  RunResult run(const std::vector<std::string>& args) {
    const fs::path out = dir_ / "stdout.txt";
    const fs::path err = dir_ / "stderr.txt";
    std::string cmd = shellQuote(CWS_WIRE_SIM_EXE);
    for (const std::string& a : args) cmd += " " + shellQuote(a);
    cmd += " </dev/null >" + shellQuote(out.string()) + " 2>" + shellQuote(err.string());
    const int raw = std::system(cmd.c_str());
    RunResult r;
    if (raw != -1 && WIFEXITED(raw)) r.status = WEXITSTATUS(raw);
    r.out = readAll(out);
    r.err = readAll(err);
    return r;
  }

  // run --scene <quiet scene> <small run> <extra> --out <out>
  RunResult runSmall(const std::string& out, const std::vector<std::string>& extra = {}) {
    std::vector<std::string> args{"run", "--scene", write("quiet.yaml", kQuietScene)};
    args.insert(args.end(), kSmallRun.begin(), kSmallRun.end());
    args.insert(args.end(), extra.begin(), extra.end());
    args.push_back("--out");
    args.push_back(out);
    return run(args);
  }
};

bool contains(const std::string& text, const std::string& what) {
  return text.find(what) != std::string::npos;
}

// The number after "key": in a flat JSON object (NaN if absent or null).
double jsonNumber(const std::string& json, const std::string& key) {
  const std::string tag = "\"" + key + "\":";
  const std::size_t at = json.find(tag);
  if (at == std::string::npos) return std::nan("");
  const char* begin = json.c_str() + at + tag.size();
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  return end == begin ? std::nan("") : v;
}

std::vector<std::string> splitLines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream s(text);
  for (std::string line; std::getline(s, line);) lines.push_back(line);
  return lines;
}

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> cells;
  std::istringstream s(line);
  for (std::string cell; std::getline(s, cell, ',');) cells.push_back(cell);
  return cells;
}

// ---------------------------------------------------------------------------
TEST_F(WireSimCli, UnknownCommandIsUsageError) {
  const RunResult r = run({"frobnicate"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.err, "frobnicate")) << r.err;
  EXPECT_TRUE(contains(r.err, "usage")) << r.err;
}

TEST_F(WireSimCli, NoArgumentsIsUsageError) {
  const RunResult r = run({});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.out + r.err, "usage")) << r.out << r.err;
}

TEST_F(WireSimCli, UnknownOptionIsUsageError) {
  const RunResult r = run({"run", "--bogus-option", "--out", (dir_ / "out").string()});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.err, "--bogus-option")) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "out" / "summary.json"));
  // --out belongs to `run` only.
  const RunResult p = run({"print-scene", "--out", (dir_ / "out").string()});
  EXPECT_EQ(p.status, 2);
  EXPECT_TRUE(contains(p.err, "--out")) << p.err;
}

TEST_F(WireSimCli, OptionWithoutValueIsUsageError) {
  const RunResult r = run({"run", "--set"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.err, "--set")) << r.err;
  const RunResult s = run({"print-scene", "--scene"});
  EXPECT_EQ(s.status, 2);
  EXPECT_TRUE(contains(s.err, "--scene")) << s.err;
}

TEST_F(WireSimCli, BadSceneKeyIsNamed) {
  const fs::path out = dir_ / "out";
  const RunResult r = runSmall(out.string(), {"--set", "wire.diamter=1e-3"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.err, "wire.diamter")) << r.err;
  EXPECT_FALSE(fs::exists(out / "summary.json"));
  // A bad value of a known key: the key is named too.
  const RunResult v = run({"print-scene", "--set", "wire.bend.plastic_rigidity=1"});
  EXPECT_EQ(v.status, 2);
  EXPECT_TRUE(contains(v.err, "wire.bend.plastic_rigidity")) << v.err;
  // A malformed override.
  const RunResult m = run({"print-scene", "--set", "process.tension"});
  EXPECT_EQ(m.status, 2);
  EXPECT_TRUE(contains(m.err, "process.tension")) << m.err;
}

TEST_F(WireSimCli, MissingSceneFileIsNamed) {
  const std::string missing = (dir_ / "no_such_scene.yaml").string();
  const RunResult r = run({"run", "--scene", missing, "--out", (dir_ / "out").string()});
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.status, -1);
  EXPECT_TRUE(contains(r.err, missing)) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "out" / "summary.json"));
}

TEST_F(WireSimCli, UnwritableOutputDirectoryFails) {
  const std::string plain = write("plain_file", "not a directory\n");
  const fs::path out = fs::path(plain) / "sub";
  const RunResult r = runSmall(out.string());
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.status, -1);
  EXPECT_TRUE(contains(r.err, out.string())) << r.err;
  EXPECT_FALSE(fs::exists(out / "summary.json"));
  EXPECT_EQ(readAll(plain), "not a directory\n");  // the file is untouched
  // --out naming the regular file itself.
  const RunResult f = runSmall(plain);
  EXPECT_NE(f.status, 0);
  EXPECT_NE(f.status, -1);
  EXPECT_TRUE(contains(f.err, plain)) << f.err;
  EXPECT_TRUE(fs::is_regular_file(plain));
}

TEST_F(WireSimCli, ShortRunWritesSummaryAndCsv) {
  const fs::path out = dir_ / "out";
  const RunResult r = runSmall(out.string());
  ASSERT_EQ(r.status, 0) << r.err;

  const std::string summary = readAll(out / "summary.json");
  ASSERT_FALSE(summary.empty());
  for (const char* key :
       {"sim_time_s", "wall_time_s", "real_time_factor", "steps_accepted", "steps_rejected",
        "nodes", "max_constraint_residual", "kinetic_energy_J", "elastic_energy_J",
        "dissipated_energy_J", "bulging_height_m", "max_axial_force_N"}) {
    EXPECT_TRUE(contains(summary, std::string("\"") + key + "\":")) << key << "\n" << summary;
  }
  EXPECT_EQ(summary.front(), '{');
  EXPECT_EQ(summary.find_last_not_of(" \n"), summary.rfind('}'));
  EXPECT_DOUBLE_EQ(jsonNumber(summary, "sim_time_s"), 2e-4);  // process.duration
  EXPECT_EQ(jsonNumber(summary, "nodes"), 6.0);               // 0.01 m / 2 mm + 1
  EXPECT_GE(jsonNumber(summary, "steps_accepted"), 1.0);
  EXPECT_GE(jsonNumber(summary, "steps_rejected"), 0.0);
  EXPECT_GE(jsonNumber(summary, "wall_time_s"), 0.0);
  // Nothing acts on a straight wire at rest: it stays at rest, unstrained.
  EXPECT_NEAR(jsonNumber(summary, "kinetic_energy_J"), 0.0, 1e-15);
  EXPECT_NEAR(jsonNumber(summary, "elastic_energy_J"), 0.0, 1e-15);
  EXPECT_NEAR(jsonNumber(summary, "max_axial_force_N"), 0.0, 1e-9);

  const std::vector<std::string> lines = splitLines(readAll(out / "wire.csv"));
  ASSERT_EQ(lines.size(), 7u);
  EXPECT_EQ(lines[0],
            "index,x,y,z,axial_force_N,curvature_1pm,plastic_curvature_1pm,twist_rad_per_m,"
            "in_contact,stick");
  for (int i = 0; i < 6; ++i) {
    const std::vector<std::string> cells = splitCsv(lines[i + 1]);
    ASSERT_EQ(cells.size(), 10u) << lines[i + 1];
    EXPECT_EQ(cells[0], std::to_string(i));
    // Clamped at the origin along +x, unloaded: node i stays at (2 mm i, 0, 0).
    EXPECT_NEAR(std::stod(cells[1]), 0.002 * i, 1e-12) << lines[i + 1];
    EXPECT_NEAR(std::stod(cells[2]), 0.0, 1e-12) << lines[i + 1];
    EXPECT_NEAR(std::stod(cells[3]), 0.0, 1e-12) << lines[i + 1];
  }
  // No temporary files are left behind.
  for (const auto& e : fs::directory_iterator(out)) {
    const std::string name = e.path().filename().string();
    EXPECT_TRUE(name == "summary.json" || name == "wire.csv") << "left behind: " << name;
  }
}

// A run that fails after an earlier success in the same directory must not
// leave the earlier summary.json to be mistaken for its own. The failure: a
// fixed step of 0.1 ms (200 times the axial stability limit of 2 mm segments,
// l / 2640 m/s = 0.76 us) under a 1 N end force cannot meet the tolerance, and
// min_step forbids a smaller step.
TEST_F(WireSimCli, FailedRunAfterSuccessLeavesNoSummary) {
  const fs::path out = dir_ / "out";
  ASSERT_EQ(runSmall(out.string()).status, 0);
  ASSERT_TRUE(fs::exists(out / "summary.json"));
  const RunResult r =
      runSmall(out.string(), {"--set", "end.load=[{time: 0, force: [0, 1, 0]}]", "--set",
                              "solver.min_step=1e-4", "--set", "solver.initial_step=1e-4"});
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_TRUE(contains(r.err, "min_step")) << r.err;
  EXPECT_FALSE(fs::exists(out / "summary.json"));
  EXPECT_FALSE(fs::exists(out / "summary.json.partial"));
}

TEST_F(WireSimCli, PrintSceneAppliesOverride) {
  const RunResult r = run({"print-scene", "--set", "process.tension=42"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "tension: 42")) << r.out;
  // The printed scene is a loadable scene with the override in it.
  const std::string path = write("printed.yaml", r.out);
  const cws::Scene s = cws::loadScene(path, {});
  EXPECT_EQ(s.process.tension, 42.0);
  // Later overrides win.
  const RunResult twice =
      run({"print-scene", "--set", "process.tension=42", "--set", "process.tension=43"});
  ASSERT_EQ(twice.status, 0) << twice.err;
  EXPECT_TRUE(contains(twice.out, "tension: 43")) << twice.out;
  EXPECT_FALSE(contains(twice.out, "tension: 42")) << twice.out;
}

}  // namespace

#endif  // CWS_WIRE_SIM_EXE
