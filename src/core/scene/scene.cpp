// The Scene's derived quantities (segments, end time, point counts) and the
// geometry of a scene at t = 0 that they and validateScene need.
#include "coil_winding_sim/core/scene/scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "coil_winding_sim/core/base/quaternion.hpp"
#include "scene_detail.hpp"

namespace cws {

namespace detail {
namespace {
// The core frame at t = 0 in the world frame: z along core.axis, x and y
// as the quaternion frame with zeta = axis (as the rotating core has it).
Eigen::Matrix3d coreRotationAtStart(const CoreParams& core) {
  const quat::Vec4 q = quat::fromZetaDirection(core.axis_world.normalized());
  Eigen::Matrix3d r;
  r.col(0) = quat::xi(q);
  r.col(1) = quat::eta(q);
  r.col(2) = quat::zeta(q);
  return r;
}
}  // namespace

Eigen::Vector3d clampWorldAtStart(const Scene& s) {
  if (s.start.frame != "core") return s.start.position;
  return s.core.position_world + coreRotationAtStart(s.core) * s.start.position;
}

Eigen::Vector3d coreFrameAtStart(const Scene& s, const Eigen::Vector3d& p_world) {
  return coreRotationAtStart(s.core).transpose() * (p_world - s.core.position_world);
}
}  // namespace detail

int Scene::segmentCount() const {
  return static_cast<int>(std::ceil(wire.length / wire.segment_length - 1e-9));
}

double Scene::naturalSegmentLength() const { return wire.length / segmentCount(); }

double Scene::endTime() const {
  if (process.duration) return *process.duration;
  // Turns at the commanded speed; a core that starts at rest loses half its
  // ramp time to the acceleration.
  const double omega = std::abs(rpmToRadPerSec(process.core_speed_rpm));
  const double ramp = core.start_at_speed ? 0.0 : omega / core.max_angular_acceleration;
  return process.turns * 2.0 * M_PI / omega + 0.5 * ramp;
}

double Scene::modelSegmentLength() const {
  return physics.supply ? wire.segment_length : naturalSegmentLength();
}

double Scene::initialPoints() const {
  if (!physics.supply) return std::ceil(wire.length / wire.segment_length - 1e-9) + 1.0;
  const double span = (supply.port_position_world - detail::clampWorldAtStart(*this)).norm();
  return std::ceil(span / wire.segment_length - 1e-9);
}

double Scene::pointCapacity() const {
  const double n = initialPoints();
  if (!physics.supply) return n;
  if (supply.max_points > 0) return std::max(n, static_cast<double>(supply.max_points));
  const double estimate = wirePointsEstimate();
  // Where buried wire retires from the live arrays, a long job needs no more
  // live points than a few hundred turns hold.
  if (carriesWoundWire()) return std::min(estimate, std::max(n, double{kAutoLivePoints}));
  return estimate;
}

double Scene::wirePointsEstimate() const {
  if (!physics.supply) return initialPoints();
  // At the fastest core speed the job commands.
  double rpm = std::abs(process.core_speed_rpm);
  for (const ProcessCommand& c : process.commands) {
    if (c.core_speed_rpm) rpm = std::max(rpm, std::abs(*c.core_speed_rpm));
  }
  return pointCapacityForAngle(rpmToRadPerSec(rpm) * endTime());
}

bool Scene::carriesWoundWire() const {
  return solver.carry_stuck_wire && physics.contact && physics.friction && start.frame == "core";
}

double Scene::pointCapacityForAngle(double core_angle_rad) const {
  const double n = initialPoints();
  if (!physics.supply) return n;
  // Wound length <= core angle x largest radius of the core, plus the free
  // span; 20 % margin.
  const double wire_radius = 0.5 * wire.diameter;
  double r_max = 0.0;
  for (const CylinderParams& cyl : core.cylinders) {
    r_max = std::max(r_max, cyl.center_core.norm() + cyl.radius + wire_radius);
  }
  for (const FaceParams& f : core.faces) {
    r_max = std::max({r_max, f.from_core.norm() + wire_radius, f.to_core.norm() + wire_radius});
  }
  const Eigen::Vector3d axis = core.axis_world.normalized();
  const double angle = core_angle_rad;
  Eigen::Vector3d port_rel = supply.port_position_world - core.position_world;
  port_rel -= port_rel.dot(axis) * axis;
  const double fed = angle * r_max + 2.0 * port_rel.norm();
  return n + std::ceil(1.2 * fed / wire.segment_length) + 8.0;
}

double Scene::turnsPerLayer() const {
  if (!(process.winding_width > wire.diameter) || process.traverse_pitch == 0.0) return 0.0;
  return (process.winding_width - wire.diameter) / std::abs(process.traverse_pitch);
}

int Scene::traverseLayers() const {
  const int planned = plannedLayers();
  if (planned <= 0 || !physics.flanges || turnsPerLayer() <= 0.0) return planned;
  return std::max(planned, bobbinLayers());
}

double Scene::bobbinTurns() const {
  const double per_layer = turnsPerLayer();
  if (!physics.flanges || per_layer <= 0.0) return std::numeric_limits<double>::infinity();
  return bobbinLayers() * per_layer;
}

int Scene::plannedLayers() const {
  const double per_layer = turnsPerLayer();
  if (process.layers <= 0 || process.duration || per_layer <= 0.0) return process.layers;
  // (A job of its layers' turns, rounded up by up to a tenth of a turn,
  // plans no further layer.)
  const double needed = std::ceil((traverseTurns() - 0.1) / per_layer);
  return static_cast<int>(std::max<double>(process.layers, std::min(needed, 1e6)));
}

double Scene::traverseTurns() const {
  const double turns = std::abs(process.turns);
  const double stalled =
      std::min(process.traverse_stall_turns, std::max(0.0, turns - process.traverse_stall_turn));
  return turns - stalled;
}

int Scene::bobbinLayers() const {
  const double d = wire.diameter;
  if (core.flange_height < d) return 0;
  return 1 +
         static_cast<int>(std::floor((core.flange_height / d - 1.0) * 2.0 / std::sqrt(3.0) + 1e-9));
}

// A wave crosses a segment in l / c: axial c = sqrt(EA / rho); torsional
// c = sqrt(GJ / (2/5 rho r^2)), the frames' inertia per length.
double explicitStepLimit(const Scene& s) {
  const double l = s.modelSegmentLength();
  double c = std::sqrt(s.wire.stretch.elastic_rigidity / s.wire.line_density);
  if (s.physics.torsion) {
    const double r = 0.5 * s.wire.diameter;
    c = std::max(c,
                 std::sqrt(s.wire.torsion.elastic_rigidity / (0.4 * s.wire.line_density * r * r)));
  }
  return l / c;
}

double fixedStep(const Scene& s) {
  if (s.solver.fixed_step) return *s.solver.fixed_step;
  return std::min(kAutoStepFraction * explicitStepLimit(s), s.solver.max_step);
}

}  // namespace cws
