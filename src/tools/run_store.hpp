// Files that let a stability study resume: a finished run's result and an
// unfinished run's checkpoint (its full SimulationState), under DIR/runs/.
// Each file starts with the run's identity, a hash of the core library's
// bytes and of the run's resolved scene and speed events, so that a file
// from another build or another case is never taken for this run.
#pragma once

#include <cstdint>
#include <string>

#include "coil_winding_sim/core/run/simulation.hpp"

namespace cws_tools {

// FNV-1a (64 bit) of `bytes`.
uint64_t fnv1a(const std::string& bytes);

// Hash of the core library this process runs (the shared object holding
// cws::Simulation, or the executable when it is linked in).
uint64_t coreBuildHash();

// An unfinished run: where it was, its wall time so far [s] and the index
// of its next speed event.
struct Checkpoint {
  uint64_t identity = 0;
  double wall_s = 0.0;
  std::size_t next_event = 0;
  cws::SimulationState state;
};

// Written atomically; throws std::runtime_error naming the file.
void writeCheckpoint(const std::string& path, const Checkpoint& c);
// False when the file is missing, unreadable or malformed (the run then
// starts afresh).
bool readCheckpoint(const std::string& path, Checkpoint& c);

}  // namespace cws_tools
