// Helpers shared by the rostests of the winding cell.
#pragma once

#include <ros/ros.h>

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

}  // namespace cws_ros_test
