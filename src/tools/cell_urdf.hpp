// The winding cell as a URDF (wire_sim urdf): the core on the continuous
// joint `spindle` about its axis, the supply port on three prismatic joints
// `port_x`, `port_y`, `port_z` along the world axes, and a dancer's pulley
// (supply.tensioner.kind dancer) on the prismatic joint `dancer`. With the node's
// joint_states, robot_state_publisher gives the same frames as the node's
// own TF (world -> core, world -> supply_port), and a machine's URDF can
// take the cell's links and joints under a link of its own.
#pragma once

#include <string>
#include <vector>

#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws_tools {

// The URDF of `scene`'s cell (frame names world, core, supply_port; with a
// prefix P: world, P/core, P/supply_port).
std::string cellUrdf(const cws::Scene& scene, const std::string& frame_prefix = "");

// wire_sim urdf [--scene FILE] [--set key=value ...] [--overrides "[k=v, ...]"]
// [--frame-prefix P]:
// the URDF on stdout (--overrides takes a launch file's YAML list). Returns
// the exit code (2: bad arguments or scene, named on stderr).
int urdfMain(const std::vector<std::string>& args, const std::string& default_scene);

}  // namespace cws_tools
