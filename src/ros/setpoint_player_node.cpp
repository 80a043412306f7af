// setpoint_player: plays a core-speed and tension setpoint profile from YAML,
// as a machine controller would (for demos and tests).
//
//   ~profile   path of the profile YAML:
//                rate: 50            # publish rate [Hz]
//                keyframes:          # piecewise linear in ROS time since start
//                  - {time: 0.0, core_speed_rpm: 0, tension: 30}   # [s], [rpm], [N]
//                  - ...
//   publishes core_speed_setpoint (rad/s) and tension_setpoint (N).
// With use_sim_time the profile follows the simulation's /clock.
#include <ros/ros.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <string>
#include <vector>

#include "coil_winding_sim/CoreSpeedSetpoint.h"
#include "coil_winding_sim/TensionSetpoint.h"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace {
struct Keyframe {
  double time, speed_rad_s, tension_N;
};

std::vector<Keyframe> loadProfile(const std::string& path, double& rate) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error("cannot read profile '" + path + "': " + e.what());
  }
  rate = root["rate"] ? root["rate"].as<double>() : 50.0;
  if (!(rate > 0.0) || !std::isfinite(rate)) throw std::runtime_error("profile rate must be > 0");
  std::vector<Keyframe> k;
  const YAML::Node list = root["keyframes"];
  if (!list || !list.IsSequence() || list.size() == 0) {
    throw std::runtime_error("profile '" + path + "' needs a non-empty list 'keyframes'");
  }
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string key = "keyframes[" + std::to_string(i) + "]";
    try {
      Keyframe f{list[i]["time"].as<double>(),
                 cws::rpmToRadPerSec(list[i]["core_speed_rpm"].as<double>()),
                 list[i]["tension"].as<double>()};
      if (!std::isfinite(f.time) || (!k.empty() && !(f.time > k.back().time))) {
        throw std::runtime_error(key + ".time must increase");
      }
      k.push_back(f);
    } catch (const YAML::Exception&) {
      throw std::runtime_error(key + " needs numbers time, core_speed_rpm, tension");
    }
  }
  return k;
}

Keyframe at(const std::vector<Keyframe>& k, double t) {
  if (t <= k.front().time) return k.front();
  for (std::size_t i = 1; i < k.size(); ++i) {
    if (t <= k[i].time) {
      const double s = (t - k[i - 1].time) / (k[i].time - k[i - 1].time);
      return {t, (1 - s) * k[i - 1].speed_rad_s + s * k[i].speed_rad_s,
              (1 - s) * k[i - 1].tension_N + s * k[i].tension_N};
    }
  }
  return k.back();
}
}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "setpoint_player");
  ros::NodeHandle nh, pnh("~");
  std::string path;
  if (!pnh.getParam("profile", path)) {
    ROS_FATAL("setpoint_player: parameter ~profile (a YAML file) is required");
    return 2;
  }
  double rate = 50.0;
  std::vector<Keyframe> profile;
  try {
    profile = loadProfile(path, rate);
  } catch (const std::exception& e) {
    ROS_FATAL("setpoint_player: %s", e.what());
    return 2;
  }
  auto speed_pub = nh.advertise<coil_winding_sim::CoreSpeedSetpoint>("core_speed_setpoint", 10);
  auto tension_pub = nh.advertise<coil_winding_sim::TensionSetpoint>("tension_setpoint", 10);
  // Wait for a valid time (sim time starts with the first /clock).
  while (ros::ok() && ros::Time::now().isZero()) ros::WallDuration(0.01).sleep();
  const ros::Time start = ros::Time::now();
  ros::Rate loop(rate);
  while (ros::ok()) {
    const ros::Time now = ros::Time::now();
    const Keyframe k = at(profile, (now - start).toSec());
    coil_winding_sim::CoreSpeedSetpoint s;
    s.header.stamp = now;
    s.angular_velocity = k.speed_rad_s;
    speed_pub.publish(s);
    coil_winding_sim::TensionSetpoint f;
    f.header.stamp = now;
    f.tension = k.tension_N;
    tension_pub.publish(f);
    ros::spinOnce();
    loop.sleep();
  }
  return 0;
}
