// Tests of the wire_sim command-line tool: exit codes, messages and outputs.
//
// The tool's path comes from the compile definition CWS_WIRE_SIM_EXE (a
// string literal); without it this file compiles to nothing. Every run uses
// its own scene file and --set values for what is asserted, so the package's
// default scene (config/scenes/default.yaml) cannot change the outcome.
#ifdef CWS_WIRE_SIM_EXE

#include "cli_test_support.hpp"

namespace {

using namespace cli_test;

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
  EXPECT_EQ(r.status, 2);  // a bad --out is a bad command line
  EXPECT_TRUE(contains(r.err, out.string())) << r.err;
  EXPECT_FALSE(fs::exists(out / "summary.json"));
  EXPECT_EQ(readAll(plain), "not a directory\n");  // the file is untouched
  // --out naming the regular file itself.
  const RunResult f = runSmall(plain);
  EXPECT_EQ(f.status, 2);
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
            "in_contact,stick,turn,layer");
  for (int i = 0; i < 6; ++i) {
    const std::vector<std::string> cells = splitCsv(lines[i + 1]);
    ASSERT_EQ(cells.size(), 12u) << lines[i + 1];
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
// leave the earlier summary.json to be mistaken for its own: its own, marked
// "stopped", replaces it. The failure: a
// fixed step of 0.1 ms (200 times the axial stability limit of 2 mm segments,
// l / 2640 m/s = 0.76 us) under a 1 N end force cannot meet the tolerance, and
// min_step forbids a smaller step.
TEST_F(WireSimCli, FailedRunAfterSuccessLeavesOnlyItsStoppedSummary) {
  const fs::path out = dir_ / "out";
  ASSERT_EQ(runSmall(out.string()).status, 0);
  ASSERT_TRUE(fs::exists(out / "summary.json"));
  const RunResult r =
      runSmall(out.string(), {"--set", "end.load=[{time: 0, force: [0, 1, 0]}]", "--set",
                              "solver.min_step=1e-4", "--set", "solver.initial_step=1e-4"});
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_TRUE(contains(r.err, "min_step")) << r.err;
  EXPECT_TRUE(contains(readAll(out / "summary.json"), "\"stopped\": {\"cause\": \"error\""))
      << readAll(out / "summary.json");
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

// ---------------------------------------------------------------------------
// Bad command lines: exit 2, the message names the option, and no summary.

TEST_F(WireSimCli, UnknownOptionsOfEveryCommandAreRefused) {
  const fs::path out = dir_ / "out";
  for (const std::string command : {"run", "print-scene", "study", "work-precision"}) {
    const bool takes_out = command != "print-scene";
    for (const std::vector<std::string>& extra :
         std::vector<std::vector<std::string>>{{"--bogus"},
                                               {"-x"},
                                               {"--scene=file.yaml"},  // no '=' form
                                               {"stray.yaml"},
                                               {"--jobs", "2"},
                                               {"--out", (dir_ / "o2").string()}}) {
      // --jobs belongs to study and work-precision, --out to all but
      // print-scene: those are fine there.
      if (extra[0] == "--jobs" && (command == "study" || command == "work-precision")) continue;
      if (extra[0] == "--out" && takes_out) continue;
      std::vector<std::string> args{command};
      args.insert(args.end(), extra.begin(), extra.end());
      if (takes_out) {
        args.push_back("--out");
        args.push_back(out.string());
      }
      const RunResult r = run(args);
      const std::string what = command + " " + extra[0];
      EXPECT_EQ(r.status, 2) << what << ": " << shownRun(r);
      EXPECT_TRUE(contains(r.err, "'" + extra[0] + "'")) << what << ": " << r.err;
      EXPECT_TRUE(contains(r.err, "usage")) << what << ": " << r.err;
      EXPECT_TRUE(r.out.empty()) << what << ": " << r.out;
      EXPECT_FALSE(fs::exists(out)) << what << ": nothing may be created";
    }
  }
}

// An option given twice or with an empty value (an unset shell variable)
// would silently mean the last one or the default.
TEST_F(WireSimCli, RepeatedOrEmptyOptionsAreRefused) {
  const fs::path out = dir_ / "out";
  const std::string scene = write("quiet.yaml", kQuietScene);
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"run", "--out", out.string(), "--out", (dir_ / "b").string()}, "--out given twice"},
      {{"run", "--scene", scene, "--scene", scene, "--out", out.string()}, "--scene given twice"},
      {{"study", "--jobs", "1", "--jobs", "2", "--out", out.string()}, "--jobs given twice"},
      {{"run", "--scene", "", "--out", out.string()}, "--scene needs a file, got an empty"},
      {{"run", "--out", ""}, "--out needs a directory, got an empty"},
      {{"print-scene", "--set", ""}, "--set needs key.path=value, got an empty"},
      {{"work-precision", "--jobs", "", "--out", out.string()}, "--jobs needs a number, got an"},
  };
  for (const auto& [args, message] : cases) {
    const RunResult r = run(args);
    EXPECT_EQ(r.status, 2) << message << ": " << shownRun(r);
    EXPECT_TRUE(contains(r.err, message)) << r.err;
    EXPECT_FALSE(fs::exists(out)) << message;
  }
}

