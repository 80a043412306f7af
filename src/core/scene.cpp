#include "coil_winding_sim/core/scene.hpp"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
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
  root["solver"]["implicit_step"] = num(s.solver.implicit_step);
  root["solver"]["newton_tol"] = num(s.solver.newton_tol);
  root["solver"]["newton_max_iterations"] = s.solver.newton_max_iterations;
  root["solver"]["flag_rounds"] = s.solver.flag_rounds;
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

// Length of the valid UTF-8 sequence at text[i], or 0 if there is none.
std::size_t utf8Length(const std::string& text, std::size_t i) {
  const unsigned char c = static_cast<unsigned char>(text[i]);
  const std::size_t n = c < 0x80           ? 1
                        : (c >> 5) == 0x6  ? 2
                        : (c >> 4) == 0xe  ? 3
                        : (c >> 3) == 0x1e ? 4
                                           : 0;
  if (n == 0 || i + n > text.size()) return 0;
  for (std::size_t k = 1; k < n; ++k) {
    if ((static_cast<unsigned char>(text[i + k]) & 0xc0) != 0x80) return 0;
  }
  return n;
}

// User text for a message: control characters and bytes that are not
// UTF-8 escaped as \xNN (a scene may hold any bytes; a message goes to a
// terminal or a log), text longer than `max` bytes cut short.
std::string printable(const std::string& text, std::size_t max = 60) {
  const std::string cut = text.substr(0, max);
  std::string out;
  for (std::size_t i = 0; i < cut.size();) {
    const unsigned char c = static_cast<unsigned char>(cut[i]);
    const std::size_t n = utf8Length(cut, i);
    if (n == 0 || c < 0x20 || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
      ++i;
    } else {
      out.append(cut, i, n);
      i += n;
    }
  }
  return text.size() > max ? out + "..." : out;
}

// A number for a message: six significant digits (std::to_string would
// print 1e-9 as 0.000000).
std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string describe(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Null:
      return "nothing (null)";
    case YAML::NodeType::Sequence:
      return "a list of " + std::to_string(n.size());
    case YAML::NodeType::Map:
      return "a map";
    default:
      return "'" + printable(n.Scalar()) + "'";
  }
}

// " (line N)" of a node in its text (1-based), for messages; empty if the
// node has no position (one built in code).
std::string lineOf(const YAML::Node& n, const char* what = "line") {
  const YAML::Mark m = n.Mark();
  return m.is_null() ? std::string()
                     : " (" + std::string(what) + " " + std::to_string(m.line + 1) + ")";
}

double readDouble(const YAML::Node& n, const std::string& key) {
  if (!n.IsScalar()) throw SceneError(key, "expected a number, got " + describe(n));
  double v = 0.0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    // A number beyond the range of a double (1e400) is a number, but too
    // large (or too small) to use: say so rather than "not a number".
    errno = 0;
    char* end = nullptr;
    const char* text = n.Scalar().c_str();
    std::strtod(text, &end);
    if (end != text && *end == '\0' && errno == ERANGE) {
      throw SceneError(key, describe(n) + " is beyond the range of a double");
    }
    throw SceneError(key, "expected a number, got " + describe(n));
  }
  if (!std::isfinite(v)) {
    throw SceneError(key, "must be a finite number, got " + printable(n.Scalar()));
  }
  return v;
}

