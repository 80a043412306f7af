// A machine recording replayed through the simulation as fast as it can
// run, without a ROS master (wire_sim replay, and each evaluation of a
// calibration). The steps are those of the node's replay
// (replay_machine.launch, WindingCell::advanceReplay): commands apply at
// their stamps, the port follows its commanded samples, and steps end only
// at commands, at the sampling grid and at the bag's end, so both give the
// same series.
#pragma once

#include <rosbag/bag.h>

#include <functional>
#include <string>
#include <vector>

#include "coil_winding_sim/core/run/simulation.hpp"
#include "coil_winding_sim/ros/bridge.hpp"
#include "coil_winding_sim/ros/machine_bag.hpp"

namespace cws_ros {

struct ReplayRates {
  double spindle_hz = 100.0;   // sim/spindle/*, sim/tension/*, sim/port/* [Hz of simulated time]
  double profile_hz = 5.0;     // sim/profile [Hz]
  double frames_hz = 20.0;     // TF and joint_states [Hz] (the node's frameRateHz)
  double profile_turns = 2.0;  // sim/profile's last turns; 0: all the wound wire
  Frames frames;
};

// What a replay samples on its grid, with the simulation at the sample's
// time; `stamp` is the bag's start plus the simulated time.
class ReplaySink {
 public:
  virtual ~ReplaySink() = default;
  virtual void fast(const cws::Simulation& sim, const ros::Time& stamp) = 0;
  virtual void frames(const cws::Simulation&, const ros::Time&) {}
  virtual void profile(const cws::Simulation& sim, const ros::Time& stamp) = 0;
};

// The scene and the recording of a replay: the scene's file with its
// overrides, the bag read against the scene's limits, and the wire's
// storage sized for the recording (its fastest speed, the scene's or a
// command's, over its whole length) unless the scene or the overrides set
// supply.max_points. Throws MachineBagError for a bad bag, cws::SceneError
// for a bad scene.
void loadReplay(const std::string& scene_path, const std::vector<std::string>& overrides,
                const std::string& bag_path, const Frames& frames, cws::Scene& scene,
                MachineRecording& rec);

// Runs `rec`'s commands through `sim` (in its initial state) to the bag's
// end, handing the grid's samples to `sink`. Commands the simulation
// refuses are left out with a line in `refused`. Returns false when `stop`
// turned true; throws what the simulation throws when it fails.
bool replayRecording(cws::Simulation& sim, const MachineRecording& rec, const ReplayRates& rates,
                     ReplaySink& sink, std::vector<std::string>& refused,
                     const std::function<bool()>& stop = {});

// The `sim/` topics of docs/MACHINE_INTERFACE.md written to a bag, as the
// node publishes them in a replay.
class BagSink : public ReplaySink {
 public:
  BagSink(rosbag::Bag& bag, const ReplayRates& rates) : bag_(bag), rates_(rates) {}
  void fast(const cws::Simulation& sim, const ros::Time& stamp) override;
  void profile(const cws::Simulation& sim, const ros::Time& stamp) override;

 private:
  rosbag::Bag& bag_;
  ReplayRates rates_;
};

// The series a cell measures (spindle angle, tension at the port, profile),
// from the replay, as the bag would hold them; times from the bag's start.
class SeriesSink : public ReplaySink {
 public:
  SeriesSink(const ReplayRates& rates, cws::RecordedSeries& out) : rates_(rates), out_(out) {}
  void fast(const cws::Simulation& sim, const ros::Time& stamp) override;
  void profile(const cws::Simulation& sim, const ros::Time& stamp) override;
  void setStart(const ros::Time& start) { start_ = start; }

 private:
  ReplayRates rates_;
  cws::RecordedSeries& out_;
  ros::Time start_;
};

// wire_sim replay MACHINE.bag --out DIR [--scene FILE] [--set key=value ...]
// [--spindle-rate HZ] [--profile-rate HZ] [--profile-turns N]: DIR/replay.bag
// (the machine's topics and the sim/ series) and DIR/summary.json. Returns
// the exit code: 0, 1 when the simulation failed, 2 for bad input (a
// message on stderr names it).
int replayMain(const std::vector<std::string>& args, const std::string& default_scene);

}  // namespace cws_ros
