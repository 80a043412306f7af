// Replay of a machine recording (replay_machine.launch), end to end: the
// test writes a short machine bag from a known command profile (spindle
// ramp to 1200 rpm, 30 N, a port moving along the core axis), runs
// `roslaunch coil_winding_sim replay_machine.launch` on a ROS master port of
// its own until it ends by itself (the node stops at the bag's end), and
// checks the output bag against closed forms: the spindle angle is the
// integral of the commanded speed reached at core.max_angular_acceleration,
// the port follows the straight lines between the commanded samples, the
// port force is near the commanded tension. Two runs at play rates 0.02
// (the simulation, at a real-time factor of about 0.04, follows the clock) and 1 (far faster than
// it can follow) must give the same numbers: setpoints apply at their stamps.
//
// A plain gtest (catkin_add_gtest): it runs under the devel space, so that
// roslaunch finds the package; it starts no ROS node itself.
#include <arpa/inet.h>
#include <geometry_msgs/PointStamped.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <ros/time.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/PointCloud2.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "coil_winding_sim/TensionSetpoint.h"
#include "coil_winding_sim/WireTension.h"
#include "ros_test_support.hpp"

#if !defined(CWS_SOURCE_DIR) || !defined(CWS_PYTHON) || !defined(CWS_WIRE_SIM_EXE)
#error "CWS_SOURCE_DIR, CWS_PYTHON and CWS_WIRE_SIM_EXE must be defined"
#endif

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

// The command profile (times from the bag's start [s]).
constexpr double kStart = 1000.0;       // the bag's start on the machine's clock [s]
constexpr double kEnd = 0.1;            // bag length [s]
constexpr double kPeriod = 0.01;        // command period [s] (100 Hz)
constexpr double kOmega = 40.0 * M_PI;  // 1200 rpm [rad/s]
constexpr double kAlphaMax = 2.0e4;     // core.max_angular_acceleration of the scene [rad/s^2]
constexpr double kTension = 30.0;       // [N]
constexpr double kPortSpeed = 5.0e-3;   // along the core axis from t = 0.02 s [m/s]
const double kPort0[3] = {5.5e-3, -0.03, 0.0};  // the scene's port position [m]

// Commanded speed: 0 until 10 ms, a straight ramp to 1200 rpm at 40 ms, held.
double speedCommand(double t) { return kOmega * std::clamp((t - 0.01) / 0.03, 0.0, 1.0); }
double portZ(double t) { return kPortSpeed * std::max(0.0, t - 0.02); }

// Closed form of the core angle: the commands (t_k, w_k) apply at their
// stamps; between them the speed moves towards the last command at alpha
// and holds it.
double angleAt(const std::vector<std::pair<double, double>>& cmds, double t) {
  double theta = 0.0, w = 0.0, target = 0.0, tc = 0.0;
  auto advance = [&](double dt) {
    const double s = target > w ? 1.0 : -1.0;
    const double tr = std::abs(target - w) / kAlphaMax;
    if (dt <= tr) {
      theta += w * dt + 0.5 * s * kAlphaMax * dt * dt;
      w += s * kAlphaMax * dt;
    } else {
      theta += w * tr + 0.5 * s * kAlphaMax * tr * tr + target * (dt - tr);
      w = target;
    }
  };
  for (const auto& [tk, wk] : cmds) {
    if (tk > t) break;
    advance(tk - tc);
    tc = tk;
    target = wk;
  }
  advance(t - tc);
  return theta;
}

using cws_ros_test::freePort;
using cws_ros_test::readFile;