TEST_F(WireSimCli, MalformedSetNamesTheKey) {
  const fs::path out = dir_ / "out";
  // --set value, and words the message must hold.
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {"process.tension", {"'process.tension'", "key.path=value"}},  // no '='
      {"=5", {"'=5'", "key.path=value"}},                            // no key
      {"process..tension=5", {"process..tension", "empty key"}},
      {".tension=5", {".tension", "empty key"}},
      {"process.tension=", {"'process.tension'", "number", "null"}},  // no value
      {"process.tensoin=5", {"'process.tensoin'", "unknown key", "tension"}},
      {"nosuch.key=5", {"'nosuch'", "unknown key"}},
      {"process.tension=strong", {"'process.tension'", "number", "strong"}},
      {"physics.gravity=maybe", {"'physics.gravity'", "true or false"}},
      {"start.direction=[1, 0]", {"'start.direction'", "three", "list of 2"}},
      {"process.tension=[1,", {"'process.tension'", "cannot parse"}},
      {"wire.diameter.x=1", {"wire.diameter.x", "'wire.diameter' is a value"}},
      {"wire=3", {"'wire'", "map of keys"}},
      {"core.cylinders.0.radius=1", {"'core.cylinders' is a list", "core.cylinders=[...]"}},
  };
  for (const auto& [set, words] : cases) {
    const RunResult r = runSmall(out.string(), {"--set", set});
    EXPECT_EQ(r.status, 2) << "--set '" << set << "': " << shownRun(r);
    for (const std::string& w : words) {
      EXPECT_TRUE(contains(r.err, w)) << "--set '" << set << "': missing '" << w << "' in\n"
                                      << r.err;
    }
    EXPECT_FALSE(fs::exists(out)) << "--set '" << set << "': a refused scene touches nothing";
  }
}

