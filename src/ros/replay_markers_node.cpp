// replay_markers: the wire's markers again from a recording. It reads
// wire_state_compact (as `rosbag play` sends it) and publishes the wire as
// the cell draws it on wire_markers: line strips coloured by axial force,
// 0 N blue to ~force_color_max red. The cell records no markers.
#include <ros/ros.h>

#include <string>

#include "coil_winding_sim/WireStateCompact.h"
#include "coil_winding_sim/ros/bridge.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, "replay_markers");
  ros::NodeHandle nh, pnh("~");
  double force_max_N = 60.0;
  pnh.param("force_color_max", force_max_N, force_max_N);
  if (!(force_max_N > 0.0)) {
    ROS_FATAL("replay_markers: ~force_color_max must be positive [N], not %g", force_max_N);
    return 2;
  }
  ros::Publisher pub = nh.advertise<visualization_msgs::MarkerArray>("wire_markers", 2, true);
  cws_ros::CompactWire wire;
  bool waiting = false;
  ros::Subscriber sub = nh.subscribe<coil_winding_sim::WireStateCompact>(
      "wire_state_compact", 20, [&](const coil_winding_sim::WireStateCompact::ConstPtr& msg) {
        std::string why;
        if (!wire.add(*msg, why)) {
          if (!waiting) ROS_INFO("replay_markers: skipping a message: %s", why.c_str());
          waiting = true;
          return;
        }
        waiting = false;
        pub.publish(wire.markers(msg->header.stamp, force_max_N));
      });
  ros::spin();
  return 0;
}
