// Snapshots as messages and bag files, and a bag's time range: part of the
// ROS bridge (bridge.hpp).
#pragma once

#include <ros/time.h>

#include <cstdint>
#include <string>

#include "coil_winding_sim/SimulationSnapshot.h"
#include "coil_winding_sim/core/run/simulation.hpp"

namespace cws_ros {

// Start and end time of a bag (its first and last message). Throws
// std::runtime_error naming the file and the problem.
void bagTimeRange(const std::string& path, ros::Time& start, ros::Time& end);

// Snapshots as messages and bag files. The readers throw std::runtime_error
// with a message that says what is wrong with the file. toSnapshotMsg sets
// the checksum; fromSnapshotMsg refuses a message whose checksum does not
// match (a bag has no checksum of its own: a changed number would restore).
coil_winding_sim::SimulationSnapshot toSnapshotMsg(const cws::SimulationState& state,
                                                   const ros::Time& stamp);
cws::SimulationState fromSnapshotMsg(const coil_winding_sim::SimulationSnapshot& msg);
// FNV-1a (64 bit) of the message serialized with its checksum field 0.
uint64_t snapshotChecksum(const coil_winding_sim::SimulationSnapshot& msg);
void writeSnapshotBag(const std::string& path, const coil_winding_sim::SimulationSnapshot& msg);
// In this process: a corrupt bag can crash rosbag's reader or make the
// deserializer allocate gigabytes. Use it for trusted files only.
coil_winding_sim::SimulationSnapshot readSnapshotBag(const std::string& path);

extern const char* const kSnapshotFormat;
extern const char* const kSnapshotTopic;

}  // namespace cws_ros
