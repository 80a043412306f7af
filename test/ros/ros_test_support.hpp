// Helpers shared by the rostests of the winding cell.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <ros/ros.h>
#include <sys/socket.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

namespace cws_ros_test {

// Waits (wall time, polling every 10 ms) until pred() holds; the last call
// decides.
template <class Pred>
bool waitFor(Pred pred, double seconds) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::WallTime::now() < end) {
    if (pred()) return true;
    ros::WallDuration(0.01).sleep();
  }
  return pred();
}

// A TCP port that is free now (the kernel's choice), for a ROS master of a
// test's own; -1 if none.
inline int freePort() {
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = 0;
  socklen_t len = sizeof a;
  if (s < 0 || ::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
      ::getsockname(s, reinterpret_cast<sockaddr*>(&a), &len) != 0) {
    if (s >= 0) ::close(s);
    return -1;
  }
  ::close(s);
  return ntohs(a.sin_port);
}

// A whole file as text (empty if unreadable).
inline std::string readFile(const std::filesystem::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Starts `roslaunch args...` (args without the program name) against a
// master of its own on master_port: the child in a process group of its own
// (as a shell's foreground job, so that a signal to -pid reaches the whole
// launch), ROS logs in dir/ros_log, its output to log, started from the
// directory `cwd` if one is given; `program`: roslaunch, or a program that
// takes its arguments (launch_cell). Returns the child's pid, or -1.
inline pid_t startRoslaunch(std::vector<std::string> args, int master_port,
                            const std::filesystem::path& dir, const std::string& log,
                            const std::filesystem::path& cwd = {},
                            const std::string& program = "roslaunch") {
  args.insert(args.begin(), {program, "-p", std::to_string(master_port)});
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const std::string uri = "http://127.0.0.1:" + std::to_string(master_port);
  std::fflush(nullptr);  // (else the child writes out this process's buffered output again)
  const pid_t pid = ::fork();
  if (pid < 0) return -1;
  if (pid == 0) {
    ::setpgid(0, 0);
    ::setenv("ROS_MASTER_URI", uri.c_str(), 1);
    ::setenv("ROS_LOG_DIR", (dir / "ros_log").c_str(), 1);
    // Started from `cwd`, as a shell there would (PWD too).
    if (!cwd.empty() && (::chdir(cwd.c_str()) != 0 || ::setenv("PWD", cwd.c_str(), 1) != 0)) {
      ::_exit(125);
    }
    // One file description for both streams, so that neither writes over
    // the other's lines.
    if (!std::freopen(log.c_str(), "w", stdout) || ::dup2(STDOUT_FILENO, STDERR_FILENO) < 0) {
      ::_exit(126);
    }
    ::execvp(program.c_str(), argv.data());
    ::_exit(127);
  }
  ::setpgid(pid, pid);  // also here: no race with a signal sent at once
  return pid;
}

// Waits up to timeout_s of wall time for a launch started by startRoslaunch
// to end by itself (`status`: waitpid's). One that does not is ended
// (SIGINT to its group, SIGKILL 5 s later) and false returned. (A guard,
// not a timing assertion.)
inline bool waitForLaunch(pid_t pid, double timeout_s, int& status) {
  const auto t0 = std::chrono::steady_clock::now();
  while (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < timeout_s) {
    if (::waitpid(pid, &status, WNOHANG) == pid) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ::kill(-pid, SIGINT);
  std::this_thread::sleep_for(std::chrono::seconds(5));
  ::kill(-pid, SIGKILL);
  ::waitpid(pid, &status, 0);
  return false;
}

}  // namespace cws_ros_test
