#include "cell_urdf.hpp"

#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "coil_winding_sim/core/machine/rotating_core.hpp"

namespace cws_tools {

namespace {

std::string vec3(double a, double b, double c) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g", a + 0.0, b + 0.0, c + 0.0);  // no "-0"
  return buf;
}

// A prismatic joint of the port along one world axis.
void portJoint(std::ostringstream& u, const char* name, const std::string& parent,
               const std::string& child, const char* axis) {
  u << "  <joint name=\"" << name << "\" type=\"prismatic\">\n"
    << "    <parent link=\"" << parent << "\"/>\n    <child link=\"" << child << "\"/>\n"
    << "    <axis xyz=\"" << axis << "\"/>\n"
    << "    <limit lower=\"-10\" upper=\"10\" effort=\"0\" velocity=\"100\"/>\n  </joint>\n";
}

}  // namespace

std::string cellUrdf(const cws::Scene& scene, const std::string& frame_prefix) {
  // The cell's own links under the prefix (as the node names its frames,
  // ~frame_prefix); world is shared.
  const std::string p = frame_prefix.empty() ? "" : frame_prefix + "/";
  // The core's frame at rest: its origin and orientation (z: the axis), as
  // the simulation sets them up.
  const cws::RotatingCore core(scene.core, 0.0);
  const Eigen::Vector3d o = core.originWorld();
  const Eigen::Matrix3d r = core.quaternionWorldCore(0.0).toRotationMatrix();
  // URDF's rpy: R = Rz(yaw) Ry(pitch) Rx(roll).
  const Eigen::Vector3d ypr = r.eulerAngles(2, 1, 0);
  std::ostringstream u;
  u << "<?xml version=\"1.0\"?>\n"
    << "<!-- The simulated winding cell (coil_winding_sim, wire_sim urdf): the core turns\n"
    << "     on the continuous joint spindle about its z axis (the scene's core axis),\n"
    << "     the supply port moves on port_x, port_y, port_z along the world axes [m];\n"
    << "     a dancer's pulley travels on the prismatic joint dancer (+: stores wire).\n"
    << "     The joints' positions are the node's joint_states. -->\n"
    << "<robot name=\"winding_cell\">\n"
    << "  <link name=\"world\"/>\n  <link name=\"" << p << "core\"/>\n"
    << "  <joint name=\"spindle\" type=\"continuous\">\n"
    << "    <parent link=\"world\"/>\n    <child link=\"" << p << "core\"/>\n"
    << "    <origin xyz=\"" << vec3(o.x(), o.y(), o.z()) << "\" rpy=\""
    << vec3(ypr(2), ypr(1), ypr(0)) << "\"/>\n"
    << "    <axis xyz=\"0 0 1\"/>\n  </joint>\n";
  if (scene.physics.supply) {
    u << "  <link name=\"" << p << "port_x_link\"/>\n  <link name=\"" << p << "port_y_link\"/>\n"
      << "  <link name=\"" << p << "supply_port\"/>\n";
    portJoint(u, "port_x", "world", p + "port_x_link", "1 0 0");
    portJoint(u, "port_y", p + "port_x_link", p + "port_y_link", "0 1 0");
    portJoint(u, "port_z", p + "port_y_link", p + "supply_port", "0 0 1");
    if (scene.supply.tensioner.kind == "dancer") {
      // The dancer's pulley, drawn 0.1 m behind the port at the start (away
      // from the core's axis), travelling along that line: + stores wire.
      const Eigen::Vector3d port = scene.supply.port_position_world;
      Eigen::Vector3d away = port - o;
      away -= away.dot(scene.core.axis_world.normalized()) * scene.core.axis_world.normalized();
      away = away.norm() > 0.0 ? away.normalized() : Eigen::Vector3d::UnitX();
      const Eigen::Vector3d at = port + 0.1 * away;
      u << "  <link name=\"" << p << "dancer_pulley\"/>\n"
        << "  <joint name=\"dancer\" type=\"prismatic\">\n"
        << "    <parent link=\"world\"/>\n    <child link=\"" << p << "dancer_pulley\"/>\n"
        << "    <origin xyz=\"" << vec3(at.x(), at.y(), at.z()) << "\" rpy=\"0 0 0\"/>\n"
        << "    <axis xyz=\"" << vec3(away.x(), away.y(), away.z()) << "\"/>\n"
        << "    <limit lower=\"-1\" upper=\"1\" effort=\"0\" velocity=\"100\"/>\n  </joint>\n";
    }
  }
  u << "</robot>\n";
  return u.str();
}

int urdfMain(const std::vector<std::string>& args, const std::string& default_scene) {
  std::string scene_path = default_scene;
  std::vector<std::string> overrides;
  bool world_on_error = false;
  std::string frame_prefix;
  for (std::size_t i = 1; i < args.size(); ++i) {
    const std::string& opt = args[i];
    if (i + 1 >= args.size()) {
      std::cerr << "wire_sim: urdf: " << opt << " needs a value\n";
      return 2;
    }
    const std::string& value = args[++i];
    if (opt == "--scene") {
      scene_path = value;
    } else if (opt == "--on-error") {
      if (value != "fail" && value != "world") {
        std::cerr << "wire_sim: urdf: --on-error takes fail or world, not '" << value << "'\n";
        return 2;
      }
      world_on_error = value == "world";
    } else if (opt == "--frame-prefix") {
      // (As the node's ~frame_prefix: a trailing '/' is dropped.)
      frame_prefix = value;
      while (!frame_prefix.empty() && frame_prefix.back() == '/') frame_prefix.pop_back();
    } else if (opt == "--set") {
      overrides.push_back(value);
    } else if (opt == "--overrides") {
      // A launch file's list, e.g. "[process.turns=2, core.start_at_speed=true]".
      try {
        const YAML::Node list = YAML::Load(value);
        if (!list.IsNull() && !list.IsSequence()) throw YAML::Exception({}, "not a list");
        for (const YAML::Node& item : list) overrides.push_back(item.as<std::string>());
      } catch (const YAML::Exception&) {
        std::cerr << "wire_sim: urdf: --overrides '" << value
                  << "' is not a YAML list of key.path=value\n";
        return 2;
      }
    } else {
      std::cerr << "wire_sim: urdf: unknown option '" << opt
                << "' (it takes --scene, --set, --overrides, --on-error, --frame-prefix)\n";
      return 2;
    }
  }
  // The cell's frames do not depend on the job's length: storage for the
  // most points a scene may have, so that a long job is not checked here.
  overrides.push_back("supply.max_points=" + std::to_string(cws::kMaxScenePoints));
  try {
    std::cout << cellUrdf(cws::loadScene(scene_path, overrides), frame_prefix);
  } catch (const cws::SceneError& e) {
    // --on-error world (the cell's launch file): a URDF of the world link
    // alone, so that roslaunch goes on to the node, which names the error
    // in one line.
    if (world_on_error) {
      std::cout
          << "<?xml version=\"1.0\"?>\n<robot name=\"winding_cell\">\n  <link name=\"world\"/>\n"
             "</robot>\n";
      return 0;
    }
    std::cerr << "wire_sim: bad scene: " << e.what() << "\n";
    return 2;
  }
  return 0;
}

}  // namespace cws_tools
