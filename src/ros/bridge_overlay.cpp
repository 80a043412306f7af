// The bridge's overlay markers for rviz (bridge.hpp, toOverlayMarkers): the
// cell's figures as text beside the core, the bulge marked by an arrow and
// its height, and the wound wire's profile with the stand-off magnified.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "coil_winding_sim/ros/bridge.hpp"
#include "marker_style.hpp"

namespace cws_ros {

using namespace marker_style;

namespace {

std::string format(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

// The outward direction from the core axis to p_core, in the core's xy
// plane (x when p_core lies on the axis).
Eigen::Vector3d outward(const Eigen::Vector3d& p_core) {
  const Eigen::Vector3d r(p_core.x(), p_core.y(), 0.0);
  return r.norm() > 1e-12 ? Eigen::Vector3d(r / r.norm()) : Eigen::Vector3d::UnitX();
}

}  // namespace

visualization_msgs::MarkerArray toOverlayMarkers(const cws::Simulation& sim, const ros::Time& stamp,
                                                 const Frames& frames, const Overlay& o) {
  visualization_msgs::MarkerArray out;
  const cws::WireModel& m = sim.model();
  const cws::RotatingCore* core = m.core();
  const cws::BulgeReport b = cws::headlineBulging(m, sim.scene());
  const bool coil = sim.scene().physics.wire_contact;

  // The figures beside the core, a marker per line (rviz spaces the lines
  // of one text marker far apart), top down along world -y: in the package's
  // rviz view (looking down the core axis, world +y up), up and to the left
  // of the core. World frame: the text does not turn with the core.
  std::vector<std::string> lines;
  lines.push_back(o.state);
  lines.push_back("t = " + format("%.4f", sim.time()) + " s, " + format("%.3f", sim.coreTurns()) +
                  " turns");
  // (A cell that does not wind has no pace to show: its factor is 0.)
  const std::string target = o.pace.target_real_time_factor > 0.0
                                 ? format("%.3g", o.pace.target_real_time_factor)
                                 : std::string("as fast as possible");
  lines.push_back(o.winding ? "real-time factor " + format("%.3g", o.pace.real_time_factor) +
                                  " (target " + target +
                                  (o.pace.keeping_pace ? ", on pace)" : ", BEHIND)")
                            : "real-time factor - (not winding; target " + target + ")");
  lines.push_back(m.supply() ? "tension " + format("%.4g", o.tension_setpoint_N) + " N set, " +
                                   format("%.4g", m.portAxialForce()) + " N at the port"
                             : std::string("no supply"));
  // (A coil's bulging is above its layers; their build-up beside it.)
  lines.push_back("bulging " + (b.valid ? format("%.3f", 1e3 * b.height_m) + " mm" : "-") +
                  (coil && b.valid
                       ? ", layers built up " + format("%.3f", 1e3 * b.build_up_m) + " mm"
                       : std::string()));
  lines.push_back("wire colour: force " + format("%.3g", o.force_min_N) + " N blue to " +
                  format("%.3g", o.force_max_N) + " N red");
  if (o.profile_magnification > 0.0 && b.valid) {
    lines.push_back("yellow: wound profile, stand-off x" + format("%g", o.profile_magnification));
  }
  // (The layers' legend in two short lines, 4 mm further from the core:
  // as one line, centred as every line is, it ran into the coil seen from
  // the side.)
  const std::size_t legend = lines.size();
  if (coil) {
    lines.push_back(o.enamel_risk ? "enamel: blue within half its limits, red at one, magenta past"
                                  : "layers: blue 1, orange 2, red 3, brown 4+");
    lines.push_back("marks: red overlap, yellow after a gap");
  }
  // Lines step down along world -y and along the core axis at once, so
  // that they stand apart both looking down the axis (winding_cell.rviz)
  // and from the side (coil.rviz). With the legend, the block starts 5.5
  // mm higher up the axis, so that its last line stays above the port seen
  // from the side (looking down the axis, that brings the block closer and
  // larger: without the legend it stays where it was).
  const Eigen::Vector3d axis = core ? core->axisWorld() : Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d top = (core ? core->originWorld() : Eigen::Vector3d::Zero()) +
                              Eigen::Vector3d(-0.020, 0.0150, 0.0) + (coil ? 0.0155 : 0.010) * axis;
  const Eigen::Vector3d step = Eigen::Vector3d(0.0, -0.0014, 0.0) - 0.0016 * axis;
  const Eigen::Vector3d legend_offset = Eigen::Vector3d(-0.004, 0.0, 0.0) + 0.001 * axis;
  lines.resize(9);  // a fixed count: no stale line stays behind
  for (std::size_t k = 0; k < lines.size(); ++k) {
    visualization_msgs::Marker text =
        marker(stamp, frames.world, "cell_status", static_cast<int>(k),
               visualization_msgs::Marker::TEXT_VIEW_FACING);
    text.pose.position = point(top + static_cast<double>(k) * step +
                               (k >= legend ? legend_offset : Eigen::Vector3d::Zero()));
    text.scale.z = 0.0009;  // text height [m]
    text.color = k == 0 ? color(1.0, 1.0, 0.6) : color(0.95, 0.95, 0.95);
    text.text = lines[k];
    // (An unused line: deleted, not an empty text, which rviz flags.)
    if (text.text.empty()) text.action = visualization_msgs::Marker::DELETE;
    out.markers.push_back(text);
  }

  // The bulge: an arrow from outside onto the point, and its height.
  visualization_msgs::Marker arrow =
      marker(stamp, frames.core, "bulge", 0, visualization_msgs::Marker::ARROW);
  visualization_msgs::Marker label =
      marker(stamp, frames.core, "bulge", 1, visualization_msgs::Marker::TEXT_VIEW_FACING);
  if (core && b.valid && b.height_m > 0.0) {
    const Eigen::Vector3d dir = outward(b.p_core);
    arrow.points = {point(b.p_core + 0.006 * dir), point(b.p_core + 0.0008 * dir)};
    arrow.scale.x = 0.0004;  // shaft diameter [m]
    arrow.scale.y = 0.0010;  // head diameter [m]
    arrow.scale.z = 0.0015;  // head length [m]
    arrow.color = color(1.0, 0.2, 0.8);
    label.pose.position = point(b.p_core + 0.0085 * dir);
    label.scale.z = 0.0012;
    label.color = color(1.0, 0.2, 0.8);
    label.text = "bulge " + format("%.3f", 1e3 * b.height_m) + " mm";
  } else {
    arrow.action = label.action = visualization_msgs::Marker::DELETE;
  }
  out.markers.push_back(arrow);
  out.markers.push_back(label);

  // The wound wire's profile, its stand-off magnified outward (core frame).
  visualization_msgs::Marker profile =
      marker(stamp, frames.core, "profile", 0, visualization_msgs::Marker::LINE_STRIP);
  if (core && b.valid && o.profile_magnification > 0.0 && b.wound_points > 1) {
    profile.scale.x = 0.0003;
    profile.color = color(1.0, 1.0, 0.3);
    for (int i = 0; i < b.wound_points && i < m.wirePoints(); ++i) {
      const Eigen::Vector3d p = cws::wirePointCore(m, i);
      profile.points.push_back(
          point(p + (o.profile_magnification - 1.0) * cws::standOff(m, i) * outward(p)));
    }
  } else {
    profile.action = visualization_msgs::Marker::DELETE;
  }
  out.markers.push_back(profile);
  return out;
}

}  // namespace cws_ros