// The machine bag: commands at 100 Hz, measured topics as copies.
void writeMachineBag(const fs::path& path) {
  rosbag::Bag bag(path.string(), rosbag::bagmode::Write);
  for (int k = 0; k <= static_cast<int>(std::lround(kEnd / kPeriod)); ++k) {
    const double t = k * kPeriod;
    const ros::Time stamp = ros::Time(kStart) + ros::Duration(t);
    sensor_msgs::JointState spindle;
    spindle.header.stamp = stamp;
    spindle.name = {"spindle"};
    spindle.velocity = {speedCommand(t)};
    bag.write("machine/spindle/command", stamp, spindle);
    // The measured state: the closed-form angle of the commands so far
    // (compare_bags.py needs the angle).
    std::vector<std::pair<double, double>> so_far;
    for (int i = 0; i <= k; ++i) so_far.emplace_back(i * kPeriod, speedCommand(i * kPeriod));
    spindle.position = {angleAt(so_far, t)};
    bag.write("machine/spindle/state", stamp, spindle);
    coil_winding_sim::TensionSetpoint tension;
    tension.header.stamp = stamp;
    tension.tension = kTension;
    bag.write("machine/tension/command", stamp, tension);
    coil_winding_sim::WireTension measured;
    measured.header.stamp = stamp;
    measured.tension = kTension;
    bag.write("machine/tension/measured", stamp, measured);
    geometry_msgs::PointStamped port;
    port.header.stamp = stamp;
    port.header.frame_id = "world";
    port.point.x = kPort0[0];
    port.point.y = kPort0[1];
    port.point.z = kPort0[2] + portZ(t);
    bag.write("machine/port/command", stamp, port);
    bag.write("machine/port/position", stamp, port);
  }
  bag.close();
}

// Runs the replay launch to its end (at most 120 s); returns roslaunch's
// exit status (-1: killed on the time limit) and its output.
int runReplay(const fs::path& dir, const fs::path& machine, const fs::path& out, double rate,
              std::string& output, double& wall_s, const std::vector<std::string>& extra = {}) {
  const int port = freePort();
  if (port <= 0) return -2;
  const std::string log = (dir / ("roslaunch_" + out.stem().string() + ".log")).string();
  char rate_text[32];
  std::snprintf(rate_text, sizeof rate_text, "%g", rate);
  std::vector<std::string> args = {
      "coil_winding_sim",
      "replay_machine.launch",
      "bag:=" + machine.string(),
      "out:=" + out.string(),
      std::string("scene:=") + CWS_SOURCE_DIR + "/test/scenes/replay_drum.yaml",
      std::string("rate:=") + rate_text,
      "delay:=2",
      "profile_rate:=50"};
  args.insert(args.end(), extra.begin(), extra.end());
  const auto t0 = Clock::now();
  const pid_t pid = cws_ros_test::startRoslaunch(args, port, dir, log);
  if (pid < 0) return -2;
  int status = 0;
  const bool exited = cws_ros_test::waitForLaunch(pid, 120.0, status);
  wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  output = readFile(log);
  if (!exited) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -3;
}

// One topic of the output bag: stamps (from the bag's start) and values.
struct Series {
  std::vector<double> t;
  std::vector<std::vector<double>> v;
};

std::map<std::string, Series> readOutput(const fs::path& path) {
  std::map<std::string, Series> out;
  rosbag::Bag bag(path.string(), rosbag::bagmode::Read);
  rosbag::View view(bag);
  const ros::Time start(kStart);
  for (const rosbag::MessageInstance& m : view) {
    std::string topic = m.getTopic();
    if (!topic.empty() && topic[0] == '/') topic.erase(0, 1);
    Series& s = out[topic];
    if (auto j = m.instantiate<sensor_msgs::JointState>()) {
      s.t.push_back((j->header.stamp - start).toSec());
      std::vector<double> v = j->position;
      v.insert(v.end(), j->velocity.begin(), j->velocity.end());
      s.v.push_back(v);
    } else if (auto p = m.instantiate<geometry_msgs::PointStamped>()) {
      s.t.push_back((p->header.stamp - start).toSec());
      s.v.push_back({p->point.x, p->point.y, p->point.z});
    } else if (auto w = m.instantiate<coil_winding_sim::WireTension>()) {
      s.t.push_back((w->header.stamp - start).toSec());
      s.v.push_back({w->tension});
    } else if (auto c = m.instantiate<coil_winding_sim::TensionSetpoint>()) {
      s.t.push_back((c->header.stamp - start).toSec());
      s.v.push_back({c->tension});
    } else if (auto pc = m.instantiate<sensor_msgs::PointCloud2>()) {
      s.t.push_back((pc->header.stamp - start).toSec());
      // Fields x, y, z, stand_off as float32: the raw values.
      std::vector<double> v;
      for (std::size_t i = 0; i + 4 <= pc->data.size(); i += 4) {
        float f;
        std::memcpy(&f, &pc->data[i], 4);
        v.push_back(f);
      }
      v.push_back(pc->width);
      v.push_back(pc->fields.size() == 4 && pc->fields[3].name == "stand_off" ? 1.0 : 0.0);
      s.v.push_back(v);
    } else {
      s.t.push_back(m.getTime().toSec() - kStart);
    }
  }
  return out;
}

