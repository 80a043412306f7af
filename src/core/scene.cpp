#include "coil_winding_sim/core/scene.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "coil_winding_sim/core/core_geometry.hpp"
#include "coil_winding_sim/core/rotating_core.hpp"

namespace cws {

namespace {

// ---------------------------------------------------------------------------
// Scene -> YAML. The defaults emitted here are also the schema: a key that a
// default scene does not have is unknown.
// Numbers as plain scalars, as short as round-trips exactly (so that a
// printed scene, and a snapshot's scene, load back bit-identical).
YAML::Node num(double v) {
  char buf[32];
  for (int digits = 10; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return YAML::Node(std::string(buf));
}

YAML::Node vec3(const Eigen::Vector3d& v) {
  YAML::Node n(YAML::NodeType::Sequence);
  n.SetStyle(YAML::EmitterStyle::Flow);
  for (int i = 0; i < 3; ++i) n.push_back(num(v[i]));
  return n;
}

YAML::Node hysteresis(const HysteresisParams& h, const char* yield_key) {
  YAML::Node n;
  n["elastic_rigidity"] = num(h.elastic_rigidity);
  n["plastic_rigidity"] = num(h.plastic_rigidity);
  n[yield_key] = num(h.yield);
  return n;
}

YAML::Node toYaml(const Scene& s) {
  YAML::Node root;
  YAML::Node w;
  w["diameter"] = num(s.wire.diameter);
  w["line_density"] = num(s.wire.line_density);
  w["length"] = num(s.wire.length);
  w["segment_length"] = num(s.wire.segment_length);
  w["stretch"] = hysteresis(s.wire.stretch, "yield_strain");
  w["bend"] = hysteresis(s.wire.bend, "yield_curvature");
  w["torsion"] = hysteresis(s.wire.torsion, "yield_twist");
  root["wire"] = w;

  root["contact"]["static_friction"] = num(s.contact.static_friction);
  root["contact"]["kinetic_friction"] = num(s.contact.kinetic_friction);
  root["contact"]["stiffness"] = num(s.contact.stiffness);
  root["contact"]["stick_stiffness"] = num(s.contact.stick_stiffness);
  root["contact"]["stick_speed"] = num(s.contact.stick_speed);

  root["core"]["position"] = vec3(s.core.position_world);
  root["core"]["axis"] = vec3(s.core.axis_world);
  root["core"]["start_at_speed"] = s.core.start_at_speed;
  root["core"]["max_angular_acceleration"] = num(s.core.max_angular_acceleration);
  YAML::Node cyl(YAML::NodeType::Sequence);
  for (const CylinderParams& c : s.core.cylinders) {
    YAML::Node cn;
    YAML::Node center(YAML::NodeType::Sequence);
    center.SetStyle(YAML::EmitterStyle::Flow);
    center.push_back(num(c.center_core.x()));
    center.push_back(num(c.center_core.y()));
    cn["center"] = center;
    cn["radius"] = num(c.radius);
    cyl.push_back(cn);
  }
  root["core"]["cylinders"] = cyl;
  YAML::Node faces(YAML::NodeType::Sequence);
  for (const FaceParams& f : s.core.faces) {
    YAML::Node fn;
    for (const auto& [key, v] : {std::pair<const char*, Eigen::Vector2d>{"from", f.from_core},
                                 std::pair<const char*, Eigen::Vector2d>{"to", f.to_core}}) {
      YAML::Node xy(YAML::NodeType::Sequence);
      xy.SetStyle(YAML::EmitterStyle::Flow);
      xy.push_back(num(v.x()));
      xy.push_back(num(v.y()));
      fn[key] = xy;
    }
    faces.push_back(fn);
  }
  root["core"]["faces"] = faces;
  root["core"]["hull_faces"] = s.core.hull_faces;

  root["process"]["core_speed_rpm"] = num(s.process.core_speed_rpm);
  root["process"]["tension"] = num(s.process.tension);
  root["process"]["traverse_pitch"] = num(s.process.traverse_pitch);
  root["process"]["max_core_speed_rpm"] = num(s.process.max_core_speed_rpm);
  root["process"]["max_tension"] = num(s.process.max_tension);
  root["process"]["turns"] = num(s.process.turns);
  if (s.process.duration) {
    root["process"]["duration"] = num(*s.process.duration);
  } else {
    root["process"]["duration"] = YAML::Node(YAML::NodeType::Null);
  }

  root["solver"]["integrator"] = s.solver.integrator;
  root["solver"]["rtol"] = num(s.solver.rtol);
  root["solver"]["atol"] = num(s.solver.atol);
  root["solver"]["min_step"] = num(s.solver.min_step);
  root["solver"]["max_step"] = num(s.solver.max_step);
  root["solver"]["initial_step"] = num(s.solver.initial_step);
  root["solver"]["fixed_step"] = num(s.solver.fixed_step);
  root["solver"]["baumgarte_nu"] = num(s.solver.baumgarte_nu);
  root["solver"]["carry_stuck_wire"] = s.solver.carry_stuck_wire;

  root["physics"]["torsion"] = s.physics.torsion;
  root["physics"]["plasticity"] = s.physics.plasticity;
  root["physics"]["gravity"] = s.physics.gravity;
  root["physics"]["damping"] = s.physics.damping;
  root["physics"]["contact"] = s.physics.contact;
  root["physics"]["friction"] = s.physics.friction;
  root["physics"]["supply"] = s.physics.supply;
  root["physics"]["planar"] = s.physics.planar;
  root["supply"]["port_position"] = vec3(s.supply.port_position_world);
  root["supply"]["max_points"] = s.supply.max_points;

  root["gravity"]["acceleration"] = vec3(s.gravity.acceleration_world);
  root["damping"]["translational"] = num(s.damping.translational);
  root["damping"]["rotational"] = num(s.damping.rotational);

  root["start"]["type"] = s.start.type;
  root["start"]["frame"] = s.start.frame;
  root["start"]["position"] = vec3(s.start.position);
  root["start"]["direction"] = vec3(s.start.direction);

  root["end"]["type"] = s.end.type;
  YAML::Node load(YAML::NodeType::Sequence);
  for (const LoadKeyframe& k : s.end.load) {
    YAML::Node kn;
    kn["time"] = num(k.time);
    kn["force"] = vec3(k.force_world);
    kn["moment"] = vec3(k.moment_world);
    load.push_back(kn);
  }
  root["end"]["load"] = load;

  root["output"]["progress_interval_s"] = num(s.output.progress_interval_s);
  return root;
}

// ---------------------------------------------------------------------------
// YAML -> Scene, every conversion naming its key.
std::string join(const std::string& prefix, const std::string& key) {
  return prefix.empty() ? key : prefix + "." + key;
}

std::string describe(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Null:
      return "nothing (null)";
    case YAML::NodeType::Sequence:
      return "a list";
    case YAML::NodeType::Map:
      return "a map";
    default:
      return "'" + n.Scalar() + "'";
  }
}

double readDouble(const YAML::Node& n, const std::string& key) {
  if (!n.IsScalar()) throw SceneError(key, "expected a number, got " + describe(n));
  double v = 0.0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    throw SceneError(key, "expected a number, got " + describe(n));
  }
  if (!std::isfinite(v)) throw SceneError(key, "must be a finite number, got " + n.Scalar());
  return v;
}

bool readBool(const YAML::Node& n, const std::string& key) {
  if (!n.IsScalar()) throw SceneError(key, "expected true or false, got " + describe(n));
  try {
    return n.as<bool>();
  } catch (const YAML::Exception&) {
    throw SceneError(key, "expected true or false, got " + describe(n));
  }
}

std::string readString(const YAML::Node& n, const std::string& key) {
  if (!n.IsScalar()) throw SceneError(key, "expected a word, got " + describe(n));
  return n.Scalar();
}

Eigen::Vector3d readVec3(const YAML::Node& n, const std::string& key) {
  if (!n.IsSequence() || n.size() != 3) {
    throw SceneError(key, "expected a list of three numbers [x, y, z], got " + describe(n));
  }
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) v[i] = readDouble(n[i], key + "[" + std::to_string(i) + "]");
  return v;
}