TEST_F(WireSimCli, BadSceneFilesAreNamed) {
  const fs::path out = dir_ / "out";
  const fs::path subdir = dir_ / "a_directory";
  fs::create_directories(subdir);
  // --scene, and words the message must hold besides the path.
  const std::vector<std::pair<std::string, std::string>> cases = {
      {subdir.string(), "is a directory"},
      // Unreadable even for root: reading /proc/self/mem at offset 0 fails.
      {"/proc/self/mem", "cannot read"},
      {(dir_ / "missing.yaml").string(), "cannot open"},
      {write("empty.yaml", ""), "no settings"},
      {write("comments.yaml", "# nothing but a comment\n"), "no settings"},
      {write("binary.yaml", std::string("\x7f"
                                        "ELF\x02\x01\x01\0\0\0",
                                        10)),
       "not valid YAML: yaml-cpp: error at line 1, column"},
      {write("word.yaml", "hello world\n"), "must hold a map"},
      {write("list.yaml", "- wire\n- core\n"), "must hold a map"},
      {write("broken.yaml", "wire: {diameter: [1\n"), "not valid YAML"},
      {write("tab.yaml", "wire:\n\tdiameter: 1.0e-3\n"), "not valid YAML"},
      {write("two_docs.yaml", "process: {tension: 40}\n---\nprocess: {tension: 50}\n"),
       "more than one YAML document"},
      {"/dev/zero", "larger than 16 MiB"},
  };
  for (const auto& [scene, why] : cases) {
    for (const std::string command : {"run", "print-scene"}) {
      std::vector<std::string> args{command, "--scene", scene};
      if (command == "run") {
        args.push_back("--out");
        args.push_back(out.string());
      }
      const RunResult r = run(args);
      EXPECT_EQ(r.status, 2) << command << " --scene " << scene << ": " << shownRun(r);
      EXPECT_TRUE(contains(r.err, "'" + scene + "'")) << r.err;
      EXPECT_TRUE(contains(r.err, why)) << "missing '" << why << "' in\n" << r.err;
      EXPECT_TRUE(r.out.empty()) << command << " --scene " << scene << ": " << r.out;
      EXPECT_FALSE(fs::exists(out)) << scene << ": a refused scene touches nothing";
    }
  }
}

// Output directories that cannot be used, found before anything runs. Root
// may write anywhere chmod forbids, so these are paths nobody can use.
TEST_F(WireSimCli, UnusableOutDirIsABadCommandLine) {
  const std::string plain = write("plain_file", "keep\n");
  fs::create_directories(dir_ / "blocked" / "summary.json" / "x");  // cannot be removed
  const std::vector<std::pair<std::string, std::string>> cases = {
      {plain, "cannot create output directory"},
      {(fs::path(plain) / "sub").string(), "cannot create output directory"},
      {"/proc", "not writable"},
      {"/proc/self/no_such_dir/sub", "cannot create output directory"},
      {(dir_ / "blocked").string(), "cannot remove the earlier result"},
  };
  for (const auto& [out, why] : cases) {
    const RunResult r = runSmall(out);
    EXPECT_EQ(r.status, 2) << "--out " << out << ": " << shownRun(r);
    EXPECT_TRUE(contains(r.err, "bad --out")) << r.err;
    EXPECT_TRUE(contains(r.err, "'" + out)) << r.err;
    EXPECT_TRUE(contains(r.err, why)) << "missing '" << why << "' in\n" << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
  EXPECT_EQ(readAll(plain), "keep\n");
  // study and work-precision check their directory the same way.
  for (const std::string command : {"study", "work-precision"}) {
    const RunResult r = run({command, "--out", plain});
    EXPECT_EQ(r.status, 2) << command << ": " << shownRun(r);
    EXPECT_TRUE(contains(r.err, "bad --out")) << r.err;
  }
}

TEST_F(WireSimCli, JobsMustBeAWholeNumberFrom1To64) {
  const fs::path out = dir_ / "out";
  for (const std::string command : {"study", "work-precision"}) {
    for (const std::string jobs :
         {"abc", "0", "65", "-1", "1.5", "2x", " ", "0x2", "99999999999999999999"}) {
      const RunResult r = run({command, "--jobs", jobs, "--out", out.string()});
      EXPECT_EQ(r.status, 2) << command << " --jobs '" << jobs << "': " << shownRun(r);
      EXPECT_TRUE(contains(r.err, "--jobs needs a whole number from 1 to 64, got '" + jobs + "'"))
          << r.err;
      EXPECT_FALSE(fs::exists(out)) << command << " --jobs '" << jobs << "'";
    }
  }
}

}  // namespace

#endif  // CWS_WIRE_SIM_EXE