class ReplayMachine : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    char tmpl[] = "/tmp/cws_replay_XXXXXX";
    ASSERT_NE(::mkdtemp(tmpl), nullptr);
    dir_ = tmpl;
    writeMachineBag(dir_ / "machine.bag");
  }
  // CWS_KEEP_TEST_OUTPUT=1 keeps the bags and the comparison for a look.
  static void TearDownTestSuite() {
    if (std::getenv("CWS_KEEP_TEST_OUTPUT")) {
      std::printf("test output kept in %s\n", dir_.c_str());
      return;
    }
    if (!::testing::Test::HasFailure()) fs::remove_all(dir_);
  }
  static fs::path dir_;
};
fs::path ReplayMachine::dir_;

// The runs, shared by the tests (slow: roslaunch and the simulation).
std::map<double, std::map<std::string, Series>> runs;

const std::map<std::string, Series>& replay(const fs::path& dir, double rate) {
  auto it = runs.find(rate);
  if (it != runs.end()) return it->second;
  const fs::path out = dir / ("replay_" + std::to_string(static_cast<int>(rate * 1000)) + ".bag");
  std::string output;
  double wall_s = 0.0;
  const int rc = runReplay(dir, dir / "machine.bag", out, rate, output, wall_s);
  std::printf("replay at rate %g: roslaunch exit %d after %.1f s of wall time\n", rate, rc, wall_s);
  EXPECT_EQ(rc, 0) << "roslaunch did not end by itself (exit " << rc << "):\n" << output;
  EXPECT_TRUE(fs::exists(out)) << "no closed output bag " << out << ":\n" << output;
  EXPECT_FALSE(fs::exists(out.string() + ".active")) << "the output bag was not closed";
  if (!fs::exists(out)) return runs[rate];
  return runs[rate] = readOutput(out);
}

}  // namespace

TEST_F(ReplayMachine, OutputFollowsTheCommandsInClosedForm) {
  const auto& bag = replay(dir_, 0.02);
  for (const char* topic :
       {"machine/spindle/command", "machine/spindle/state", "machine/tension/command",
        "machine/tension/measured", "machine/port/command", "machine/port/position",
        "sim/spindle/command", "sim/spindle/state", "sim/tension/command", "sim/tension/measured",
        "sim/port/command", "sim/port/position", "sim/profile", "wire_state", "winding_metrics",
        "tf"}) {
    EXPECT_TRUE(bag.count(topic) && !bag.at(topic).t.empty()) << "missing topic " << topic;
  }
  if (!bag.count("sim/spindle/state")) return;

  // Spindle: 100 Hz of simulated time from 0 to the bag's end.
  std::vector<std::pair<double, double>> cmds;
  for (int k = 0; k <= 10; ++k) cmds.emplace_back(k * kPeriod, speedCommand(k * kPeriod));
  const Series& state = bag.at("sim/spindle/state");
  EXPECT_EQ(state.t.size(), 11u) << "0, 10, .., 100 ms";
  EXPECT_NEAR(state.t.back(), kEnd, 1e-9) << "the replay must reach the bag's end";
  double worst_angle = 0.0, worst_speed = 0.0;
  for (std::size_t i = 0; i < state.t.size(); ++i) {
    const double t = state.t[i];
    ASSERT_EQ(state.v[i].size(), 2u);
    worst_angle = std::max(worst_angle, std::abs(state.v[i][0] - angleAt(cmds, t)));
    const double dt = 1e-9;
    const double w = (angleAt(cmds, t + dt) - angleAt(cmds, t - dt)) / (2 * dt);
    worst_speed = std::max(worst_speed, std::abs(state.v[i][1] - w));
  }
  std::printf(
      "replay: %zu spindle states, angle error %.3e rad (final angle %.4f rad), speed "
      "error %.3e rad/s\n",
      state.t.size(), worst_angle, state.v.back()[0], worst_speed);
  // Stamps carry nanoseconds: 0.5 ns x 126 rad/s = 6e-8 rad.
  EXPECT_LT(worst_angle, 1e-6);
  EXPECT_LT(worst_speed, 1e-3);

  // Port: on the commanded straight lines (here along the axis).
  const Series& port = bag.at("sim/port/position");
  double worst_port = 0.0;
  for (std::size_t i = 0; i < port.t.size(); ++i) {
    const double t = port.t[i];
    const double e = std::hypot(port.v[i][0] - kPort0[0], port.v[i][1] - kPort0[1],
                                port.v[i][2] - kPort0[2] - portZ(t));
    worst_port = std::max(worst_port, e);
  }
  std::printf("replay: %zu port positions, error %.3e m (final z %.4f mm)\n", port.t.size(),
              worst_port, 1e3 * port.v.back()[2]);
  EXPECT_EQ(port.t.size(), 11u);
  EXPECT_LT(worst_port, 1e-9);

  // Tension: the commanded value, and the wire's force at the port near it
  // once the spindle turns at speed (mean over 50 .. 100 ms).
  for (const auto& v : bag.at("sim/tension/command").v) EXPECT_EQ(v[0], kTension);
  const Series& force = bag.at("sim/tension/measured");
  double sum = 0.0, worst_rel = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < force.t.size(); ++i) {
    if (force.t[i] < 0.05) continue;
    sum += force.v[i][0];
    ++n;
    worst_rel = std::max(worst_rel, std::abs(force.v[i][0] / kTension - 1.0));
  }
  ASSERT_GT(n, 3);
  std::printf("replay: port force mean %.3f N over %d samples (commanded %.1f N), worst %.1f %%\n",
              sum / n, n, kTension, 100.0 * worst_rel);
  EXPECT_NEAR(sum / n / kTension, 1.0, 0.05);
  EXPECT_LT(worst_rel, 0.2);

  // Profile: x, y, z, stand_off of the wound points.
  const Series& profile = bag.at("sim/profile");
  EXPECT_EQ(profile.t.size(), 6u) << "50 Hz: 0, 20, .., 100 ms";
  if (!profile.v.empty()) {
    EXPECT_EQ(profile.v.back().back(), 1.0) << "fields x, y, z, stand_off";
    EXPECT_GT(profile.v.back()[profile.v.back().size() - 2], 1.0) << "no wound points";
  }
}

