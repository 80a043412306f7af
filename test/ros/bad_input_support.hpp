// Shared by the bad-input rostest (test_bad_input.cpp, test_bad_input_services.cpp):
// what the test sees of the node, and calls of its topics and services.
#pragma once

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <rosgraph_msgs/Log.h>
#include <std_msgs/String.h>
#include <std_srvs/SetBool.h>
#include <std_srvs/Trigger.h>
#include <topic_tools/shape_shifter.h>
#include <unistd.h>
#include <visualization_msgs/MarkerArray.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "coil_winding_sim/CoreSpeedSetpoint.h"
#include "coil_winding_sim/Restore.h"
#include "coil_winding_sim/RunUntil.h"
#include "coil_winding_sim/SimulationSnapshot.h"
#include "coil_winding_sim/Snapshot.h"
#include "coil_winding_sim/WindingMetrics.h"
#include "coil_winding_sim/ros/snapshot_bag.hpp"
#include "ros_test_support.hpp"

namespace fs = std::filesystem;
using coil_winding_sim::WindingMetrics;

namespace bad_input {

constexpr double kTargetRtf = 0.01;  // bad_input.test: real_time_factor
inline const char* const kSnapshotTopic = "/coil_winding_sim/snapshot";

// What the test sees of the node: metrics (with their wall time of
// arrival), DELETEALL markers (sent on reset and restore only) and the
// node's log.
class Observer {
 public:
  struct Sample {
    double wall;  // [s]
    WindingMetrics m;
  };

  Observer() {
    ros::NodeHandle nh;
    metrics_sub_ = nh.subscribe("winding_metrics", 100, &Observer::onMetrics, this);
    markers_sub_ = nh.subscribe("wire_markers", 10, &Observer::onMarkers, this);
    log_sub_ = nh.subscribe("/rosout", 1000, &Observer::onLog, this);
  }

  std::vector<Sample> samples() {
    std::lock_guard<std::mutex> l(mutex_);
    return samples_;
  }
  std::size_t count() {
    std::lock_guard<std::mutex> l(mutex_);
    return samples_.size();
  }
  WindingMetrics latest() {
    std::lock_guard<std::mutex> l(mutex_);
    return samples_.empty() ? WindingMetrics() : samples_.back().m;
  }
  int deleteAlls() {
    std::lock_guard<std::mutex> l(mutex_);
    return delete_all_;
  }
  // The number of lines the node logged that hold all of `parts`.
  int logged(const std::vector<std::string>& parts) {
    std::lock_guard<std::mutex> l(mutex_);
    int n = 0;
    for (const std::string& line : log_) {
      bool all = true;
      for (const std::string& p : parts) all = all && line.find(p) != std::string::npos;
      if (all) ++n;
    }
    return n;
  }

 private:
  void onMetrics(const WindingMetrics::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex_);
    samples_.push_back({ros::WallTime::now().toSec(), *m});
  }
  void onMarkers(const visualization_msgs::MarkerArray::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex_);
    for (const auto& k : m->markers) {
      if (k.action == visualization_msgs::Marker::DELETEALL) ++delete_all_;
    }
  }
  void onLog(const rosgraph_msgs::Log::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex_);
    if (m->name == "/winding_cell") log_.push_back(m->msg);
  }

  std::mutex mutex_;
  std::vector<Sample> samples_;
  int delete_all_ = 0;
  std::vector<std::string> log_;
  ros::Subscriber metrics_sub_, markers_sub_, log_sub_;
};

inline Observer* observer = nullptr;
inline ros::Publisher* speed_pub = nullptr;

using cws_ros_test::waitFor;

// The metrics after `n` more messages (20 Hz; 1 Hz while paused): a state
// published after this call, with time for a DELETEALL marker (10 Hz) to
// arrive.
inline WindingMetrics fresh(std::size_t n = 4) {
  const std::size_t seen = observer->count();
  EXPECT_TRUE(waitFor([&] { return observer->count() >= seen + n; }, 10.0))
      << "no metrics from winding_cell";
  return observer->latest();
}

inline double speedSetpoint() { return observer->latest().core_angular_velocity_setpoint; }

// True if the speed setpoint in the metrics stays `w` for `seconds`.
inline bool speedStays(double w, double seconds) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::WallTime::now() < end) {
    if (speedSetpoint() != w) return false;
    ros::WallDuration(0.01).sleep();
  }
  return speedSetpoint() == w;
}

inline void publishSpeed(double w, const ros::Time& stamp) {
  coil_winding_sim::CoreSpeedSetpoint sp;
  sp.header.stamp = stamp;
  sp.angular_velocity = w;
  speed_pub->publish(sp);
}

// A service call that is tried up to three times when roscpp reports a
// failure of the call itself (not of the service): roscpp's non-persistent
// calls fail sporadically, more often when several run at once (seen here
// about once in a few hundred concurrent calls; ros/ros_comm#1976). A dead
// node fails all three.
template <class Service>
inline bool call(const std::string& name, Service& srv) {
  for (int attempt = 1; attempt <= 3; ++attempt) {
    if (ros::service::call(name, srv)) return true;
    std::printf("call of %s failed in roscpp (attempt %d of 3)\n", name.c_str(), attempt);
    ros::WallDuration(0.1).sleep();
  }
  return false;
}

inline bool pause(bool on) {
  std_srvs::SetBool s;
  s.request.data = on;
  return call("/winding_cell/pause", s) && s.response.success;
}

// Resumes the run when a test ends, passed or not.
struct Resume {
  ~Resume() { pause(false); }
};

inline coil_winding_sim::Snapshot::Response snapshot(const std::string& path) {
  coil_winding_sim::Snapshot s;
  s.request.path = path;
  EXPECT_TRUE(call("/winding_cell/snapshot", s)) << path;
  return s.response;
}

inline coil_winding_sim::Restore::Response restore(const std::string& path) {
  coil_winding_sim::Restore r;
  r.request.path = path;
  EXPECT_TRUE(call("/winding_cell/restore", r)) << path;
  return r.response;
}

inline std_srvs::Trigger::Response reset() {
  std_srvs::Trigger t;
  EXPECT_TRUE(call("/winding_cell/reset", t));
  return t.response;
}

// A file name of this test in /tmp.
inline std::string tmpPath(const std::string& name) {
  return "/tmp/cws_bad_input_" + std::to_string(::getpid()) + "_" + name;
}

inline std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

inline void writeFile(const std::string& path, const std::string& data) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << data;
}

// Checks that the run went on from `before` untouched: the simulated time
// advanced, no step was lost, no reset or restore happened (those send a
// DELETEALL) and the node still runs.
inline void expectRunWentOn(const WindingMetrics& before, int delete_all_before,
                            const std::string& what) {
  const WindingMetrics after = fresh();
  EXPECT_GT(after.sim_time, before.sim_time) << what << ": the simulated time did not advance";
  EXPECT_GE(after.steps_accepted, before.steps_accepted) << what << ": steps were lost";
  EXPECT_EQ(observer->deleteAlls(), delete_all_before) << what << ": the run was replaced";
}

inline std::string stampText(const ros::Time& t) {
  char text[64];
  std::snprintf(text, sizeof text, "%.6f", t.toSec());
  return text;
}
}  // namespace bad_input