Eigen::Vector2d readVec2(const YAML::Node& n, const std::string& key) {
  if (!n.IsSequence() || n.size() != 2) {
    throw SceneError(key, "expected a list of two numbers [x, y], got " + describe(n));
  }
  return {readDouble(n[0], key + "[0]"), readDouble(n[1], key + "[1]")};
}

// Reads the list of maps at `key`, each entry with only the `allowed` keys,
// calling read(entry, "key[i]"); every refusal names the entry or its key.
template <class Fn>
void readEntries(const YAML::Node& list, const std::string& key,
                 const std::vector<std::string>& allowed, bool non_empty, Fn read) {
  std::string names;
  for (const std::string& a : allowed) names += (names.empty() ? "" : ", ") + a;
  if (!list.IsSequence() || (non_empty && list.size() == 0)) {
    throw SceneError(key, std::string("expected a ") + (non_empty ? "non-empty " : "") +
                              "list of {" + names + "}, got " + describe(list));
  }
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string entry_key = key + "[" + std::to_string(i) + "]";
    const YAML::Node entry = list[i];
    if (!entry.IsMap()) throw SceneError(entry_key, "expected a map {" + names + "}");
    for (const auto& kv : entry) {
      const std::string name = kv.first.Scalar();
      if (std::find(allowed.begin(), allowed.end(), name) == allowed.end()) {
        throw SceneError(entry_key + "." + name, "unknown key (allowed: " + names + ")");
      }
    }
    read(entry, entry_key);
  }
}