TEST_F(ReplayMachine, SameResultWhenPlayedFasterThanTheSimulation) {
  const auto& slow = replay(dir_, 0.02);
  const auto& fast = replay(dir_, 1.0);
  for (const char* topic : {"sim/spindle/state", "sim/spindle/command", "sim/port/position",
                            "sim/tension/measured", "sim/profile"}) {
    ASSERT_TRUE(slow.count(topic) && fast.count(topic)) << topic;
    const Series& a = slow.at(topic);
    const Series& b = fast.at(topic);
    EXPECT_EQ(a.t, b.t) << topic << ": stamps differ";
    EXPECT_EQ(a.v, b.v) << topic << ": values differ";
  }
}

// End to end with the comparison tool: the replay's own output, perturbed
// as a machine's recording would differ from it (tension 2 N high with
// 0.2 N of noise, stamps 2 ms late, the profile 0.1 mm further out), then
// compared with the clean replay by compare_bags.py. The tool must recover
// each perturbation. Spindle and tension at 2 kHz, so that the 2 ms shift
// spans 4 samples and the 6 ms speed ramp 12.
TEST_F(ReplayMachine, ComparisonRecoversAPerturbationOfTheReplay) {
  const fs::path sim_bag = dir_ / "replay_2khz.bag";
  std::string output;
  double wall_s = 0.0;
  const int rc =
      runReplay(dir_, dir_ / "machine.bag", sim_bag, 1.0, output, wall_s, {"spindle_rate:=2000"});
  ASSERT_EQ(rc, 0) << output;
  ASSERT_TRUE(fs::exists(sim_bag)) << output;
  const std::string tools = std::string(CWS_SOURCE_DIR) + "/src/tools/";
  const fs::path machine_bag = dir_ / "perturbed_machine.bag";
  const fs::path out = dir_ / "comparison";
  const std::string python = CWS_PYTHON;  // catkin's (Debian's) interpreter
  const std::string perturb = python + " " + tools + "make_synthetic_bags.py --from-sim-bag " +
                              sim_bag.string() + " --machine-bag " + machine_bag.string() +
                              " --tension-offset 2 --tension-noise 0.2 --seed 7"
                              " --time-shift 0.002 --profile-offset-mm 0.1 > " +
                              (dir_ / "perturb.log").string() + " 2>&1";
  ASSERT_EQ(std::system(perturb.c_str()), 0) << readFile(dir_ / "perturb.log");
  const std::string compare = python + " " + tools + "compare_bags.py --machine " +
                              machine_bag.string() + " --sim " + sim_bag.string() + " --out " +
                              out.string() + " --align angle --no-plots > " +
                              (dir_ / "compare.log").string() + " 2>&1";
  ASSERT_EQ(std::system(compare.c_str()), 0) << readFile(dir_ / "compare.log");
  const YAML::Node s = YAML::LoadFile((out / "summary.json").string());
  const double offset_N = s["tension"]["mean_offset_N"].as<double>();
  const double rms_N = s["tension"]["rms_N"].as<double>();
  const double lag_s = s["lag"]["spindle_speed_lag_s"].as<double>();
  const double profile_mm = s["profile"]["all_pairs"]["rms_mm"].as<double>();
  std::printf(
      "comparison of the perturbed replay: tension offset %.3f N, RMS %.3f N over %d samples, "
      "spindle lag %.3f ms, profile RMS %.4f mm\n",
      offset_N, rms_N, s["tension"]["samples"].as<int>(), 1e3 * lag_s, profile_mm);
  // Errors are sim - machine. The noise's mean over ~200 samples is
  // 0.2 / sqrt(200) = 0.014 N; the replay's own tension varies by far less
  // than 0.05 N between neighbouring angles.
  EXPECT_NEAR(offset_N, -2.0, 0.05);
  EXPECT_NEAR(rms_N, std::sqrt(2.0 * 2.0 + 0.2 * 0.2), 0.05);
  // Half a sample of 2 kHz.
  EXPECT_NEAR(lag_s, 0.002, 2.5e-4);
  // A radial offset of the points: at most the chord sag (l^2 / (8 r) =
  // 0.1 mm for 2 mm points on r = 5.5 mm) off the offset.
  EXPECT_NEAR(profile_mm, 0.1, 0.02);
}

