// Helpers shared by the rostests of the winding cell.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <ros/ros.h>
#include <sys/socket.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

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

}  // namespace cws_ros_test
