// validateScene: the single-key ranges from the key table, and the rules
// that relate several keys, written out here. Works on the Scene struct
// alone (and the plane geometry of its core's section).
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "coil_winding_sim/core/scene/core_geometry.hpp"
#include "coil_winding_sim/core/scene/integrators.hpp"
#include "coil_winding_sim/core/scene/setpoint_limits.hpp"
#include "scene_detail.hpp"

namespace cws {

namespace {
using detail::fmt;
using detail::printable;
using detail::requireNonNegative;
using detail::requirePositive;

// The clamp and what places it, for messages.
std::string clampText(const Scene& s) {
  return s.start.frame == "core"
             ? "the clamp (start.position on the core at core.position about core.axis)"
             : "the clamp (start.position)";
}

// The keys the estimate of the drawn-in wire depends on, for its message.
const char* kSupplyEstimateKeys =
    "process.turns or process.duration, process.core_speed_rpm (with its ramp at "
    "core.max_angular_acceleration when core.start_at_speed is false), the size of "
    "core.cylinders and core.faces, supply.port_position, wire.segment_length";

// ---------------------------------------------------------------------------
// The wire.
void segmentsFitWire(const Scene& s) {
  if (s.wire.segment_length > s.wire.length) {
    throw SceneError("wire.segment_length",
                     fmt(s.wire.segment_length) +
                         " m is longer than wire.length = " + fmt(s.wire.length) + " m");
  }
  // Bounded before anything converts the count to int (segmentCount()).
  const double segments = std::ceil(s.wire.length / s.wire.segment_length - 1e-9);
  if (!(segments < kMaxScenePoints)) {
    throw SceneError("wire.segment_length", "wire.length / wire.segment_length gives " +
                                                fmt(segments) +
                                                " segments, more than the limit of " +
                                                std::to_string(kMaxScenePoints - 1));
  }
}

// The plastic slope of a two-line law (at `law`, e.g. "wire.stretch") does
// not exceed its elastic one.
void plasticNotAboveElastic(const HysteresisParams& h, const std::string& law) {
  if (h.plastic_rigidity > h.elastic_rigidity) {
    throw SceneError(law + ".plastic_rigidity",
                     fmt(h.plastic_rigidity) + " is above the elastic rigidity " + law +
                         ".elastic_rigidity = " + fmt(h.elastic_rigidity));
  }
}

// ---------------------------------------------------------------------------
// Contact and the core.
void kineticNotAboveStatic(const Scene& s) {
  if (s.contact.kinetic_friction > s.contact.static_friction) {
    throw SceneError("contact.kinetic_friction",
                     fmt(s.contact.kinetic_friction) +
                         " is above static friction, contact.static_friction = " +
                         fmt(s.contact.static_friction));
  }
}

// A traverse that reverses needs a pitch, and room for more than one turn.
void traverseFits(const Scene& s) {
  if (s.process.winding_width == 0.0) return;
  if (s.process.traverse_pitch == 0.0) {
    throw SceneError("process.winding_width",
                     "needs a traverse: process.traverse_pitch is 0 (the port would not move)");
  }
  if (!(s.process.winding_width > s.wire.diameter)) {
    throw SceneError("process.winding_width", fmt(s.process.winding_width) +
                                                  " m leaves no travel for the port: it must be "
                                                  "wider than the wire, wire.diameter = " +
                                                  fmt(s.wire.diameter) + " m");
  }
}

// Flanges stand at the ends of the winding width, as contact surfaces of a
// core that the wire can reach along its axis.
void flangesFit(const Scene& s) {
  if (!s.physics.flanges) return;
  if (!s.physics.contact) throw SceneError("physics.flanges", "flanges need physics.contact");
  if (s.physics.planar) {
    throw SceneError("physics.flanges",
                     "must be false with physics.planar (a flange is parallel to the plane)");
  }
  if (s.process.winding_width == 0.0) {
    throw SceneError("physics.flanges",
                     "flanges stand at the ends of process.winding_width, which is 0");
  }
  if (s.core.flange_spacing != 0.0 && !(s.core.flange_spacing > s.wire.diameter)) {
    throw SceneError("core.flange_spacing", fmt(s.core.flange_spacing) +
                                                " m leaves no room for a wire of " +
                                                fmt(s.wire.diameter) + " m between the flanges");
  }
  // An over-full bobbin: its layers, packed as closely as wire packs
  // (orthocyclic, each layer in the grooves of the one below), rise above
  // the flanges. Wire above a flange's rim would fall over it, and wire
  // beyond a face stops the run (a scrap coil).
  const int layers = s.plannedLayers();
  if (layers > 0) {
    const double d = s.wire.diameter;
    const double stack = d * (1.0 + (layers - 1) * 0.5 * std::sqrt(3.0));
    if (stack > s.core.flange_height * (1.0 + 1e-12)) {
      // Its capacity: the layers that fit, in turns where the traverse
      // reverses.
      const int holds = s.bobbinLayers();
      const double per_layer = s.turnsPerLayer();
      const std::string capacity =
          "the bobbin holds " + std::to_string(holds) + " layers" +
          (per_layer > 0.0 ? " (" + fmt(holds * per_layer) + " turns)" : std::string()) +
          " under core.flange_height = " + fmt(s.core.flange_height) + " m";
      if (layers > s.process.layers) {
        throw SceneError("process.turns",
                         fmt(s.process.turns) + " turns wind past the " +
                             std::to_string(s.process.layers) +
                             " planned layers (process.layers) into " + std::to_string(layers) +
                             " layers of " + fmt(per_layer) + " turns each, but " + capacity +
                             ": the bobbin is full; wind at most " + fmt(holds * per_layer) +
                             " turns or raise core.flange_height to at least " + fmt(stack) + " m");
      }
      throw SceneError("process.layers",
                       std::to_string(s.process.layers) + " layers of wire " + fmt(d) +
                           " m thick stand at least " + fmt(stack) +
                           " m high, above core.flange_height = " + fmt(s.core.flange_height) +
                           " m: the bobbin is over-full and the wire would climb over the "
                           "flanges' rims (" +
                           capacity + "); raise core.flange_height to at least " + fmt(stack) +
                           " m or wind fewer layers");
    }
  }
}

// Contact between segments acts against wire the core carries (wound wire
// held by friction on a core that also holds the fixed end) and between
// free segments (docs/MODEL.md); the carried wire is what keeps the Newton
// system's couplings outside the band few.
void wireContactFits(const Scene& s) {
  if (!s.physics.wire_contact) return;
  auto refuse = [](const std::string& why) { throw SceneError("physics.wire_contact", why); };
  if (!s.physics.contact) refuse("wire contact needs physics.contact");
  if (s.physics.planar) {
    refuse("must be false with physics.planar (turns lie beside each other along the axis)");
  }
  if (!s.physics.friction || !s.solver.carry_stuck_wire || s.start.frame != "core") {
    refuse(
        "acts against the wound wire the core carries, which needs physics.friction, "
        "solver.carry_stuck_wire and start.frame core");
  }
  // Each point acts as a sphere of the wire's radius: segments longer than
  // the diameter leave room for a crossing wire to pass between two.
  if (s.wire.segment_length > s.wire.diameter * (1.0 + 1e-12)) {
    throw SceneError("wire.segment_length",
                     fmt(s.wire.segment_length) + " m is longer than the wire's diameter " +
                         fmt(s.wire.diameter) +
                         " m: wire contact (physics.wire_contact) needs segments no longer");
  }
}

// Dashpots beyond twice critical only slow a landing down, and stiffen the
// explicit methods' step limit (2 zeta sqrt(k / M) h < 2).
void dampingRatioInRange(const Scene& s) {
  if (s.contact.damping_ratio > 2.0) {
    throw SceneError("contact.damping_ratio",
                     fmt(s.contact.damping_ratio) +
                         " is above 2 (1: critical damping of one mass point on the contact "
                         "and stick springs)");
  }
}

void coreFitsEffects(const Scene& s) {
  if (s.core.hull_faces && s.core.cylinders.size() < 2) {
    throw SceneError("core.hull_faces", "needs at least two core.cylinders");
  }
  if (s.physics.contact && s.core.cylinders.empty() && s.core.faces.empty()) {
    throw SceneError("core.cylinders",
                     "physics.contact needs at least one entry in core.cylinders or core.faces");
  }
  if (s.physics.friction && !s.physics.contact) {
    throw SceneError("physics.friction", "friction needs physics.contact");
  }
}

// No tunnelling: a segment must not pass a cylinder between two contact
// checks of its points; the stated bound is l <= the smallest radius.
void segmentsWithinRadius(const Scene& s) {
  if (!s.physics.contact) return;
  for (std::size_t i = 0; i < s.core.cylinders.size(); ++i) {
    if (s.modelSegmentLength() > s.core.cylinders[i].radius) {
      const std::string radius = s.core.shape.kind == "rounded_rectangle"
                                     ? std::string("core.shape.corner_radius")
                                     : "core.cylinders[" + std::to_string(i) + "].radius";
      throw SceneError("wire.segment_length",
                       "segments of " + fmt(s.modelSegmentLength()) +
                           " m (from wire.segment_length and wire.length) are longer than " +
                           radius + " = " + fmt(s.core.cylinders[i].radius) +
                           " m and could pass through that cylinder; use at most " +
                           fmt(s.core.cylinders[i].radius) + " m");
    }
  }
}

// The supply's port: outside the core, away from the clamp, in the plane.
void portPlacement(const Scene& s) {
  if (!s.physics.supply) return;
  if (s.core.cylinders.empty() && s.core.faces.empty()) {
    throw SceneError("core.cylinders",
                     "physics.supply winds wire onto a core: give at least one entry in "
                     "core.cylinders or core.faces");
  }
  // The port must lie outside the core (the convex hull of its cylinders).
  const Eigen::Vector3d axis = s.core.axis_world.normalized();
  const Eigen::Vector3d port_core = detail::coreFrameAtStart(s, s.supply.port_position_world);
  const double gap = CoreSection(s.core).signedDistance(port_core.head<2>());
  if (!(gap > 0.5 * s.wire.diameter)) {
    throw SceneError("supply.port_position",
                     "lies inside the core (the convex hull of core.cylinders and core.faces "
                     "about core.position and core.axis, widened by the wire radius, half of "
                     "wire.diameter)");
  }
  const Eigen::Vector3d clamp_world = detail::clampWorldAtStart(s);
  if (!((s.supply.port_position_world - clamp_world).norm() >= 2.0 * s.wire.segment_length)) {
    throw SceneError("supply.port_position",
                     "is closer to " + clampText(s) + " than two segments (wire.segment_length)");
  }
  if (s.physics.planar && s.process.traverse_pitch != 0.0) {
    throw SceneError("process.traverse_pitch",
                     "must be 0 with physics.planar (the port cannot leave the plane)");
  }
  if (s.physics.planar &&
      !(std::abs((s.supply.port_position_world - clamp_world).dot(axis)) <= 1e-12)) {
    throw SceneError("supply.port_position", "must lie in the plane of " + clampText(s) +
                                                 " normal to core.axis with physics.planar");
  }
}

void planarGravity(const Scene& s) {
  if (s.physics.planar && s.physics.gravity &&
      std::abs(s.gravity.acceleration_world.dot(s.core.axis_world.normalized())) > 1e-12) {
    throw SceneError("gravity.acceleration",
                     "must lie in the plane normal to core.axis with physics.planar and "
                     "physics.gravity");
  }
}

// ---------------------------------------------------------------------------
// The process.
// (The same check as every setpoint during a run: setpoint_limits.hpp.)
void setpointsWithinLimits(const Scene& s) {
  const SetpointLimits limits = SetpointLimits::of(s.process);
  std::string why = coreSpeedRefusal(limits, rpmToRadPerSec(s.process.core_speed_rpm));
  if (!why.empty())
    throw SceneError("process.core_speed_rpm",
                     fmt(s.process.core_speed_rpm) + " rpm, a " +
                         coreSpeedText(rpmToRadPerSec(s.process.core_speed_rpm)) + ", " + why);
  why = tensionRefusal(limits, s.process.tension);
  if (!why.empty()) throw SceneError("process.tension", fmt(s.process.tension) + " N " + why);
}

// Without a duration the turns end the run: some, at a speed that ends them.
void runEnds(const Scene& s) {
  if (s.process.duration) return;
  requirePositive(s.process.turns, "process.turns");
  if (s.process.core_speed_rpm == 0.0) {
    throw SceneError("process.duration",
                     "must be given when process.core_speed_rpm is 0 (process.turns never end)");
  }
  // A speed so small that the turns take forever (1e-320 rpm).
  if (!std::isfinite(s.endTime())) {
    throw SceneError(
        "process.turns",
        fmt(s.process.turns) +
            " turns at process.core_speed_rpm = " + fmt(s.process.core_speed_rpm) +
            (s.core.start_at_speed ? std::string()
                                   : " (after the ramp at core.max_angular_acceleration = " +
                                         fmt(s.core.max_angular_acceleration) + " rad/s^2)") +
            " take longer than any time a double can hold");
  }
}

// A tensioner or a nozzle stands between the setpoint and a supply's port:
// set without one, it would do nothing the user asked for.
void machineNeedsSupply(const Scene& s) {
  if (s.physics.supply) return;
  if (s.supply.tensioner.kind != "ideal") {
    throw SceneError("supply.tensioner.kind", s.supply.tensioner.kind +
                                                  " needs physics.supply (a port the wire is drawn "
                                                  "in through)");
  }
  if (s.supply.nozzle_friction * s.supply.nozzle_wrap_angle > 0.0) {
    throw SceneError("supply.nozzle_friction",
                     "a nozzle with friction needs physics.supply (a port the wire is drawn in "
                     "through)");
  }
}

// Storage: the points the model reserves, bounded before it converts the
// counts to int or allocates anything.
void supplyStorage(const Scene& s) {
  if (!s.physics.supply) return;
  const double n = s.initialPoints();
  if (!(n < kMaxScenePoints)) {
    throw SceneError("supply.port_position",
                     "the wire from " + clampText(s) + " to the port needs " + fmt(n) +
                         " points of wire.segment_length, more than the limit of " +
                         std::to_string(kMaxScenePoints));
  }
  requireNonNegative(s.supply.max_points, "supply.max_points");
  if (s.supply.max_points > kMaxScenePoints) {
    throw SceneError("supply.max_points", std::to_string(s.supply.max_points) +
                                              " is above the limit of " +
                                              std::to_string(kMaxScenePoints) + " points");
  }
  // Wire that retires from the live points keeps a record of about 100
  // bytes a point: the whole wire's points are bounded too.
  const double wire = s.wirePointsEstimate();
  if (s.carriesWoundWire() && !(wire <= kMaxWirePoints)) {
    throw SceneError(s.process.duration ? "process.duration" : "process.turns",
                     "the wire drawn in during the run needs an estimated " + fmt(wire) +
                         " points, more than the limit of " + fmt(kMaxWirePoints) +
                         " a run may wind (the estimate comes from " + kSupplyEstimateKeys +
                         "); shorten the run");
  }
  const double capacity = s.pointCapacity();
  if (!(capacity <= kMaxScenePoints)) {
    throw SceneError(s.process.duration ? "process.duration" : "process.turns",
                     "the wire drawn in during the run needs an estimated " + fmt(capacity) +
                         " points, more than the limit of " + std::to_string(kMaxScenePoints) +
                         " (the estimate comes from " + kSupplyEstimateKeys +
                         "); shorten the run or set supply.max_points");
  }
}

// ---------------------------------------------------------------------------
// The solver.

// The fixed step is compared for any finite value; its sign is the table's
// check.
// `auto` is within both bounds by construction (fixedStep()), but an
// absurd wire (a wave speed that overflows) leaves it no step at all.
void fixedStepStable(const Scene& s) {
  const IntegratorInfo* info = findIntegrator(s.solver.integrator);
  if (!info || !info->explicit_fixed_step) return;
  if (!s.solver.fixed_step) {
    const double step = fixedStep(s);
    if (!(step > 0.0) || !std::isfinite(step)) {
      throw SceneError("solver.fixed_step",
                       "auto (1/4 of l / c) gives " + fmt(step) +
                           " s for this wire: its wave speed c (from wire.stretch.elastic_rigidity "
                           "and wire.line_density; with physics.torsion also from "
                           "wire.torsion.elastic_rigidity and wire.diameter) or its segment l "
                           "(wire.segment_length) is out of range");
    }
    return;
  }
  const double step = *s.solver.fixed_step;
  if (step > s.solver.max_step) {
    throw SceneError("solver.fixed_step",
                     fmt(step) + " s is above solver.max_step = " + fmt(s.solver.max_step) + " s");
  }
  // Above the explicit stability limit symplectic Euler stays bounded but
  // wrong, with no warning (docs/MODEL.md, "Other integrators").
  const double limit = explicitStepLimit(s);
  if (step > limit) {
    std::ostringstream why;
    why << step << " s is above the stability limit l / c = " << limit
        << " s of this wire (the time a wave needs to cross a segment l from "
        << "wire.segment_length and wire.length, at the wave speed c from "
        << "wire.stretch.elastic_rigidity, wire.line_density and, with physics.torsion, "
        << "wire.torsion.elastic_rigidity and wire.diameter); " << info->name << " "
        << "(solver.integrator) would run but be wrong: use at most that step, auto "
        << "(1/4 of it), or rkf45";
    throw SceneError("solver.fixed_step", why.str());
  }
}

void stepBoundsOrdered(const Scene& s) {
  if (s.solver.max_step < s.solver.min_step) {
    throw SceneError("solver.max_step", fmt(s.solver.max_step) + " s is below solver.min_step = " +
                                            fmt(s.solver.min_step) + " s");
  }
  if (s.solver.initial_step < s.solver.min_step || s.solver.initial_step > s.solver.max_step) {
    throw SceneError("solver.initial_step",
                     fmt(s.solver.initial_step) +
                         " s must lie between solver.min_step = " + fmt(s.solver.min_step) +
                         " s and solver.max_step = " + fmt(s.solver.max_step) + " s");
  }
}

// ---------------------------------------------------------------------------
// Each rule runs right after the range check of the key `after` (in table
// order), so that the keys it relies on have been checked before it.
struct CrossRule {
  const char* after;
  void (*check)(const Scene&);
};

const CrossRule kCrossRules[] = {
    {"wire.segment_length", segmentsFitWire},
    {"wire.stretch.plastic_rigidity",
     [](const Scene& s) { plasticNotAboveElastic(s.wire.stretch, "wire.stretch"); }},
    {"wire.bend.plastic_rigidity",
     [](const Scene& s) { plasticNotAboveElastic(s.wire.bend, "wire.bend"); }},
    {"wire.torsion.plastic_rigidity",
     [](const Scene& s) { plasticNotAboveElastic(s.wire.torsion, "wire.torsion"); }},
    {"contact.kinetic_friction", kineticNotAboveStatic},
    {"contact.damping_ratio", dampingRatioInRange},
    {"process.layers", traverseFits},
    {"physics.planar", flangesFit},
    {"physics.planar", wireContactFits},
    {"core.hull_faces", coreFitsEffects},
    {"core.hull_faces", segmentsWithinRadius},
    {"core.hull_faces", portPlacement},
    {"core.hull_faces", planarGravity},
    {"process.max_tension", setpointsWithinLimits},
    {"process.duration", runEnds},
    {"process.duration", supplyStorage},
    {"supply.nozzle_wrap_angle", machineNeedsSupply},
    {"solver.fixed_step", fixedStepStable},
    {"solver.initial_step", stepBoundsOrdered},
};

// The rules to run after each key of the table (by index), found once; a
// rule after an undeclared key would never run, so it is an error.
const std::vector<std::vector<const CrossRule*>>& rulesByKey() {
  static const std::vector<std::vector<const CrossRule*>> by_key = [] {
    const std::vector<SceneKey>& keys = sceneKeys();
    std::vector<std::vector<const CrossRule*>> rules(keys.size());
    for (const CrossRule& r : kCrossRules) {
      const SceneKey* k = findSceneKey(r.after);
      if (!k) throw std::logic_error(std::string("cross-key rule after unknown key ") + r.after);
      rules[k - keys.data()].push_back(&r);
    }
    return rules;
  }();
  return by_key;
}
}  // namespace

void validateScene(const Scene& s) {
  // Scenes built in code may hold what YAML cannot: refuse any non-finite
  // number first, by its key.
  detail::forEachNumber(s, [](const std::string& key, double v) {
    if (!std::isfinite(v)) throw SceneError(key, "must be a finite number, got " + fmt(v));
  });
  const std::vector<SceneKey>& keys = sceneKeys();
  const std::vector<std::vector<const CrossRule*>>& rules = rulesByKey();
  for (std::size_t i = 0; i < keys.size(); ++i) {
    detail::checkRange(keys[i], s);
    for (const CrossRule* r : rules[i]) r->check(s);
  }
}

}  // namespace cws