// A whole number from 0 to `most`.
int readCount(const YAML::Node& n, const std::string& key, int most) {
  const double v = readDouble(n, key);
  if (v != std::floor(v) || v < 0.0 || v > most) {
    throw SceneError(key, "must be a whole number from 0 to " + std::to_string(most) + ", got " +
                              printable(n.Scalar()));
  }
  return static_cast<int>(v);
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

// The names of the keys of `map` (the map at `path`, "" at the top), in
// order. Refuses a key that is not a plain name (a list, a map or null used
// as a key) and a key given twice: YAML forbids the second, and silently
// keeping either value would hide a mistake.
std::vector<std::string> keysOf(const YAML::Node& map, const std::string& path) {
  std::vector<std::string> names;
  for (const auto& kv : map) {
    if (!kv.first.IsScalar()) {
      throw SceneError(path.empty() ? "(top level)" : path,
                       "a key must be a name, got " + describe(kv.first) + lineOf(kv.first));
    }
    const std::string name = printable(kv.first.Scalar());
    const auto seen = std::find(names.begin(), names.end(), name);
    if (seen != names.end()) {
      throw SceneError(join(path, name), "given twice" + lineOf(kv.first, "again at line"));
    }
    names.push_back(name);
  }
  return names;
}

// Reads the list of maps at `key`, each entry with only the `allowed` keys
// and all of the `required` ones, calling read(entry, "key[i]"); every
// refusal names the entry or its key.
template <class Fn>
void readEntries(const YAML::Node& list, const std::string& key,
                 const std::vector<std::string>& allowed, const std::vector<std::string>& required,
                 bool non_empty, Fn read) {
  std::string names;
  for (const std::string& a : allowed) names += (names.empty() ? "" : ", ") + a;
  if (!list.IsSequence() || (non_empty && list.size() == 0)) {
    throw SceneError(key, std::string("expected a ") + (non_empty ? "non-empty " : "") +
                              "list of {" + names + "}, got " + describe(list));
  }
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string entry_key = key + "[" + std::to_string(i) + "]";
    const YAML::Node entry = list[i];
    if (!entry.IsMap()) {
      throw SceneError(entry_key, "expected a map {" + names + "}, got " + describe(entry));
    }
    const std::vector<std::string> present = keysOf(entry, entry_key);
    for (const std::string& name : present) {
      if (std::find(allowed.begin(), allowed.end(), name) == allowed.end()) {
        throw SceneError(entry_key + "." + name, "unknown key (allowed: " + names + ")");
      }
    }
    for (const std::string& name : required) {
      if (std::find(present.begin(), present.end(), name) == present.end()) {
        throw SceneError(entry_key + "." + name, "missing (every entry of " + key + " needs it)");
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
  readEntries(core["cylinders"], "core.cylinders", {"center", "radius"}, {"center"}, false,
              [&](const YAML::Node& c, const std::string& key) {
                CylinderParams cp;
                cp.center_core = readVec2(c["center"], key + ".center");
                if (c["radius"]) cp.radius = readDouble(c["radius"], key + ".radius");
                s.core.cylinders.push_back(cp);
              });
  readEntries(core["faces"], "core.faces", {"from", "to"}, {"from", "to"}, false,
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
  s.solver.implicit_step = readDouble(so["implicit_step"], "solver.implicit_step");
  s.solver.newton_tol = readDouble(so["newton_tol"], "solver.newton_tol");
  s.solver.newton_max_iterations =
      readCount(so["newton_max_iterations"], "solver.newton_max_iterations", 1000);
  s.solver.flag_rounds = readCount(so["flag_rounds"], "solver.flag_rounds", 100);
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
    // Only what the conversion to int needs; validateScene checks the range.
    const double mp = readDouble(r["supply"]["max_points"], "supply.max_points");
    if (mp != std::floor(mp)) {
      throw SceneError("supply.max_points", "must be a whole number, got " + fmt(mp));
    }
    if (std::abs(mp) > kMaxScenePoints + 1.0) {  // far beyond the limit: no int for it
      throw SceneError("supply.max_points", fmt(mp) + " is above the limit of " +
                                                std::to_string(kMaxScenePoints) + " points");
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
  readEntries(r["end"]["load"], "end.load", {"time", "force", "moment"}, {"time"}, true,
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
  keysOf(user, prefix);  // plain names, none twice
  for (const auto& kv : user) {
    const std::string key = kv.first.Scalar();
    const std::string path = join(prefix, printable(key));
    const YAML::Node& cbase = base;
    if (!cbase[key]) {
      std::string known;
      for (const auto& b : cbase) known += (known.empty() ? "" : ", ") + b.first.Scalar();
      throw SceneError(path, "unknown key (" + (prefix.empty() ? std::string("a scene") : prefix) +
                                 " has: " + known + ")");
    }
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
  // A path that goes on below a value (wire.diameter.x) names no key.
  std::vector<YAML::Node> chain{root};
  std::string walked;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    const YAML::Node& here = chain.back();
    const YAML::Node next = here[parts[i]];
    if (!next) break;  // an unknown key: mergeChecked names it
    walked = join(walked, parts[i]);
    if (next.IsSequence()) {
      throw SceneError(path, "'" + walked + "' is a list, set as a whole: " + walked + "=[...]");
    }
    if (!next.IsMap()) {
      throw SceneError(path, "'" + walked + "' is a value, not a section with keys");
    }
    chain.push_back(next);
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
  if (!(v > 0.0)) throw SceneError(key, "must be positive, got " + fmt(v));
}
void requireNonNegative(double v, const std::string& key) {
  if (!(v >= 0.0)) throw SceneError(key, "must not be negative, got " + fmt(v));
}
// A direction: not zero, and short enough that its length does not overflow
// (normalizing [1e300, 1e300, 0] would give the zero vector).
void requireDirection(const Eigen::Vector3d& v, const std::string& key) {
  const double norm = v.norm();
  if (!(norm > 1e-12) || !std::isfinite(norm)) {
    throw SceneError(key,
                     "must be a direction: a vector of length above 1e-12 whose length "
                     "does not overflow, got length " +
                         fmt(norm));
  }
}

void validateHysteresis(const HysteresisParams& h, const std::string& key, const char* yield_key) {
  requirePositive(h.elastic_rigidity, key + ".elastic_rigidity");
  requireNonNegative(h.plastic_rigidity, key + ".plastic_rigidity");
  if (h.plastic_rigidity > h.elastic_rigidity) {
    throw SceneError(key + ".plastic_rigidity",
                     fmt(h.plastic_rigidity) + " is above the elastic rigidity " + key +
                         ".elastic_rigidity = " + fmt(h.elastic_rigidity));
  }
  requirePositive(h.yield, key + "." + yield_key);
}

// The clamp at t = 0 in the world frame.
Eigen::Vector3d clampWorldAtStart(const Scene& s) {
  if (s.start.frame != "core") return s.start.position;
  return RotatingCore(s.core, 0.0).pointWorld(0.0, s.start.position);
}

// Calls fn(key, value) for every number of the scene, vectors by component.
template <class Fn>
void forEachNumber(const Scene& s, Fn fn) {
  auto vec = [&](const auto& v, const std::string& key) {
    for (int i = 0; i < v.size(); ++i) fn(key + "[" + std::to_string(i) + "]", v[i]);
  };
  auto law = [&](const HysteresisParams& h, const std::string& key, const char* yield_key) {
    fn(key + ".elastic_rigidity", h.elastic_rigidity);
    fn(key + ".plastic_rigidity", h.plastic_rigidity);
    fn(key + "." + yield_key, h.yield);
  };
  fn("wire.diameter", s.wire.diameter);
  fn("wire.line_density", s.wire.line_density);
  fn("wire.length", s.wire.length);
  fn("wire.segment_length", s.wire.segment_length);
  law(s.wire.stretch, "wire.stretch", "yield_strain");
  law(s.wire.bend, "wire.bend", "yield_curvature");
  law(s.wire.torsion, "wire.torsion", "yield_twist");
  fn("contact.static_friction", s.contact.static_friction);
  fn("contact.kinetic_friction", s.contact.kinetic_friction);
  fn("contact.stiffness", s.contact.stiffness);
  fn("contact.stick_stiffness", s.contact.stick_stiffness);
  fn("contact.stick_speed", s.contact.stick_speed);
  vec(s.core.position_world, "core.position");
  vec(s.core.axis_world, "core.axis");
  fn("core.max_angular_acceleration", s.core.max_angular_acceleration);
  for (std::size_t i = 0; i < s.core.cylinders.size(); ++i) {
    const std::string key = "core.cylinders[" + std::to_string(i) + "]";
    vec(s.core.cylinders[i].center_core, key + ".center");
    fn(key + ".radius", s.core.cylinders[i].radius);
  }
  for (std::size_t i = 0; i < s.core.faces.size(); ++i) {
    const std::string key = "core.faces[" + std::to_string(i) + "]";
    vec(s.core.faces[i].from_core, key + ".from");
    vec(s.core.faces[i].to_core, key + ".to");
  }
  vec(s.supply.port_position_world, "supply.port_position");
  fn("process.core_speed_rpm", s.process.core_speed_rpm);
  fn("process.tension", s.process.tension);
  fn("process.traverse_pitch", s.process.traverse_pitch);
  fn("process.max_core_speed_rpm", s.process.max_core_speed_rpm);
  fn("process.max_tension", s.process.max_tension);
  fn("process.turns", s.process.turns);
  if (s.process.duration) fn("process.duration", *s.process.duration);
  fn("solver.rtol", s.solver.rtol);
  fn("solver.atol", s.solver.atol);
  fn("solver.min_step", s.solver.min_step);
  fn("solver.max_step", s.solver.max_step);
  fn("solver.initial_step", s.solver.initial_step);
  fn("solver.fixed_step", s.solver.fixed_step);
  fn("solver.baumgarte_nu", s.solver.baumgarte_nu);
  fn("solver.implicit_step", s.solver.implicit_step);
  fn("solver.newton_tol", s.solver.newton_tol);
  vec(s.gravity.acceleration_world, "gravity.acceleration");
  fn("damping.translational", s.damping.translational);
  fn("damping.rotational", s.damping.rotational);
  vec(s.start.position, "start.position");
  vec(s.start.direction, "start.direction");
  for (std::size_t i = 0; i < s.end.load.size(); ++i) {
    const std::string key = "end.load[" + std::to_string(i) + "]";
    fn(key + ".time", s.end.load[i].time);
    vec(s.end.load[i].force_world, key + ".force");
    vec(s.end.load[i].moment_world, key + ".moment");
  }
  fn("output.progress_interval_s", s.output.progress_interval_s);
}

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

double Scene::modelSegmentLength() const {
  return physics.supply ? wire.segment_length : naturalSegmentLength();
}

double Scene::initialPoints() const {
  if (!physics.supply) return std::ceil(wire.length / wire.segment_length - 1e-9) + 1.0;
  const double span = (supply.port_position_world - clampWorldAtStart(*this)).norm();
  return std::ceil(span / wire.segment_length - 1e-9);
}

double Scene::pointCapacity() const {
  const double n = initialPoints();
  if (!physics.supply) return n;
  if (supply.max_points > 0) return std::max(n, static_cast<double>(supply.max_points));
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
  const double angle = std::abs(process.core_speed_rpm * 2.0 * M_PI / 60.0) * endTime();
  Eigen::Vector3d port_rel = supply.port_position_world - core.position_world;
  port_rel -= port_rel.dot(axis) * axis;
  const double fed = angle * r_max + 2.0 * port_rel.norm();
  return n + std::ceil(1.2 * fed / wire.segment_length) + 8.0;
}

void validateScene(const Scene& s) {
  // Scenes built in code may hold what YAML cannot: refuse any non-finite
  // number first, by its key.
  forEachNumber(s, [](const std::string& key, double v) {
    if (!std::isfinite(v)) throw SceneError(key, "must be a finite number, got " + fmt(v));
  });

  requirePositive(s.wire.diameter, "wire.diameter");
  requirePositive(s.wire.line_density, "wire.line_density");
  requirePositive(s.wire.length, "wire.length");
  requirePositive(s.wire.segment_length, "wire.segment_length");
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
  validateHysteresis(s.wire.stretch, "wire.stretch", "yield_strain");
  validateHysteresis(s.wire.bend, "wire.bend", "yield_curvature");
  validateHysteresis(s.wire.torsion, "wire.torsion", "yield_twist");

  requireNonNegative(s.contact.static_friction, "contact.static_friction");
  requireNonNegative(s.contact.kinetic_friction, "contact.kinetic_friction");
  if (s.contact.kinetic_friction > s.contact.static_friction) {
    throw SceneError("contact.kinetic_friction",
                     fmt(s.contact.kinetic_friction) +
                         " is above static friction, contact.static_friction = " +
                         fmt(s.contact.static_friction));
  }

  requirePositive(s.contact.stiffness, "contact.stiffness");
  requirePositive(s.contact.stick_stiffness, "contact.stick_stiffness");
  requirePositive(s.contact.stick_speed, "contact.stick_speed");

  requireDirection(s.core.axis_world, "core.axis");
  requirePositive(s.core.max_angular_acceleration, "core.max_angular_acceleration");
  for (std::size_t i = 0; i < s.core.cylinders.size(); ++i) {
    requirePositive(s.core.cylinders[i].radius, "core.cylinders[" + std::to_string(i) + "].radius");
  }
  for (std::size_t i = 0; i < s.core.faces.size(); ++i) {
    const std::string key = "core.faces[" + std::to_string(i) + "]";
    if (!((s.core.faces[i].to_core - s.core.faces[i].from_core).norm() > 0.0)) {
      throw SceneError(key, key + ".from and " + key + ".to coincide");
    }
  }
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
  if (s.physics.contact) {
    // No tunnelling: a segment must not pass a cylinder between two contact
    // checks of its points; the stated bound is l <= the smallest radius.
    for (std::size_t i = 0; i < s.core.cylinders.size(); ++i) {
      if (s.modelSegmentLength() > s.core.cylinders[i].radius) {
        const std::string radius = "core.cylinders[" + std::to_string(i) + "].radius";
        throw SceneError("wire.segment_length",
                         "segments of " + fmt(s.modelSegmentLength()) +
                             " m (from wire.segment_length and wire.length) are longer than " +
                             radius + " = " + fmt(s.core.cylinders[i].radius) +
                             " m and could pass through that cylinder; use at most " +
                             fmt(s.core.cylinders[i].radius) + " m");
      }
    }
  }

  if (s.physics.supply) {
    if (s.core.cylinders.empty() && s.core.faces.empty()) {
      throw SceneError("core.cylinders",
                       "physics.supply winds wire onto a core: give at least one entry in "
                       "core.cylinders or core.faces");
    }
    // The port must lie outside the core (the convex hull of its cylinders).
    const Eigen::Vector3d axis = s.core.axis_world.normalized();
    const RotatingCore core(s.core, 0.0);
    const Eigen::Vector3d port_core = core.pointCore(0.0, s.supply.port_position_world);
    const double gap = CoreSection(s.core).signedDistance(port_core.head<2>());
    if (!(gap > 0.5 * s.wire.diameter)) {
      throw SceneError("supply.port_position",
                       "lies inside the core (the convex hull of core.cylinders and core.faces "
                       "about core.position and core.axis, widened by the wire radius, half of "
                       "wire.diameter)");
    }
    const Eigen::Vector3d clamp_world = clampWorldAtStart(s);
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
  if (s.physics.planar && s.physics.gravity &&
      std::abs(s.gravity.acceleration_world.dot(s.core.axis_world.normalized())) > 1e-12) {
    throw SceneError("gravity.acceleration",
                     "must lie in the plane normal to core.axis with physics.planar and "
                     "physics.gravity");
  }

  requireNonNegative(s.process.tension, "process.tension");
  requirePositive(s.process.max_core_speed_rpm, "process.max_core_speed_rpm");
  requirePositive(s.process.max_tension, "process.max_tension");
  if (std::abs(s.process.core_speed_rpm) > s.process.max_core_speed_rpm) {
    throw SceneError("process.core_speed_rpm", fmt(s.process.core_speed_rpm) +
                                                   " is beyond process.max_core_speed_rpm = " +
                                                   fmt(s.process.max_core_speed_rpm));
  }
  if (s.process.tension > s.process.max_tension) {
    throw SceneError(
        "process.tension",
        fmt(s.process.tension) + " is above process.max_tension = " + fmt(s.process.max_tension));
  }
  requireNonNegative(s.process.turns, "process.turns");
  if (s.process.duration) {
    requirePositive(*s.process.duration, "process.duration");
  } else {
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

  // Storage: the points the model reserves, bounded before it converts the
  // counts to int or allocates anything.
  if (s.physics.supply) {
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
    const double capacity = s.pointCapacity();
    if (!(capacity <= kMaxScenePoints)) {
      throw SceneError(s.process.duration ? "process.duration" : "process.turns",
                       "the wire drawn in during the run needs an estimated " + fmt(capacity) +
                           " points, more than the limit of " + std::to_string(kMaxScenePoints) +
                           " (the estimate comes from " + kSupplyEstimateKeys +
                           "); shorten the run or set supply.max_points");
    }
  }

  if (s.solver.integrator != "rkf45" && s.solver.integrator != "symplectic_euler" &&
      s.solver.integrator != "rosenbrock2" && s.solver.integrator != "implicit_euler" &&
      s.solver.integrator != "bdf2") {
    throw SceneError("solver.integrator",
                     "unknown integrator '" + printable(s.solver.integrator) +
                         "' (available: rkf45, symplectic_euler, rosenbrock2, implicit_euler, "
                         "bdf2)");
  }
  if ((s.solver.integrator == "implicit_euler" || s.solver.integrator == "bdf2") &&
      !s.physics.planar) {
    throw SceneError("solver.integrator",
                     s.solver.integrator +
                         " integrates planar scenes (physics.planar: true) only; use "
                         "symplectic_euler or rkf45 for a 3-D scene");
  }
  requirePositive(s.solver.implicit_step, "solver.implicit_step");
  requirePositive(s.solver.newton_tol, "solver.newton_tol");
  if (s.solver.newton_max_iterations < 1) {
    throw SceneError("solver.newton_max_iterations",
                     "must be at least 1, got " + std::to_string(s.solver.newton_max_iterations));
  }
  requirePositive(s.solver.fixed_step, "solver.fixed_step");
  if (s.solver.integrator == "symplectic_euler" && s.solver.fixed_step > s.solver.max_step) {
    throw SceneError("solver.fixed_step",
                     fmt(s.solver.fixed_step) +
                         " s is above solver.max_step = " + fmt(s.solver.max_step) + " s");
  }
  // Above the explicit stability limit symplectic Euler stays bounded but
  // wrong, with no warning (measured on the paper's case at 2 mm: three
  // wire diameters off at 1.05 l / c, right at 0.53 l / c).
  if (s.solver.integrator == "symplectic_euler") {
    const double limit = explicitStepLimit(s);
    if (s.solver.fixed_step > limit) {
      std::ostringstream why;
      why << s.solver.fixed_step << " s is above the stability limit l / c = " << limit
          << " s of this wire (the time a wave needs to cross a segment l from "
          << "wire.segment_length and wire.length, at the wave speed c from "
          << "wire.stretch.elastic_rigidity, wire.line_density and, with physics.torsion, "
          << "wire.torsion.elastic_rigidity and wire.diameter); symplectic_euler "
          << "(solver.integrator) would run but be wrong: use at most that step, or rkf45";
      throw SceneError("solver.fixed_step", why.str());
    }
  }
  requirePositive(s.solver.rtol, "solver.rtol");
  requirePositive(s.solver.atol, "solver.atol");
  requirePositive(s.solver.min_step, "solver.min_step");
  requirePositive(s.solver.max_step, "solver.max_step");
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
  requireNonNegative(s.solver.baumgarte_nu, "solver.baumgarte_nu");

  requireNonNegative(s.damping.translational, "damping.translational");
  requireNonNegative(s.damping.rotational, "damping.rotational");

  if (s.start.type != "clamped") {
    throw SceneError("start.type",
                     "unknown type '" + printable(s.start.type) + "' (available: clamped)");
  }
  if (s.start.frame != "world" && s.start.frame != "core") {
    throw SceneError("start.frame",
                     "unknown frame '" + printable(s.start.frame) + "' (available: world, core)");
  }
  requireDirection(s.start.direction, "start.direction");

  if (s.end.type != "free") {
    throw SceneError("end.type", "unknown type '" + printable(s.end.type) + "' (available: free)");
  }
  if (s.end.load.empty()) {
    throw SceneError("end.load", "needs at least one keyframe {time, force, moment}");
  }
  for (std::size_t i = 0; i < s.end.load.size(); ++i) {
    const std::string key = "end.load[" + std::to_string(i) + "].time";
    requireNonNegative(s.end.load[i].time, key);
    if (i > 0 && !(s.end.load[i].time > s.end.load[i - 1].time)) {
      throw SceneError(key, "keyframe times must increase strictly: " + fmt(s.end.load[i].time) +
                                " s is not after end.load[" + std::to_string(i - 1) +
                                "].time = " + fmt(s.end.load[i - 1].time) + " s");
    }
  }
  requirePositive(s.output.progress_interval_s, "output.progress_interval_s");
}

namespace {
// Records where each document starts, ignoring everything else.
class DocumentStarts : public YAML::EventHandler {
 public:
  std::vector<YAML::Mark> starts;
  void OnDocumentStart(const YAML::Mark& mark) override { starts.push_back(mark); }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t,
                const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                       YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                  YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}
};

// The one YAML document of `text` (null if it has none), refused under
// `key` with `what` (the file) named: text that is not YAML (yaml-cpp's
// message gives line and column), more than one document (YAML::Load would
// silently drop all but the first), and text yaml-cpp cannot read on after
// its first document (a stray ',' or ']' at the top level, which
// YAML::Load silently drops; YAML::LoadAll never returns on it and
// allocates until memory runs out, yaml-cpp 0.7 issue 1040). The documents
// are therefore counted by the parser, a bounded number of times.
YAML::Node parseOne(const std::string& text, const std::string& key, const std::string& what) {
  YAML::Node doc;
  DocumentStarts docs;
  try {
    doc = YAML::Load(text);
    std::istringstream in(text);
    YAML::Parser parser(in);
    while (docs.starts.size() < 3 && parser.HandleNextDocument(docs)) {
    }
  } catch (const YAML::Exception& e) {
    throw SceneError(key, what + " is not valid YAML: " + printable(e.what(), 300));
  }
  for (std::size_t i = 1; i < docs.starts.size(); ++i) {
    const YAML::Mark& m = docs.starts[i];
    if (m.pos == docs.starts[i - 1].pos) {
      throw SceneError(key, what + " is not valid YAML: at line " + std::to_string(m.line + 1) +
                                ", column " + std::to_string(m.column + 1) +
                                " the text cannot be read on (a stray ',' or bracket?)");
    }
  }
  if (docs.starts.size() > 1) {
    throw SceneError(key, what +
                              " holds more than one YAML document (separated by ---); a "
                              "scene is one");
  }
  return doc;
}

// Scene files are small; anything larger (such as /dev/zero) is not one.
constexpr std::size_t kMaxSceneFileBytes = 16u << 20;

// The text of the scene file at `path`. A directory, a file that cannot be
// opened or read (an I/O error), and a file too large to be a scene are
// refused by its path.
std::string readSceneFile(const std::string& path) {
  const std::string shown = printable(path, 4096);  // a path may hold any bytes
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw SceneError("(file)", "'" + shown + "' is a directory, not a scene file");
  }
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) {
    throw SceneError("(file)", "cannot open scene file '" + shown + "': " + std::strerror(errno));
  }
  std::string text;
  char buf[1 << 16];
  for (std::size_t got; (got = std::fread(buf, 1, sizeof buf, f.get())) > 0;) {
    text.append(buf, got);
    if (text.size() > kMaxSceneFileBytes) {
      throw SceneError("(file)", "'" + shown + "' is larger than 16 MiB, not a scene file");
    }
  }
  if (std::ferror(f.get())) {
    throw SceneError("(file)", "cannot read scene file '" + shown + "': " + std::strerror(errno));
  }
  return text;
}

// Merges the scene file at `path` into root: first its `base` file (a path
// relative to it), if it names one, then its own keys.
void mergeFile(YAML::Node root, const std::string& path, int depth) {
  const std::string shown = printable(path, 4096);  // a path may hold any bytes
  if (depth > 8) throw SceneError("base", "more than 8 nested base files at '" + shown + "'");
  const std::string text = readSceneFile(path);
  YAML::Node user = parseOne(text, "(file)", "'" + shown + "'");
  // An empty file is more likely a failed write (print-scene > file after an
  // error) than a wish for the defaults, which `{}` states.
  if (user.IsNull()) {
    throw SceneError("(file)", "'" + shown +
                                   "' holds no settings (it is empty or only comments); write {} "
                                   "for a scene of the defaults");
  }
  if (!user.IsMap()) {
    throw SceneError("(top level)",
                     "'" + shown + "' must hold a map of keys, got " + describe(user));
  }
  keysOf(user, "");  // plain names, none twice (base included)
  if (user["base"]) {
    const YAML::Node base = user["base"];
    if (!base.IsScalar()) throw SceneError("base", "expected a file name in '" + shown + "'");
    const std::string dir = std::filesystem::path(path).parent_path().string();
    try {
      mergeFile(root, (std::filesystem::path(dir) / base.Scalar()).string(), depth + 1);
    } catch (const SceneError& e) {
      // Name the file that asked for the base too.
      throw SceneError(e.key(), e.why() + " (in the base file of '" + shown + "')");
    }
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
  const YAML::Node user = parseOne(text, "(text)", "the scene text");
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
  const double l = s.modelSegmentLength();
  double c = std::sqrt(s.wire.stretch.elastic_rigidity / s.wire.line_density);
  if (s.physics.torsion) {
    const double r = 0.5 * s.wire.diameter;
    c = std::max(c,
                 std::sqrt(s.wire.torsion.elastic_rigidity / (0.4 * s.wire.line_density * r * r)));
  }
  return l / c;
}

}  // namespace cws