HysteresisParams readHysteresis(const YAML::Node& n, const std::string& key,
                                const char* yield_key) {
  HysteresisParams h;
  h.elastic_rigidity = readDouble(n["elastic_rigidity"], key + ".elastic_rigidity");
  h.plastic_rigidity = readDouble(n["plastic_rigidity"], key + ".plastic_rigidity");
  h.yield = readDouble(n[yield_key], key + "." + yield_key);
  return h;
}

Scene fromYaml(const YAML::Node& r) {
  Scene s;
  const YAML::Node w = r["wire"];
  s.wire.diameter = readDouble(w["diameter"], "wire.diameter");
  s.wire.line_density = readDouble(w["line_density"], "wire.line_density");
  s.wire.length = readDouble(w["length"], "wire.length");
  s.wire.segment_length = readDouble(w["segment_length"], "wire.segment_length");
  s.wire.stretch = readHysteresis(w["stretch"], "wire.stretch", "yield_strain");
  s.wire.bend = readHysteresis(w["bend"], "wire.bend", "yield_curvature");
  s.wire.torsion = readHysteresis(w["torsion"], "wire.torsion", "yield_twist");

  s.contact.static_friction =
      readDouble(r["contact"]["static_friction"], "contact.static_friction");
  s.contact.kinetic_friction =
      readDouble(r["contact"]["kinetic_friction"], "contact.kinetic_friction");
  s.contact.stiffness = readDouble(r["contact"]["stiffness"], "contact.stiffness");
  s.contact.stick_stiffness =
      readDouble(r["contact"]["stick_stiffness"], "contact.stick_stiffness");
  s.contact.stick_speed = readDouble(r["contact"]["stick_speed"], "contact.stick_speed");

  const YAML::Node core = r["core"];
  s.core.position_world = readVec3(core["position"], "core.position");
  s.core.axis_world = readVec3(core["axis"], "core.axis");
  s.core.start_at_speed = readBool(core["start_at_speed"], "core.start_at_speed");
  s.core.max_angular_acceleration =
      readDouble(core["max_angular_acceleration"], "core.max_angular_acceleration");
  readEntries(core["cylinders"], "core.cylinders", {"center", "radius"}, false,
              [&](const YAML::Node& c, const std::string& key) {
                CylinderParams cp;
                cp.center_core = readVec2(c["center"], key + ".center");
                if (c["radius"]) cp.radius = readDouble(c["radius"], key + ".radius");
                s.core.cylinders.push_back(cp);
              });
  readEntries(core["faces"], "core.faces", {"from", "to"}, false,
              [&](const YAML::Node& f, const std::string& key) {
                s.core.faces.push_back(
                    FaceParams{readVec2(f["from"], key + ".from"), readVec2(f["to"], key + ".to")});
              });
  s.core.hull_faces = readBool(core["hull_faces"], "core.hull_faces");

  const YAML::Node p = r["process"];
  s.process.core_speed_rpm = readDouble(p["core_speed_rpm"], "process.core_speed_rpm");
  s.process.tension = readDouble(p["tension"], "process.tension");
  s.process.traverse_pitch = readDouble(p["traverse_pitch"], "process.traverse_pitch");
  s.process.max_core_speed_rpm = readDouble(p["max_core_speed_rpm"], "process.max_core_speed_rpm");
  s.process.max_tension = readDouble(p["max_tension"], "process.max_tension");
  s.process.turns = readDouble(p["turns"], "process.turns");
  if (!p["duration"].IsNull()) s.process.duration = readDouble(p["duration"], "process.duration");

  const YAML::Node so = r["solver"];
  s.solver.integrator = readString(so["integrator"], "solver.integrator");
  s.solver.rtol = readDouble(so["rtol"], "solver.rtol");
  s.solver.atol = readDouble(so["atol"], "solver.atol");
  s.solver.min_step = readDouble(so["min_step"], "solver.min_step");
  s.solver.max_step = readDouble(so["max_step"], "solver.max_step");
  s.solver.initial_step = readDouble(so["initial_step"], "solver.initial_step");
  s.solver.fixed_step = readDouble(so["fixed_step"], "solver.fixed_step");
  s.solver.baumgarte_nu = readDouble(so["baumgarte_nu"], "solver.baumgarte_nu");
  s.solver.carry_stuck_wire = readBool(so["carry_stuck_wire"], "solver.carry_stuck_wire");

  const YAML::Node ph = r["physics"];
  s.physics.torsion = readBool(ph["torsion"], "physics.torsion");
  s.physics.plasticity = readBool(ph["plasticity"], "physics.plasticity");
  s.physics.gravity = readBool(ph["gravity"], "physics.gravity");
  s.physics.damping = readBool(ph["damping"], "physics.damping");
  s.physics.contact = readBool(ph["contact"], "physics.contact");
  s.physics.friction = readBool(ph["friction"], "physics.friction");
  s.physics.supply = readBool(ph["supply"], "physics.supply");
  s.physics.planar = readBool(ph["planar"], "physics.planar");
  s.supply.port_position_world = readVec3(r["supply"]["port_position"], "supply.port_position");
  {
    const double mp = readDouble(r["supply"]["max_points"], "supply.max_points");
    if (mp != std::floor(mp) || mp < 0.0 || mp > 1e7) {
      throw SceneError("supply.max_points", "must be a whole number from 0 to 1e7");
    }
    s.supply.max_points = static_cast<int>(mp);
  }

  s.gravity.acceleration_world = readVec3(r["gravity"]["acceleration"], "gravity.acceleration");
  s.damping.translational = readDouble(r["damping"]["translational"], "damping.translational");
  s.damping.rotational = readDouble(r["damping"]["rotational"], "damping.rotational");

  s.start.type = readString(r["start"]["type"], "start.type");
  s.start.frame = readString(r["start"]["frame"], "start.frame");
  s.start.position = readVec3(r["start"]["position"], "start.position");
  s.start.direction = readVec3(r["start"]["direction"], "start.direction");

  s.end.type = readString(r["end"]["type"], "end.type");
  s.end.load.clear();
  readEntries(r["end"]["load"], "end.load", {"time", "force", "moment"}, true,
              [&](const YAML::Node& k, const std::string& key) {
                LoadKeyframe f;
                f.time = readDouble(k["time"], key + ".time");
                if (k["force"]) f.force_world = readVec3(k["force"], key + ".force");
                if (k["moment"]) f.moment_world = readVec3(k["moment"], key + ".moment");
                s.end.load.push_back(f);
              });

  s.output.progress_interval_s =
      readDouble(r["output"]["progress_interval_s"], "output.progress_interval_s");
  return s;
}

