// The markers' common style, shared by the bridge's files (bridge.cpp,
// bridge_overlay.cpp): points, colours, the force colour scale and a
// marker's header. Internal to the ROS layer.
#pragma once

#include <geometry_msgs/Point.h>
#include <ros/time.h>
#include <std_msgs/ColorRGBA.h>
#include <visualization_msgs/Marker.h>

#include <Eigen/Core>
#include <algorithm>
#include <string>

namespace cws_ros {
namespace marker_style {

inline geometry_msgs::Point point(const Eigen::Vector3d& p) {
  geometry_msgs::Point m;
  m.x = p.x();
  m.y = p.y();
  m.z = p.z();
  return m;
}

inline std_msgs::ColorRGBA color(double r, double g, double b, double a = 1.0) {
  std_msgs::ColorRGBA c;
  c.r = static_cast<float>(r);
  c.g = static_cast<float>(g);
  c.b = static_cast<float>(b);
  c.a = static_cast<float>(a);
  return c;
}

// Blue (0) -> green -> red (1).
inline std_msgs::ColorRGBA heat(double s) {
  s = std::clamp(s, 0.0, 1.0);
  return s < 0.5 ? color(0.0, 2.0 * s, 1.0 - 2.0 * s) : color(2.0 * s - 1.0, 2.0 - 2.0 * s, 0.0);
}

// A marker with its header, namespace, id, type and ADD set.
inline visualization_msgs::Marker marker(const ros::Time& stamp, const std::string& frame,
                                         const char* ns, int id, int type) {
  visualization_msgs::Marker k;
  k.header.stamp = stamp;
  k.header.frame_id = frame;
  k.ns = ns;
  k.id = id;
  k.type = type;
  k.action = visualization_msgs::Marker::ADD;
  k.pose.orientation.w = 1.0;
  return k;
}

}  // namespace marker_style
}  // namespace cws_ros
