// The bridge's message and TF conversions (bridge.hpp).
#include "coil_winding_sim/ros/bridge.hpp"

#include <sensor_msgs/point_cloud2_iterator.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "coil_winding_sim/core/run/coil_report.hpp"
#include "coil_winding_sim/core/run/output.hpp"
#include "coil_winding_sim/core/run/quality_report.hpp"
#include "coil_winding_sim/core/scene/core_geometry.hpp"
#include "marker_style.hpp"

namespace cws_ros {

const char* const kSpindleJoint = "spindle";

bool coilOf(const cws::Simulation& sim, cws::CoilReport& out) {
  if (!sim.scene().physics.wire_contact) return false;
  out = cws::reportCoil(sim.model(), sim.scene());
  return out.valid;
}

namespace {
using namespace marker_style;

// Layer 1 blue, 2 orange, 3 red, 4 and above brown.
std_msgs::ColorRGBA layerColor(int layer) {
  switch (layer) {
    case 1:
      return color(0.62, 0.79, 0.88);
    case 2:
      return color(0.99, 0.68, 0.42);
    case 3:
      return color(0.90, 0.33, 0.05);
    default:
      return color(0.65, 0.21, 0.01);
  }
}

// Pale blue below half the enamel's limits, through yellow at 3/4 to red
// at a limit, magenta past one (apart from the force colours' greens).
std_msgs::ColorRGBA enamelRiskColor(double risk) {
  if (risk > 1.0) return color(0.9, 0.0, 0.9);
  const double f = std::clamp(2.0 * risk - 1.0, 0.0, 1.0);  // 0 at half, 1 at the limit
  if (f < 0.5) return color(0.55 + 0.9 * f, 0.75 + 0.2 * f, 0.95 - 1.9 * f);  // to yellow
  return color(1.0, 0.85 * (2.0 - 2.0 * f), 0.0);                             // to red
}

// The wound wire as spheres coloured by layer, or by the share of its
// enamel's limits used ("coil_layers"), and its defects ("coil_defects"):
// red around points of an overlapping turn that lie above the traverse's
// plan, yellow around the turns after a gap.
void addCoilMarkers(const cws::Simulation& sim, const cws::CoilReport& r, const ros::Time& stamp,
                    const Frames& frames, bool enamel_risk, visualization_msgs::MarkerArray& out) {
  const cws::WireModel& m = sim.model();
  const double diameter = 2.0 * m.constants().radius;
  visualization_msgs::Marker layers =
      marker(stamp, frames.world, "coil_layers", 0, visualization_msgs::Marker::SPHERE_LIST);
  // (A little wider than the wire's strips, which they would otherwise
  // flicker through.)
  layers.scale.x = layers.scale.y = layers.scale.z = 1.08 * diameter;
  visualization_msgs::Marker defects =
      marker(stamp, frames.world, "coil_defects", 0, visualization_msgs::Marker::SPHERE_LIST);
  defects.scale.x = defects.scale.y = defects.scale.z = 1.6 * diameter;
  // (The live wire's turns: retired wire lies buried under them.)
  for (const cws::TurnReport& t : r.turns) {
    for (int i = std::max(t.first_point, m.retiredPoints()); i < t.first_point + t.points; ++i) {
      const geometry_msgs::Point p = point(cws::wirePoint(m, i).p_world);
      layers.points.push_back(p);
      layers.colors.push_back(enamel_risk ? enamelRiskColor(cws::enamelRisk(m, sim.scene(), i))
                                          : layerColor(r.point_layer[i]));
      if (t.overlap && r.point_layer[i] > t.planned_max) {
        defects.points.push_back(p);
        defects.colors.push_back(color(1.0, 0.0, 0.0, 0.6));
      } else if (t.gap_m > 0.0) {
        defects.points.push_back(p);
        defects.colors.push_back(color(1.0, 0.9, 0.0, 0.35));
      }
    }
  }
  out.markers.push_back(layers);
  // (An empty list would leave the last defects on screen: DELETE them.)
  if (defects.points.empty()) defects.action = visualization_msgs::Marker::DELETE;
  out.markers.push_back(defects);
}

}  // namespace

coil_winding_sim::WireState toWireState(const cws::Simulation& sim, const ros::Time& stamp,
                                        const Frames& frames) {
  const cws::WireModel& m = sim.model();
  const int n = m.wirePoints();
  coil_winding_sim::WireState msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = frames.world;
  msg.sim_time = sim.time();
  msg.positions.reserve(n);
  const bool core = m.core() && !sim.scene().core.cylinders.empty();
  for (int i = 0; i < n; ++i) {
    const cws::PointReport r = cws::wirePoint(m, i);
    msg.positions.push_back(point(r.p_world));
    msg.axial_force.push_back(r.axial_force_N);
    msg.curvature.push_back(r.curvature_1pm);
    msg.plastic_curvature.push_back(r.plastic_curvature_1pm);
    msg.twist.push_back(r.twist_rad_per_m);
    msg.stand_off.push_back(core ? cws::standOff(m, i) : std::numeric_limits<double>::quiet_NaN());
    msg.in_contact.push_back(r.in_contact);
    msg.stick.push_back(r.stick);
  }
  return msg;
}

coil_winding_sim::WindingMetrics toMetrics(const cws::Simulation& sim, const ros::Time& stamp,
                                           const Frames& frames, const Pace& pace) {
  const cws::WireModel& m = sim.model();
  coil_winding_sim::WindingMetrics msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = frames.world;
  msg.sim_time = sim.time();
  cws::CoilReport coil;
  const bool coil_valid = coilOf(sim, coil);
  const cws::BulgeReport b = cws::headlineBulging(m, sim.scene(), coil_valid ? &coil : nullptr);
  msg.bulging_height = b.valid ? b.height_m : std::numeric_limits<double>::quiet_NaN();
  msg.build_up_height = b.valid ? b.build_up_m : std::numeric_limits<double>::quiet_NaN();
  msg.bulging_index = b.valid ? b.index : -1;
  const int last = cws::lastInContact(m);
  msg.wound_length = last > 0 ? last * m.constants().segment_length : 0.0;
  msg.fed_length = m.fedLength();
  msg.core_turns = sim.coreTurns();
  msg.core_angular_velocity = m.core() ? m.core()->omega(sim.time()) : 0.0;
  msg.core_angular_velocity_setpoint = m.core() ? m.core()->command() : 0.0;
  msg.supply_tension = m.supply() ? m.supply()->tensionSetpoint() : 0.0;
  msg.port_axial_force = m.supply() ? m.portAxialForce() : 0.0;
  msg.real_time_factor = pace.real_time_factor;
  msg.target_real_time_factor = pace.target_real_time_factor;
  msg.keeping_pace = pace.keeping_pace;
  msg.steps_accepted = sim.stepper().counts().accepted;
  msg.steps_rejected = sim.stepper().counts().rejected;
  msg.step_size = sim.stepper().lastStep();
  msg.max_constraint_residual = m.maxConstraintResidual();
  msg.points = m.wirePoints();
  if (coil_valid) {
    msg.turns = coil.wound_turns();
    msg.turns_wound = coil.turns_wound;
    msg.layers = coil.layers;
    msg.gaps = coil.gaps;
    msg.largest_gap = coil.largest_gap_m;
    msg.first_gap_turn = coil.first_gap_turn;
    msg.overlaps = coil.overlaps;
    msg.first_overlap_turn = coil.first_overlap_turn;
    msg.bulging_per_layer = coil.bulging_per_layer_m;
  }
  return msg;
}

namespace {
// A coil's figures now, as a wind result and coil_done give them: the
// bulging and build-up, per layer, layers, gaps, overlaps and the summary.
template <class Msg>
void fillCoilFigures(const cws::Simulation& sim, Msg& m) {
  cws::CoilReport coil;
  const bool coil_valid = coilOf(sim, coil);
  const cws::BulgeReport b =
      cws::headlineBulging(sim.model(), sim.scene(), coil_valid ? &coil : nullptr);
  m.bulging_height = b.valid ? b.height_m : std::numeric_limits<double>::quiet_NaN();
  m.build_up_height = b.valid ? b.build_up_m : std::numeric_limits<double>::quiet_NaN();
  if (coil_valid) {
    m.bulging_per_layer = coil.bulging_per_layer_m;
    m.layers = coil.layers;
    m.gaps = coil.gaps;
    m.overlaps = coil.overlaps;
  }
  std::ostringstream summary;
  cws::writeSummaryJson(sim, summary);
  m.summary = summary.str();
}
}  // namespace

coil_winding_sim::CoilDone toCoilDone(const cws::Simulation& sim, const ros::Time& stamp,
                                      const Frames& frames, int coil_number) {
  coil_winding_sim::CoilDone d;
  d.header.stamp = stamp;
  d.header.frame_id = frames.world;
  d.coil = coil_number;
  d.duration = sim.time();
  d.core_turns = std::abs(sim.coreTurns());
  fillCoilFigures(sim, d);
  return d;
}

coil_winding_sim::WindResult toWindResult(const cws::Simulation& sim, double start_s, double turns,
                                          double wall_s) {
  coil_winding_sim::WindResult r;
  r.turns = turns;
  r.sim_time = sim.time();
  r.duration = sim.time() - start_s;
  r.wall_time = wall_s;
  r.real_time_factor = wall_s > 0.0 ? r.duration / wall_s : 0.0;
  fillCoilFigures(sim, r);
  return r;
}

coil_winding_sim::WindFeedback toWindFeedback(const cws::Simulation& sim, double start_s,
                                              double turns, const Pace& pace) {
  coil_winding_sim::WindFeedback f;
  f.turns = turns;
  f.sim_time = sim.time();
  f.duration = sim.time() - start_s;
  f.real_time_factor = pace.real_time_factor;
  f.keeping_pace = pace.keeping_pace;
  cws::CoilReport coil;
  if (coilOf(sim, coil)) f.bulging_per_layer = coil.bulging_per_layer_m;
  return f;
}

visualization_msgs::MarkerArray toMarkers(const cws::Simulation& sim, const ros::Time& stamp,
                                          const Frames& frames, double force_scale_N,
                                          std::size_t max_points_per_marker, int retired_from,
                                          bool enamel_risk) {
  visualization_msgs::MarkerArray out;
  const cws::WireModel& m = sim.model();
  const int n = m.wirePoints(), retired = m.retiredPoints();
  const double diameter = 2.0 * m.constants().radius;
  // The wire: consecutive strips share their end point.
  const std::size_t per = std::max<std::size_t>(2, max_points_per_marker);
  int id = 0;
  for (int start = 0; start < n - 1; start += static_cast<int>(per) - 1) {
    const int end = std::min(n, start + static_cast<int>(per));
    // Retired wire turns with the core: once in the core frame.
    const bool rigid = end <= retired;
    if (rigid && end - 1 < retired_from) {
      ++id;
      continue;
    }
    visualization_msgs::Marker w = marker(stamp, rigid ? frames.core : frames.world, "wire", id++,
                                          visualization_msgs::Marker::LINE_STRIP);
    w.scale.x = diameter;
    for (int i = start; i < end; ++i) {
      const cws::PointReport r = cws::wirePoint(m, i);
      w.points.push_back(point(rigid ? cws::wirePointCore(m, i) : r.p_world));
      w.colors.push_back(heat(r.axial_force_N / std::max(1e-9, force_scale_N)));
    }
    out.markers.push_back(w);
  }
  // The core: cylinders and faces in the core frame, 20 mm tall.
  if (m.core()) {
    const cws::CoreParams& core = sim.scene().core;
    const double height = 0.02;
    int cid = 0;
    for (const cws::CylinderParams& c : core.cylinders) {
      visualization_msgs::Marker k =
          marker(stamp, frames.core, "core", cid++, visualization_msgs::Marker::CYLINDER);
      k.pose.position.x = c.center_core.x();
      k.pose.position.y = c.center_core.y();
      k.scale.x = k.scale.y = 2.0 * c.radius;
      k.scale.z = height;
      k.color = color(0.55, 0.55, 0.6, 0.9);
      out.markers.push_back(k);
    }
    for (const cws::FaceParams& f : cws::coreFaces(core)) {
      visualization_msgs::Marker k =
          marker(stamp, frames.core, "core", cid++, visualization_msgs::Marker::CUBE);
      const Eigen::Vector2d d = f.to_core - f.from_core;
      const Eigen::Vector2d mid = 0.5 * (f.from_core + f.to_core);
      const Eigen::Vector2d in(-d.y() / d.norm(), d.x() / d.norm());  // left: inside
      k.pose.position.x = mid.x() + 0.5e-3 * in.x();
      k.pose.position.y = mid.y() + 0.5e-3 * in.y();
      const double yaw = std::atan2(d.y(), d.x());
      k.pose.orientation.z = std::sin(0.5 * yaw);
      k.pose.orientation.w = std::cos(0.5 * yaw);
      k.scale.x = d.norm();
      k.scale.y = 1e-3;
      k.scale.z = height;
      k.color = color(0.55, 0.55, 0.6, 0.9);
      out.markers.push_back(k);
    }
  }
  if (m.supply()) {
    visualization_msgs::Marker p =
        marker(stamp, frames.port, "supply_port", 0, visualization_msgs::Marker::SPHERE);
    p.scale.x = p.scale.y = p.scale.z = 3.0 * diameter;
    p.color = color(1.0, 0.8, 0.0, 0.8);
    out.markers.push_back(p);
  }
  cws::CoilReport coil;
  if (coilOf(sim, coil)) addCoilMarkers(sim, coil, stamp, frames, enamel_risk, out);
  return out;
}

visualization_msgs::MarkerArray deleteAllMarkers(const ros::Time& stamp, const Frames& frames) {
  visualization_msgs::MarkerArray out;
  visualization_msgs::Marker d;
  d.header.stamp = stamp;
  d.header.frame_id = frames.world;
  d.action = visualization_msgs::Marker::DELETEALL;
  out.markers.push_back(d);
  return out;
}

bool coreTransform(const cws::Simulation& sim, const ros::Time& stamp, const Frames& frames,
                   geometry_msgs::TransformStamped& out) {
  const cws::RotatingCore* core = sim.model().core();
  if (!core) return false;
  out = geometry_msgs::TransformStamped();
  out.header.stamp = stamp;
  out.header.frame_id = frames.world;
  out.child_frame_id = frames.core;
  out.transform.translation.x = core->originWorld().x();
  out.transform.translation.y = core->originWorld().y();
  out.transform.translation.z = core->originWorld().z();
  const Eigen::Quaterniond q = core->quaternionWorldCore(sim.time()).normalized();
  out.transform.rotation.w = q.w();
  out.transform.rotation.x = q.x();
  out.transform.rotation.y = q.y();
  out.transform.rotation.z = q.z();
  return true;
}

bool portTransform(const cws::Simulation& sim, const ros::Time& stamp, const Frames& frames,
                   geometry_msgs::TransformStamped& out) {
  const cws::Supply* supply = sim.model().supply();
  if (!supply) return false;
  const Eigen::Vector3d p = supply->port(sim.time()).p_world;
  out = geometry_msgs::TransformStamped();
  out.header.stamp = stamp;
  out.header.frame_id = frames.world;
  out.child_frame_id = frames.port;
  out.transform.translation.x = p.x();
  out.transform.translation.y = p.y();
  out.transform.translation.z = p.z();
  out.transform.rotation.w = 1.0;
  return true;
}

coil_winding_sim::ErrorEstimate toErrorEstimateMsg(const cws::ErrorEstimate& e, double sim_time_s,
                                                   int inputs, const std::string& failure,
                                                   const ros::Time& stamp) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  coil_winding_sim::ErrorEstimate m;
  m.header.stamp = stamp;
  m.sim_time = sim_time_s;
  m.inputs = inputs;
  m.failure = failure;
  const bool ok = failure.empty();
  m.refinement = e.refinement;
  m.shape_error = ok ? e.shape_error_rel_diameter : nan;
  m.bulging_error = ok && e.bulging_valid ? e.bulging_error_rel : nan;
  m.compute_time = ok ? e.wall_s : nan;
  m.refined_compute_time = ok ? e.refined_wall_s : nan;
  return m;
}