// ---------------------------------------------------------------------------
// Merging user YAML over the defaults, refusing keys the schema lacks.
void mergeChecked(YAML::Node base, const YAML::Node& user, const std::string& prefix) {
  if (!user.IsMap()) {
    throw SceneError(prefix.empty() ? "(top level)" : prefix,
                     "expected a map of keys, got " + describe(user));
  }
  for (const auto& kv : user) {
    const std::string key = kv.first.Scalar();
    const std::string path = join(prefix, key);
    const YAML::Node& cbase = base;
    if (!cbase[key]) throw SceneError(path, "unknown key");
    YAML::Node target = base[key];
    if (target.IsMap()) {
      mergeChecked(target, kv.second, path);
    } else {
      base[key] = YAML::Clone(kv.second);
    }
  }
}

void applyOverride(YAML::Node root, const std::string& text) {
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw SceneError(text, "an override must look like key.path=value");
  }
  const std::string path = text.substr(0, eq);
  const std::string value = text.substr(eq + 1);
  YAML::Node parsed;
  try {
    parsed = YAML::Load(value);
  } catch (const YAML::Exception& e) {
    throw SceneError(path, "cannot parse value '" + value + "': " + e.msg);
  }
  // Build a one-key nested map and merge it like a scene file.
  std::vector<std::string> parts;
  std::stringstream ss(path);
  for (std::string part; std::getline(ss, part, '.');) {
    if (part.empty()) throw SceneError(path, "empty key in path");
    parts.push_back(part);
  }
  YAML::Node user = parsed;
  for (auto it = parts.rbegin(); it != parts.rend(); ++it) {
    YAML::Node m(YAML::NodeType::Map);
    m[*it] = user;
    user = m;
  }
  mergeChecked(root, user, "");
}

