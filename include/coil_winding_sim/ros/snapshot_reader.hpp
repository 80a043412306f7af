// Reading an untrusted snapshot bag in a child process: part of the ROS
// bridge (bridge.hpp, snapshot_bag.hpp).
#pragma once

#include <string>

#include "coil_winding_sim/SimulationSnapshot.h"

namespace cws_ros {

// Reads and checks a snapshot bag in a child process, `reader_exe
// --read-snapshot <path>` (an executable whose main() hands that call to
// snapshotReaderMain), under an address-space limit and a wall-time limit
// of `timeout_s`: a file that crashes the reader, exhausts its memory or
// hangs it fails with a message, the calling process is never harmed.
coil_winding_sim::SimulationSnapshot readSnapshotBagIsolated(const std::string& path,
                                                             const std::string& reader_exe,
                                                             double timeout_s);
// The child's side of readSnapshotBagIsolated: reads `path`, checks that it
// restores (cws::Simulation::fromState) and writes the result to `out_fd`.
// Returns the process exit code.
int snapshotReaderMain(const std::string& path, int out_fd);
// The argument that selects snapshotReaderMain, and the descriptor it writes to.
extern const char* const kReadSnapshotArg;
constexpr int kSnapshotReaderFd = 3;

}  // namespace cws_ros
