// winding_cell: the simulated winding cell as a ROS node (winding_cell.hpp).
#include <ros/ros.h>

#include <cstring>
#include <memory>

#include "coil_winding_sim/ros/node_options.hpp"
#include "coil_winding_sim/ros/snapshot_reader.hpp"
#include "coil_winding_sim/ros/winding_cell.hpp"

#ifndef CWS_DEFAULT_SCENE
#define CWS_DEFAULT_SCENE ""
#endif

int main(int argc, char** argv) {
  // The snapshot reader process of ~restore (cws_ros::readSnapshotBagIsolated).
  if (argc == 3 && std::strcmp(argv[1], cws_ros::kReadSnapshotArg) == 0) {
    return cws_ros::snapshotReaderMain(argv[2], cws_ros::kSnapshotReaderFd);
  }
  ros::init(argc, argv, "winding_cell");
  ros::NodeHandle nh, pnh("~");
  std::unique_ptr<cws_ros::WindingCell> cell;
  try {
    cws_ros::NodeOptions options = cws_ros::readNodeOptions(pnh, CWS_DEFAULT_SCENE);
    cws_ros::validateNodeOptions(options, ros::Time::isSimTime());
    // This executable reads snapshots too; the link of the process itself
    // still works after a rebuild replaced the file.
    cell = std::make_unique<cws_ros::WindingCell>(nh, pnh, options, "/proc/self/exe");
  } catch (const std::exception& e) {
    ROS_FATAL("winding_cell: %s", e.what());
    return 2;
  }
  ros::AsyncSpinner spinner(2);
  spinner.start();
  cell->run();
  spinner.stop();
  return 0;
}