void requirePositive(double v, const std::string& key) {
  if (!(v > 0.0)) throw SceneError(key, "must be positive, got " + std::to_string(v));
}
void requireNonNegative(double v, const std::string& key) {
  if (!(v >= 0.0)) throw SceneError(key, "must not be negative, got " + std::to_string(v));
}

void validateHysteresis(const HysteresisParams& h, const std::string& key, const char* yield_key) {
  requirePositive(h.elastic_rigidity, key + ".elastic_rigidity");
  requireNonNegative(h.plastic_rigidity, key + ".plastic_rigidity");
  if (h.plastic_rigidity > h.elastic_rigidity) {
    throw SceneError(key + ".plastic_rigidity",
                     "plastic rigidity " + std::to_string(h.plastic_rigidity) +
                         " is above the elastic rigidity " + std::to_string(h.elastic_rigidity));
  }
  requirePositive(h.yield, key + "." + yield_key);
}

}  // namespace

int Scene::segmentCount() const {
  return static_cast<int>(std::ceil(wire.length / wire.segment_length - 1e-9));
}

double Scene::naturalSegmentLength() const { return wire.length / segmentCount(); }

double Scene::endTime() const {
  if (process.duration) return *process.duration;
  // Turns at the commanded speed; a core that starts at rest loses half its
  // ramp time to the acceleration.
  const double omega = std::abs(process.core_speed_rpm) * 2.0 * M_PI / 60.0;
  const double ramp = core.start_at_speed ? 0.0 : omega / core.max_angular_acceleration;
  return process.turns * 2.0 * M_PI / omega + 0.5 * ramp;
}

