// Shared by the wire_sim command-line tests (test_cli.cpp, test_cli_runs.cpp):
// running the tool with captured output, a small quiet scene, and text helpers.
// Needs CWS_WIRE_SIM_EXE (the tool's path, a string literal).
#pragma once

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
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

#include "coil_winding_sim/core/scene/integrators.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"
#include "temp_dir_test.hpp"

namespace cli_test {

namespace fs = std::filesystem;

inline std::string shellQuote(const std::string& s) {
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

inline std::string readAll(const fs::path& p) {
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
inline const char* kQuietScene =
    "physics:\n"
    "  gravity: false\n"
    "  damping: false\n"
    "end:\n"
    "  load:\n"
    "    - {time: 0.0, force: [0, 0, 0], moment: [0, 0, 0]}\n";

// Small wire: 0.01 m in segments of 2 mm is 5 segments, 6 nodes.
inline const std::vector<std::string> kSmallRun{"--set", "wire.length=0.01",
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

  // Starts wire_sim with `args` in the background, stderr to `err`; returns
  // its pid (-1 if it could not start).
  pid_t spawn(std::vector<std::string> args, const fs::path& err) {
    args.insert(args.begin(), CWS_WIRE_SIM_EXE);
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t io;
    posix_spawn_file_actions_init(&io);
    posix_spawn_file_actions_addopen(&io, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&io, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&io, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    pid_t pid = -1;
    if (posix_spawn(&pid, CWS_WIRE_SIM_EXE, &io, nullptr, argv.data(), environ) != 0) pid = -1;
    posix_spawn_file_actions_destroy(&io);
    return pid;
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

inline bool contains(const std::string& text, const std::string& what) {
  return text.find(what) != std::string::npos;
}

// The number after "key": in a flat JSON object (NaN if absent or null).
inline double jsonNumber(const std::string& json, const std::string& key) {
  const std::string tag = "\"" + key + "\":";
  const std::size_t at = json.find(tag);
  if (at == std::string::npos) return std::nan("");
  const char* begin = json.c_str() + at + tag.size();
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  return end == begin ? std::nan("") : v;
}

inline std::vector<std::string> splitLines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream s(text);
  for (std::string line; std::getline(s, line);) lines.push_back(line);
  return lines;
}

inline std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> cells;
  std::istringstream s(line);
  for (std::string cell; std::getline(s, cell, ',');) cells.push_back(cell);
  return cells;
}

// The status and messages of a refused command line, for a failure message.
inline std::string shownRun(const RunResult& r) {
  return "status " + std::to_string(r.status) + ", stderr: " + r.err;
}

// No summary.json in `dir`, nor a temporary one.
inline void expectNoSummary(const fs::path& dir, const std::string& what) {
  EXPECT_FALSE(fs::exists(dir / "summary.json")) << what;
  EXPECT_FALSE(fs::exists(dir / "summary.json.partial")) << what;
}

}  // namespace cli_test
