// A machine recording replayed offline (offline_replay.hpp): the node's
// replay loop without its clock, and `wire_sim replay`.
#include "coil_winding_sim/ros/offline_replay.hpp"

#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <iostream>

#include "coil_winding_sim/core/external_forces/port_trajectory.hpp"
#include "coil_winding_sim/core/run/command_schedule.hpp"
#include "coil_winding_sim/core/run/output.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"
#include "coil_winding_sim/ros/cell_timing.hpp"
#include "coil_winding_sim/ros/node_options.hpp"

namespace cws_ros {

void loadReplay(const std::string& scene_path, const std::vector<std::string>& overrides,
                const std::string& bag_path, const Frames& frames, cws::Scene& scene,
                MachineRecording& rec) {
  scene = cws::loadScene(scene_path, overrides);
  rec = readMachineBag(bag_path, cws::SetpointLimits::of(scene.process), frames);
  // (A scene or override that sets supply.max_points keeps it.)
  if (!scene.physics.supply || scene.supply.max_points > 0) return;
  double omega = std::abs(cws::rpmToRadPerSec(scene.process.core_speed_rpm));
  for (const auto& [t, c] : rec.commands) {
    if (c.kind == cws::Setpoint::Kind::kCoreSpeed) omega = std::max(omega, std::abs(c.value));
  }
  double needed = scene.pointCapacityForAngle(omega * rec.duration_s());
  // (Buried wire retires from the live arrays where the core carries it.)
  if (scene.carriesWoundWire()) needed = std::min<double>(needed, cws::kAutoLivePoints);
  if (needed <= scene.pointCapacity()) return;
  std::vector<std::string> more = overrides;
  more.push_back("supply.max_points=" +
                 std::to_string(static_cast<long>(std::min<double>(needed, cws::kMaxScenePoints))));
  scene = cws::loadScene(scene_path, more);
}

bool replayRecording(cws::Simulation& sim, const MachineRecording& rec, const ReplayRates& rates,
                     ReplaySink& sink, std::vector<std::string>& refused,
                     const std::function<bool()>& stop) {
  PublishGrid grid(rates.spindle_hz, rates.frames_hz, rates.profile_hz);
  grid.restart(sim.time());
  // The commands at the simulated time of their stamps; a path's samples
  // (the port's) in order, handed to it while it has room.
  cws::CommandSchedule due;
  std::deque<cws::Setpoint> ports;
  for (const auto& [t, c] : rec.commands) {
    if (cws::setpointRow(c.kind).path_sample) {
      ports.push_back(c);
    } else {
      due.add(t, c);
    }
  }
  const double end = rec.duration_s();
  auto applyDue = [&] {
    due.takeDue(sim.time(), [&](double, const cws::Setpoint& c) {
      try {
        sim.apply(c);
      } catch (const std::exception& e) {
        refused.push_back(std::string("refused a ") + c.name() + " setpoint: " + e.what());
      }
    });
  };
  auto sample = [&] {
    const PublishGrid::Due d = grid.take(sim.time());
    const ros::Time stamp = rec.start + ros::Duration(sim.time());
    if (d.fast) sink.fast(sim, stamp);
    if (d.frames) sink.frames(sim, stamp);
    if (d.profile && sim.model().core()) sink.profile(sim, stamp);
  };
  auto feedPort = [&] {
    while (!ports.empty() && sim.portCommandRoom() > 1) {
      try {
        sim.apply(ports.front());
      } catch (const std::invalid_argument& e) {
        refused.push_back(std::string("refused ") +
                          cws::setpointRow(ports.front().kind).machine_topic + ": " + e.what());
      }
      ports.pop_front();
    }
  };
  applyDue();
  sample();
  for (;;) {
    if (stop && stop()) return false;
    feedPort();
    // Steps end at events only, as in the node: the grid, the bag's end,
    // the next command, and the end of the port's queued path while
    // samples wait for room.
    double limit = std::min(grid.next(), end);
    limit = std::min(limit, due.nextTime());
    if (!ports.empty()) limit = std::min(limit, sim.portCommandEnd());
    if (!(limit > sim.time())) break;
    sim.step(limit);
    applyDue();
    sample();
  }
  return sim.time() >= end - cws::PortTrajectory::timeTolerance(end);
}

void BagSink::fast(const cws::Simulation& sim, const ros::Time& stamp) {
  bag_.write("sim/spindle/command", stamp, toSpindleCommand(sim, stamp));
  bag_.write("sim/spindle/state", stamp, toSpindleState(sim, stamp));
  if (sim.model().supply()) {
    bag_.write("sim/tension/command", stamp, toTensionCommand(sim, stamp));
    bag_.write("sim/tension/measured", stamp, toTensionMeasured(sim, stamp));
  }
  geometry_msgs::PointStamped port;
  if (toPortPosition(sim, stamp, rates_.frames, port)) {
    bag_.write("sim/port/command", stamp, port);
    bag_.write("sim/port/position", stamp, port);
  }
}

void BagSink::profile(const cws::Simulation& sim, const ros::Time& stamp) {
  bag_.write("sim/profile", stamp, toProfile(sim, stamp, rates_.frames, rates_.profile_turns));
}

void SeriesSink::fast(const cws::Simulation& sim, const ros::Time& stamp) {
  const double t = (stamp - start_).toSec();
  out_.spindle_t_s.push_back(t);
  out_.spindle_angle_rad.push_back(toSpindleState(sim, stamp).position[0]);
  if (sim.model().supply()) {
    out_.tension_t_s.push_back(t);
    out_.tension_N.push_back(toTensionMeasured(sim, stamp).tension);
  }
}

void SeriesSink::profile(const cws::Simulation& sim, const ros::Time& stamp) {
  out_.profiles.push_back(profileCloud(toProfile(sim, stamp, rates_.frames, rates_.profile_turns),
                                       (stamp - start_).toSec()));
}

namespace {

int usage(const std::string& why) {
  std::cerr << "wire_sim replay: " << why
            << "\nusage: wire_sim replay MACHINE.bag --out DIR [--scene FILE] [--set key=value]..."
               " [--spindle-rate HZ] [--profile-rate HZ] [--profile-turns N]\n";
  return 2;
}

bool positiveNumber(const std::string& text, double& out, bool zero_ok) {
  try {
    std::size_t used = 0;
    out = std::stod(text, &used);
    return used == text.size() && std::isfinite(out) && (out > 0.0 || (zero_ok && out == 0.0));
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace

int replayMain(const std::vector<std::string>& args, const std::string& default_scene) {
  std::string bag_path, out, scene_path = default_scene;
  std::vector<std::string> overrides;
  NodeOptions node;  // the node's defaults for what the launch leaves as they are
  ReplayRates rates;
  rates.spindle_hz = node.spindle_rate_hz;
  rates.profile_hz = node.profile_rate_hz;
  rates.profile_turns = node.profile_turns;
  for (std::size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    const bool has_value = i + 1 < args.size();
    auto number = [&](double& v, bool zero_ok) {
      if (!has_value) return usage(a + " needs a value");
      if (!positiveNumber(args[++i], v, zero_ok)) {
        return usage(a + " must be a " + (zero_ok ? "number >= 0" : "positive number") + ", not '" +
                     args[i] + "'");
      }
      return 0;
    };
    int rc = 0;
    if (a == "--out" || a == "--scene" || a == "--set") {
      if (!has_value) return usage(a + " needs a value");
      (a == "--out"     ? out
       : a == "--scene" ? scene_path
                        : (overrides.emplace_back(), overrides.back())) = args[++i];
    } else if (a == "--spindle-rate") {
      rc = number(rates.spindle_hz, false);
    } else if (a == "--profile-rate") {
      rc = number(rates.profile_hz, false);
    } else if (a == "--profile-turns") {
      rc = number(rates.profile_turns, true);
    } else if (!a.empty() && a[0] == '-') {
      return usage("unknown option " + a);
    } else if (bag_path.empty()) {
      bag_path = a;
    } else {
      return usage("one machine bag, not also '" + a + "'");
    }
    if (rc) return rc;
  }
  if (bag_path.empty()) return usage("give the machine bag");
  if (out.empty()) return usage("give --out DIR");

  cws::Scene scene;
  MachineRecording rec;
  try {
    loadReplay(scene_path, overrides, bag_path, rates.frames, scene, rec);
    rates.frames_hz = frameRateHz(node, scene);
    cws::checkOutputDir(out);
  } catch (const MachineBagError& e) {
    std::cerr << "wire_sim replay: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "wire_sim replay: " << e.what() << "\n";
    return 2;
  }
  for (const std::string& r : rec.refused) std::cerr << "wire_sim replay: " << r << "\n";

  // The bag under a temporary name, renamed once complete: a replay that
  // fails leaves no bag that looks finished.
  const std::string out_bag = (std::filesystem::path(out) / "replay.bag").string();
  const std::string tmp_bag = out_bag + ".active";
  std::filesystem::remove(out_bag);
  cws::removeOutputs(out);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    cws::Simulation sim(scene);
    rosbag::Bag bag(tmp_bag, rosbag::bagmode::Write);
    bag.setCompression(rosbag::compression::LZ4);
    // The machine's own topics first, so that the bag compares by itself.
    {
      rosbag::Bag in(bag_path, rosbag::bagmode::Read);
      for (const rosbag::MessageInstance& m : rosbag::View(in)) {
        std::string t = m.getTopic();
        if (t.rfind("/machine/", 0) == 0) t.erase(0, 1);
        if (t.rfind("machine/", 0) == 0) bag.write(t, m.getTime(), m);
      }
    }
    BagSink sink(bag, rates);
    std::vector<std::string> refused;
    replayRecording(sim, rec, rates, sink, refused);
    for (const std::string& r : refused) std::cerr << "wire_sim replay: " << r << "\n";
    bag.close();
    std::filesystem::rename(tmp_bag, out_bag);
    cws::writeOutputs(sim, out);
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf(
        "replay: %s, %.6g s simulated in %.3g s of wall time (real-time factor %.3g) -> %s\n",
        bag_path.c_str(), sim.time(), wall_s, sim.time() / std::max(wall_s, 1e-9), out_bag.c_str());
  } catch (const std::exception& e) {
    std::error_code ec;
    std::filesystem::remove(tmp_bag, ec);
    std::cerr << "wire_sim replay: the simulation failed: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace cws_ros