void validateScene(const Scene& s) {
  requirePositive(s.wire.diameter, "wire.diameter");
  requirePositive(s.wire.line_density, "wire.line_density");
  requirePositive(s.wire.length, "wire.length");
  requirePositive(s.wire.segment_length, "wire.segment_length");
  if (s.wire.segment_length > s.wire.length) {
    throw SceneError("wire.segment_length", "is longer than wire.length");
  }
  if (s.wire.length / s.wire.segment_length > 1.0e6) {
    throw SceneError("wire.segment_length", "gives more than 1e6 segments");
  }
  validateHysteresis(s.wire.stretch, "wire.stretch", "yield_strain");
  validateHysteresis(s.wire.bend, "wire.bend", "yield_curvature");
  validateHysteresis(s.wire.torsion, "wire.torsion", "yield_twist");

  requireNonNegative(s.contact.static_friction, "contact.static_friction");
  requireNonNegative(s.contact.kinetic_friction, "contact.kinetic_friction");
  if (s.contact.kinetic_friction > s.contact.static_friction) {
    throw SceneError("contact.kinetic_friction", "kinetic friction is above static friction");
  }

  requirePositive(s.contact.stiffness, "contact.stiffness");
  requirePositive(s.contact.stick_stiffness, "contact.stick_stiffness");
  requirePositive(s.contact.stick_speed, "contact.stick_speed");

  if (!(s.core.axis_world.norm() > 1e-12)) {
    throw SceneError("core.axis", "must not be the zero vector");
  }
  requirePositive(s.core.max_angular_acceleration, "core.max_angular_acceleration");
  for (std::size_t i = 0; i < s.core.cylinders.size(); ++i) {
    requirePositive(s.core.cylinders[i].radius, "core.cylinders[" + std::to_string(i) + "].radius");
  }
  for (std::size_t i = 0; i < s.core.faces.size(); ++i) {
    if (!((s.core.faces[i].to_core - s.core.faces[i].from_core).norm() > 0.0)) {
      throw SceneError("core.faces[" + std::to_string(i) + "]", "from and to coincide");
    }
  }
  if (s.core.hull_faces && s.core.cylinders.size() < 2) {
    throw SceneError("core.hull_faces", "needs at least two cylinders");
  }
  if (s.physics.contact && s.core.cylinders.empty() && s.core.faces.empty()) {
    throw SceneError("core.cylinders", "physics.contact needs at least one cylinder or face");
  }
  if (s.physics.friction && !s.physics.contact) {
    throw SceneError("physics.friction", "friction needs physics.contact");
  }
  if (s.physics.contact) {
    // No tunnelling: a segment must not pass a cylinder between two contact
    // checks of its points; the stated bound is l <= the smallest radius.
    for (std::size_t i = 0; i < s.core.cylinders.size(); ++i) {
      if (s.naturalSegmentLength() > s.core.cylinders[i].radius) {
        throw SceneError("wire.segment_length",
                         "segments longer than the radius of core.cylinders[" + std::to_string(i) +
                             "] could pass through it; use at most " +
                             std::to_string(s.core.cylinders[i].radius) + " m");
      }
    }
  }

  if (!std::isfinite(s.process.traverse_pitch)) {
    throw SceneError("process.traverse_pitch", "must be finite");
  }
  if (s.physics.supply) {
    if (s.core.cylinders.empty() && s.core.faces.empty()) {
      throw SceneError("core.cylinders",
                       "physics.supply winds wire onto a core: give at least one cylinder");
    }
    // The port must lie outside the core (the convex hull of its cylinders).
    const Eigen::Vector3d axis = s.core.axis_world.normalized();
    const RotatingCore core(s.core, 0.0);
    const Eigen::Vector3d port_core = core.pointCore(0.0, s.supply.port_position_world);
    const double gap = CoreSection(s.core).signedDistance(port_core.head<2>());
    if (gap <= 0.5 * s.wire.diameter) {
      throw SceneError("supply.port_position",
                       "lies inside the core (the convex hull of core.cylinders, widened by the "
                       "wire radius)");
    }
    Eigen::Vector3d clamp_world = s.start.position;
    if (s.start.frame == "core") clamp_world = core.pointWorld(0.0, s.start.position);
    if ((s.supply.port_position_world - clamp_world).norm() < 2.0 * s.wire.segment_length) {
      throw SceneError("supply.port_position",
                       "is closer to the clamp than two segments (wire.segment_length)");
    }
    if (s.physics.planar && s.process.traverse_pitch != 0.0) {
      throw SceneError("process.traverse_pitch",
                       "must be 0 with physics.planar (the port cannot leave the plane)");
    }
    if (s.physics.planar &&
        std::abs((s.supply.port_position_world - clamp_world).dot(axis)) > 1e-12) {
      throw SceneError(
          "supply.port_position",
          "must lie in the plane of the clamp normal to core.axis with physics.planar");
    }
  }
  if (s.physics.planar && s.physics.gravity &&
      std::abs(s.gravity.acceleration_world.dot(s.core.axis_world.normalized())) > 1e-12) {
    throw SceneError("gravity.acceleration",
                     "must lie in the plane normal to core.axis with physics.planar");
  }

  requireNonNegative(s.process.tension, "process.tension");
  requirePositive(s.process.max_core_speed_rpm, "process.max_core_speed_rpm");
  requirePositive(s.process.max_tension, "process.max_tension");
  if (std::abs(s.process.core_speed_rpm) > s.process.max_core_speed_rpm) {
    throw SceneError("process.core_speed_rpm", "is beyond process.max_core_speed_rpm");
  }
  if (s.process.tension > s.process.max_tension) {
    throw SceneError("process.tension", "is above process.max_tension");
  }
  requireNonNegative(s.process.turns, "process.turns");
  if (s.process.duration) {
    requirePositive(*s.process.duration, "process.duration");
  } else {
    requirePositive(s.process.turns, "process.turns");
    if (s.process.core_speed_rpm == 0.0) {
      throw SceneError("process.duration",
                       "must be given when process.core_speed_rpm is 0 (turns never end)");
    }
  }

  if (s.solver.integrator != "rkf45" && s.solver.integrator != "symplectic_euler" &&
      s.solver.integrator != "rosenbrock2") {
    throw SceneError("solver.integrator",
                     "unknown integrator '" + s.solver.integrator +
                         "' (available: rkf45, symplectic_euler, rosenbrock2)");
  }
  requirePositive(s.solver.fixed_step, "solver.fixed_step");
  if (s.solver.integrator == "symplectic_euler" && s.solver.fixed_step > s.solver.max_step) {
    throw SceneError("solver.fixed_step", "is above solver.max_step");
  }
  // Above the explicit stability limit symplectic Euler stays bounded but
  // wrong, with no warning (measured on the paper's case at 2 mm: three
  // wire diameters off at 1.05 l / c, right at 0.53 l / c).
  if (s.solver.integrator == "symplectic_euler") {
    const double limit = explicitStepLimit(s);
    if (s.solver.fixed_step > limit) {
      std::ostringstream why;
      why << s.solver.fixed_step << " s is above the stability limit l / c = " << limit
          << " s of this wire (the time a wave needs to cross a segment); symplectic_euler "
             "would run but be wrong: use at most that step, or rkf45";
      throw SceneError("solver.fixed_step", why.str());
    }
  }
  requirePositive(s.solver.rtol, "solver.rtol");
  requirePositive(s.solver.atol, "solver.atol");
  requirePositive(s.solver.min_step, "solver.min_step");
  requirePositive(s.solver.max_step, "solver.max_step");
  if (s.solver.max_step < s.solver.min_step) {
    throw SceneError("solver.max_step", "is below solver.min_step");
  }
  if (s.solver.initial_step < s.solver.min_step || s.solver.initial_step > s.solver.max_step) {
    throw SceneError("solver.initial_step", "must lie between solver.min_step and solver.max_step");
  }
  requireNonNegative(s.solver.baumgarte_nu, "solver.baumgarte_nu");

  requireNonNegative(s.damping.translational, "damping.translational");
  requireNonNegative(s.damping.rotational, "damping.rotational");

  if (s.start.type != "clamped") {
    throw SceneError("start.type", "unknown type '" + s.start.type + "' (available: clamped)");
  }
  if (s.start.frame != "world" && s.start.frame != "core") {
    throw SceneError("start.frame",
                     "unknown frame '" + s.start.frame + "' (available: world, core)");
  }
  if (!(s.start.direction.norm() > 1e-12)) {
    throw SceneError("start.direction", "must not be the zero vector");
  }

  if (s.end.type != "free") {
    throw SceneError("end.type", "unknown type '" + s.end.type + "' (available: free)");
  }
  for (std::size_t i = 0; i < s.end.load.size(); ++i) {
    const std::string key = "end.load[" + std::to_string(i) + "].time";
    requireNonNegative(s.end.load[i].time, key);
    if (i > 0 && !(s.end.load[i].time > s.end.load[i - 1].time)) {
      throw SceneError(key, "keyframe times must increase strictly");
    }
  }
  requirePositive(s.output.progress_interval_s, "output.progress_interval_s");
}