sensor_msgs::JointState toSpindleCommand(const cws::Simulation& sim, const ros::Time& stamp) {
  sensor_msgs::JointState msg;
  msg.header.stamp = stamp;
  msg.name = {kSpindleJoint};
  const cws::RotatingCore* core = sim.model().core();
  msg.velocity = {core ? core->command() : 0.0};
  return msg;
}

sensor_msgs::JointState toSpindleState(const cws::Simulation& sim, const ros::Time& stamp) {
  sensor_msgs::JointState msg;
  msg.header.stamp = stamp;
  msg.name = {kSpindleJoint};
  const cws::RotatingCore* core = sim.model().core();
  msg.position = {core ? core->angle(sim.time()) : 0.0};
  msg.velocity = {core ? core->omega(sim.time()) : 0.0};
  return msg;
}

sensor_msgs::JointState toJointStates(const cws::Simulation& sim, const ros::Time& stamp) {
  sensor_msgs::JointState msg = toSpindleState(sim, stamp);
  if (const cws::Supply* supply = sim.model().supply()) {
    const cws::PortMotion port = supply->port(sim.time());
    const Eigen::Vector3d& p = port.p_world;
    const Eigen::Vector3d& v = port.v_world;
    msg.name.insert(msg.name.end(), {"port_x", "port_y", "port_z"});
    msg.position.insert(msg.position.end(), {p.x(), p.y(), p.z()});
    msg.velocity.insert(msg.velocity.end(), {v.x(), v.y(), v.z()});
    // The dancer's arm [m], + storing wire (cell_urdf's joint `dancer`).
    if (const cws::Tensioner* dancer = supply->tensioner()) {
      msg.name.push_back("dancer");
      msg.position.push_back(dancer->armPosition());
      msg.velocity.push_back(dancer->armVelocity());
    }
  }
  return msg;
}