// Runs a shell command, its output into `log`; its exit status (-1: not run).
int shell(const std::string& cmd, const fs::path& log) {
  const int rc = std::system((cmd + " > " + log.string() + " 2>&1").c_str());
  return rc == -1 ? -1 : WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

// `wire_sim replay` of the same machine bag, with the launch's scene and
// rates, gives the launch's sim/ series: the same stamps, the same values.
TEST_F(ReplayMachine, TheOfflineReplayGivesTheLaunchsSeries) {
  const auto& launch = replay(dir_, 1.0);
  const fs::path out = dir_ / "offline";
  const int rc =
      shell(std::string(CWS_WIRE_SIM_EXE) + " replay " + (dir_ / "machine.bag").string() +
                " --out " + out.string() + " --scene " + CWS_SOURCE_DIR +
                "/test/scenes/replay_drum.yaml --profile-rate 50",
            dir_ / "offline.log");
  ASSERT_EQ(rc, 0) << readFile(dir_ / "offline.log");
  ASSERT_TRUE(fs::exists(out / "replay.bag"));
  EXPECT_TRUE(fs::exists(out / "summary.json"));
  const auto offline = readOutput(out / "replay.bag");
  for (const char* topic :
       {"sim/spindle/state", "sim/spindle/command", "sim/port/position", "sim/port/command",
        "sim/tension/command", "sim/tension/measured", "sim/profile"}) {
    ASSERT_TRUE(launch.count(topic)) << topic << " missing from the launch's replay";
    ASSERT_TRUE(offline.count(topic)) << topic << " missing from the offline replay";
    const Series& a = launch.at(topic);
    const Series& b = offline.at(topic);
    ASSERT_EQ(a.t.size(), b.t.size()) << topic;
    double worst = 0.0;
    for (std::size_t i = 0; i < a.t.size(); ++i) {
      EXPECT_NEAR(a.t[i], b.t[i], 1e-9) << topic << " sample " << i;
      ASSERT_EQ(a.v[i].size(), b.v[i].size()) << topic << " sample " << i;
      for (std::size_t k = 0; k < a.v[i].size(); ++k) {
        worst = std::max(worst, std::abs(a.v[i][k] - b.v[i][k]));
      }
    }
    std::printf("offline replay against the launch: %s, %zu samples, largest difference %.3g\n",
                topic, a.t.size(), worst);
    // The same steps in the same order: equal to rounding.
    EXPECT_LT(worst, 1e-9) << topic;
  }
  // The machine's topics copied whole (the launch's recorder may miss the
  // first messages of a fast play).
  for (const char* topic : {"machine/spindle/command", "machine/spindle/state",
                            "machine/tension/measured", "machine/port/command"}) {
    ASSERT_TRUE(offline.count(topic)) << topic;
    EXPECT_EQ(offline.at(topic).t.size(), 11u) << topic;
  }
}

// A machine bag that compare_bags.py refuses is refused by `wire_sim
// replay` in the same words (after each tool's "error: ").
TEST_F(ReplayMachine, BadBagsAreRefusedAsTheComparisonRefusesThem) {
  const auto& launch = replay(dir_, 1.0);
  ASSERT_FALSE(launch.empty());
  const fs::path sim_bag = dir_ / "replay_1000.bag";
  const std::string python = CWS_PYTHON;
  const std::string tools = std::string(CWS_SOURCE_DIR) + "/src/tools/";
  // Bad bags: perturbations of the replay's own sim/ topics as a machine's.
  const std::vector<std::pair<std::string, std::string>> perturbed = {
      {"no_tension", "--drop-topic tension/measured"},
      {"no_state", "--drop-topic spindle/state"},
      {"non_monotonic", "--non-monotonic spindle/state"},
      {"renamed_joint", "--rename-joint drum"},
  };
  std::vector<std::pair<std::string, fs::path>> bags;
  for (const auto& [name, args] : perturbed) {
    const fs::path bag = dir_ / ("bad_" + name + ".bag");
    ASSERT_EQ(shell(python + " " + tools + "make_synthetic_bags.py --from-sim-bag " +
                        sim_bag.string() + " --machine-bag " + bag.string() + " " + args,
                    dir_ / "perturb.log"),
              0)
        << readFile(dir_ / "perturb.log");
    bags.emplace_back(name, bag);
  }
  {
    // Measured tension of the command's type.
    const fs::path bag = dir_ / "bad_type.bag";
    rosbag::Bag out(bag.string(), rosbag::bagmode::Write);
    rosbag::Bag in((dir_ / "machine.bag").string(), rosbag::bagmode::Read);
    for (const rosbag::MessageInstance& m : rosbag::View(in)) {
      if (m.getTopic() == "machine/tension/measured") {
        auto w = m.instantiate<coil_winding_sim::WireTension>();
        coil_winding_sim::TensionSetpoint c;
        c.header = w->header;
        c.tension = w->tension;
        out.write(m.getTopic(), m.getTime(), c);
      } else {
        out.write(m.getTopic(), m.getTime(), m);
      }
    }
    bags.emplace_back("wrong_type", bag);
  }
  bags.emplace_back("missing", dir_ / "no_such.bag");
  std::ofstream(dir_ / "not_a_bag.bag") << "a text file\n";
  bags.emplace_back("not_a_bag", dir_ / "not_a_bag.bag");

  auto errorOf = [](const std::string& log) {
    const std::size_t at = log.find("error: ");
    std::string e = at == std::string::npos ? log : log.substr(at + 7);
    return e.substr(0, e.find('\n'));
  };
  for (const auto& [name, bag] : bags) {
    const int rc_replay = shell(std::string(CWS_WIRE_SIM_EXE) + " replay " + bag.string() +
                                    " --out " + (dir_ / "bad_out").string(),
                                dir_ / "bad_replay.log");
    const int rc_compare =
        shell(python + " " + tools + "compare_bags.py --machine " + bag.string() + " --sim " +
                  sim_bag.string() + " --out " + (dir_ / "bad_cmp").string() + " --no-plots",
              dir_ / "bad_cmp.log");
    const std::string replay_error = errorOf(readFile(dir_ / "bad_replay.log"));
    const std::string compare_error = errorOf(readFile(dir_ / "bad_cmp.log"));
    std::printf("%s: replay %d '%s'\n", name.c_str(), rc_replay, replay_error.c_str());
    EXPECT_EQ(rc_compare, 2) << name;
    EXPECT_EQ(rc_replay, 2) << name;
    EXPECT_FALSE(fs::exists(dir_ / "bad_out" / "replay.bag")) << name;
    if (name == "not_a_bag") {
      // The readers' own words differ; the start is the tools'.
      const std::string start = "cannot read bag " + bag.string() + ": ";
      EXPECT_EQ(replay_error.rfind(start, 0), 0u) << replay_error;
      EXPECT_EQ(compare_error.rfind(start, 0), 0u) << compare_error;
    } else {
      EXPECT_EQ(replay_error, compare_error) << name;
    }
  }
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