namespace {
// Merges the scene file at `path` into root: first its `base` file (a path
// relative to it), if it names one, then its own keys.
void mergeFile(YAML::Node root, const std::string& path, int depth) {
  if (depth > 8) throw SceneError("base", "more than 8 nested base files at '" + path + "'");
  YAML::Node user;
  try {
    user = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw SceneError("(file)", "cannot open scene file '" + path + "'");
  } catch (const YAML::Exception& e) {
    throw SceneError("(file)", "'" + path + "' is not valid YAML: " + e.what());
  }
  if (user.IsNull()) return;
  if (user.IsMap() && user["base"]) {
    const YAML::Node base = user["base"];
    if (!base.IsScalar()) throw SceneError("base", "expected a file name in '" + path + "'");
    const std::string dir = std::filesystem::path(path).parent_path().string();
    mergeFile(root, (std::filesystem::path(dir) / base.Scalar()).string(), depth + 1);
    user.remove("base");
  }
  mergeChecked(root, user, "");
}
}  // namespace

Scene loadScene(const std::string& path, const std::vector<std::string>& overrides) {
  YAML::Node root = toYaml(Scene{});
  if (!path.empty()) mergeFile(root, path, 0);
  for (const std::string& o : overrides) applyOverride(root, o);
  Scene s = fromYaml(root);
  validateScene(s);
  return s;
}

Scene sceneFromYamlText(const std::string& text) {
  YAML::Node root = toYaml(Scene{});
  YAML::Node user;
  try {
    user = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw SceneError("(text)", std::string("not valid YAML: ") + e.what());
  }
  if (!user.IsNull()) mergeChecked(root, user, "");
  Scene s = fromYaml(root);
  validateScene(s);
  return s;
}

std::string sceneToYamlText(const Scene& scene) {
  YAML::Emitter out;
  out.SetDoublePrecision(10);
  out << toYaml(scene);
  return std::string(out.c_str()) + "\n";
}

// A wave crosses a segment in l / c: axial c = sqrt(EA / rho); torsional
// c = sqrt(GJ / (2/5 rho r^2)), the frames' inertia per length.
double explicitStepLimit(const Scene& s) {
  const double l = s.physics.supply ? s.wire.segment_length : s.naturalSegmentLength();
  double c = std::sqrt(s.wire.stretch.elastic_rigidity / s.wire.line_density);
  if (s.physics.torsion) {
    const double r = 0.5 * s.wire.diameter;
    c = std::max(c,
                 std::sqrt(s.wire.torsion.elastic_rigidity / (0.4 * s.wire.line_density * r * r)));
  }
  return l / c;
}

}  // namespace cws