coil_winding_sim::TensionSetpoint toTensionCommand(const cws::Simulation& sim,
                                                   const ros::Time& stamp) {
  coil_winding_sim::TensionSetpoint msg;
  msg.header.stamp = stamp;
  msg.tension = sim.model().supply() ? sim.model().supply()->tensionSetpoint() : 0.0;
  return msg;
}

coil_winding_sim::WireTension toTensionMeasured(const cws::Simulation& sim,
                                                const ros::Time& stamp) {
  coil_winding_sim::WireTension msg;
  msg.header.stamp = stamp;
  msg.tension = sim.model().supply() ? sim.model().portAxialForce() : 0.0;
  return msg;
}

bool toPortPosition(const cws::Simulation& sim, const ros::Time& stamp, const Frames& frames,
                    geometry_msgs::PointStamped& out) {
  const cws::Supply* supply = sim.model().supply();
  if (!supply) return false;
  out = geometry_msgs::PointStamped();
  out.header.stamp = stamp;
  out.header.frame_id = frames.world;
  out.point = point(supply->port(sim.time()).p_world);
  return true;
}

sensor_msgs::PointCloud2 toProfile(const cws::Simulation& sim, const ros::Time& stamp,
                                   const Frames& frames, double turns) {
  sensor_msgs::PointCloud2 cloud;
  cloud.header.stamp = stamp;
  cloud.header.frame_id = frames.core;
  const cws::WireModel& m = sim.model();
  const cws::RotatingCore* core = m.core();
  // The wound part: up to the last point touching the core.
  const int last = m.contact() ? cws::lastInContact(m) : m.wirePoints() - 1;
  // The first point: `turns` turns about the axis back from the last.
  int first = 0;
  if (core && turns > 0.0 && last > 0) {
    Eigen::Vector3d a = cws::wirePointCore(m, last);
    double turned = 0.0;
    for (first = last; first > 0 && turned < 2.0 * M_PI * turns; --first) {
      const Eigen::Vector3d b = cws::wirePointCore(m, first - 1);
      turned += std::abs(std::atan2(a.x() * b.y() - a.y() * b.x(), a.x() * b.x() + a.y() * b.y()));
      a = b;
    }
  }
  const int count = core ? last + 1 - first : 0;
  sensor_msgs::PointCloud2Modifier mod(cloud);
  mod.setPointCloud2Fields(
      4, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1, sensor_msgs::PointField::FLOAT32, "z", 1,
      sensor_msgs::PointField::FLOAT32, "stand_off", 1, sensor_msgs::PointField::FLOAT32);
  mod.resize(count);
  cloud.height = 1;
  cloud.width = count;
  cloud.is_dense = false;
  if (count == 0) return cloud;
  const bool section = !sim.scene().core.cylinders.empty();
  sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z"),
      h(cloud, "stand_off");
  for (int i = first; i < first + count; ++i, ++x, ++y, ++z, ++h) {
    const Eigen::Vector3d p_core = cws::wirePointCore(m, i);
    *x = static_cast<float>(p_core.x());
    *y = static_cast<float>(p_core.y());
    *z = static_cast<float>(p_core.z());
    *h =
        section ? static_cast<float>(cws::standOff(m, i)) : std::numeric_limits<float>::quiet_NaN();
  }
  return cloud;
}

}  // namespace cws_ros
