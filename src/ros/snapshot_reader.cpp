// The sandboxed snapshot reader: a child process that reads a bag under an
// address-space and a wall-time limit (snapshot_reader.hpp).
#include "coil_winding_sim/ros/snapshot_reader.hpp"

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <new>
#include <vector>

#include "coil_winding_sim/core/run/simulation.hpp"
#include "coil_winding_sim/ros/snapshot_bag.hpp"

namespace cws_ros {

const char* const kReadSnapshotArg = "--read-snapshot";

namespace {
// The reader's first output byte: a snapshot follows, or an error message.
constexpr char kReaderOk = 'K';
constexpr char kReaderError = 'E';
// Address space of the reader process [bytes]: a corrupt array length makes
// the deserializer allocate up to 32 GiB; under this limit it fails instead.
constexpr rlim_t kReaderAddressSpace = rlim_t{2} << 30;

bool writeAll(int fd, const std::string& data) {
  std::size_t done = 0;
  while (done < data.size()) {
    const ssize_t n = ::write(fd, data.data() + done, data.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

// Closes a descriptor when it goes out of scope.
struct Fd {
  int fd = -1;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};
}  // namespace

int snapshotReaderMain(const std::string& path, int out_fd) {
  rlimit limit;
  limit.rlim_cur = limit.rlim_max = kReaderAddressSpace;
  ::setrlimit(RLIMIT_AS, &limit);
  std::string out;
  int rc = 0;
  try {
    const coil_winding_sim::SimulationSnapshot msg = readSnapshotBag(path);  // names the path
    // The whole restore, so that a scene or state that cannot be built
    // fails here, within the limits, and not in the caller.
    try {
      cws::Simulation::fromState(fromSnapshotMsg(msg));
    } catch (const std::bad_alloc&) {
      throw;
    } catch (const std::exception& e) {
      throw std::runtime_error("'" + path + "': " + e.what());
    }
    // Serialized anew: the caller gets array lengths that match the data.
    const uint32_t n = ros::serialization::serializationLength(msg);
    out.assign(1 + n, kReaderOk);
    ros::serialization::OStream stream(reinterpret_cast<uint8_t*>(&out[1]), n);
    ros::serialization::serialize(stream, msg);
  } catch (const std::bad_alloc&) {
    out = std::string(1, kReaderError) + "'" + path + "' is corrupt: reading it needs more than " +
          std::to_string(kReaderAddressSpace >> 30) + " GiB of memory";
    rc = 1;
  } catch (const std::exception& e) {
    out = std::string(1, kReaderError) + e.what();
    rc = 1;
  }
  return writeAll(out_fd, out) ? rc : 1;
}

coil_winding_sim::SimulationSnapshot readSnapshotBagIsolated(const std::string& path,
                                                             const std::string& reader_exe,
                                                             double timeout_s) {
  const auto fail = [&](const std::string& why) {
    return std::runtime_error("'" + path + "': " + why);
  };
  // Cheap checks here, so that their messages need no child.
  if (!std::filesystem::exists(path)) {
    throw std::runtime_error("snapshot file '" + path + "' does not exist");
  }
  if (!std::filesystem::is_regular_file(path)) {
    throw std::runtime_error("snapshot file '" + path + "' is not a regular file");
  }

  // The child: stdin, stdout and stderr on /dev/null (rosbag's complaints
  // about a corrupt file would read like network trouble in our log), the
  // result on descriptor kSnapshotReaderFd, nothing else of ours open.
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw fail(std::string("pipe: ") + std::strerror(errno));
  Fd read_end{fds[0]}, write_end{fds[1]};
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, write_end.fd, kSnapshotReaderFd);
  posix_spawn_file_actions_addclosefrom_np(&actions, kSnapshotReaderFd + 1);
  std::vector<std::string> args = {reader_exe, kReadSnapshotArg, path};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int spawn_error =
      ::posix_spawn(&pid, reader_exe.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawn_error != 0) {
    throw fail("cannot start the snapshot reader '" + reader_exe +
               "': " + std::strerror(spawn_error));
  }
  ::close(write_end.fd);
  write_end.fd = -1;

  // Read until end of file, the time limit or the size limit.
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(timeout_s));
  const std::size_t max_bytes = kReaderAddressSpace / 2;
  std::string out;
  std::string problem;
  char buffer[65536];
  while (true) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    if (left.count() <= 0) {
      char text[128];
      std::snprintf(text, sizeof text, "reading it took longer than %g s (corrupt?)", timeout_s);
      problem = text;
      break;
    }
    pollfd p{read_end.fd, POLLIN, 0};
    const int ready = ::poll(&p, 1, static_cast<int>(std::min<long long>(left.count(), 1000)));
    if (ready < 0 && errno != EINTR) {
      problem = std::string("poll: ") + std::strerror(errno);
      break;
    }
    if (ready <= 0) continue;
    const ssize_t n = ::read(read_end.fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // end of file (or an error: judged by the exit status)
    out.append(buffer, static_cast<std::size_t>(n));
    if (out.size() > max_bytes) {
      problem = "the snapshot reader's output exceeds " + std::to_string(max_bytes) + " bytes";
      break;
    }
  }
  if (!problem.empty()) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!problem.empty()) throw fail(problem);
  if (WIFSIGNALED(status)) {
    throw std::runtime_error("'" + path + "' is corrupt: reading it crashed the bag reader (" +
                             strsignal(WTERMSIG(status)) + ")");
  }
  if (out.empty()) {
    throw fail("the snapshot reader '" + reader_exe + "' exited with status " +
               std::to_string(WEXITSTATUS(status)) + " and no result");
  }
  if (out[0] == kReaderError) throw std::runtime_error(out.substr(1));
  if (out[0] != kReaderOk || WEXITSTATUS(status) != 0) {
    throw fail("the snapshot reader '" + reader_exe + "' gave no readable result");
  }
  coil_winding_sim::SimulationSnapshot msg;
  try {
    ros::serialization::IStream stream(reinterpret_cast<uint8_t*>(&out[1]),
                                       static_cast<uint32_t>(out.size() - 1));
    ros::serialization::deserialize(stream, msg);
  } catch (const std::exception& e) {
    throw fail(std::string("the snapshot reader's result does not deserialize: ") + e.what());
  }
  return msg;
}

}  // namespace cws_ros
