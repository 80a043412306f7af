// The list-valued scene keys: core.cylinders, core.faces, end.load and
// process.commands. Each
// has hand-written handlers (read, write, numbers, own checks), registered
// in the key table (scene_keys.cpp) like any other key.
#include <cmath>
#include <string>

#include "scene_detail.hpp"

namespace cws::detail {

namespace {
std::string entryKey(const std::string& key, std::size_t i) {
  return key + "[" + std::to_string(i) + "]";
}

template <class Vec>
void visitVector(const Vec& v, const std::string& key, const NumberVisitor& fn) {
  for (int i = 0; i < v.size(); ++i) fn(key + "[" + std::to_string(i) + "]", v[i]);
}

// ---------------------------------------------------------------------------
// core.cylinders: [{center: [x, y] [m], radius [m] > 0}, ...], radius optional.
void readCylinders(const YAML::Node& n, const std::string& key, Scene& s) {
  s.core.cylinders.clear();
  readEntries(n, key, {"center", "radius"}, {"center"}, false,
              [&](const YAML::Node& c, const std::string& entry) {
                CylinderParams cp;
                cp.center_core = readVec2(c["center"], entry + ".center");
                if (c["radius"]) cp.radius = readDouble(c["radius"], entry + ".radius");
                s.core.cylinders.push_back(cp);
              });
}

YAML::Node writeCylinders(const Scene& s) {
  YAML::Node list(YAML::NodeType::Sequence);
  for (const CylinderParams& c : s.core.cylinders) {
    YAML::Node entry;
    entry["center"] = vec2(c.center_core);
    entry["radius"] = num(c.radius);
    list.push_back(entry);
  }
  return list;
}

void cylinderNumbers(const Scene& s, const std::string& key, const NumberVisitor& fn) {
  for (std::size_t i = 0; i < s.core.cylinders.size(); ++i) {
    visitVector(s.core.cylinders[i].center_core, entryKey(key, i) + ".center", fn);
    fn(entryKey(key, i) + ".radius", s.core.cylinders[i].radius);
  }
}

void checkCylinders(const Scene& s, const std::string& key) {
  for (std::size_t i = 0; i < s.core.cylinders.size(); ++i) {
    requirePositive(s.core.cylinders[i].radius, entryKey(key, i) + ".radius");
  }
}

// ---------------------------------------------------------------------------
// core.faces: [{from: [x, y], to: [x, y]} [m], ...], from and to apart.
void readFaces(const YAML::Node& n, const std::string& key, Scene& s) {
  s.core.faces.clear();
  readEntries(n, key, {"from", "to"}, {"from", "to"}, false,
              [&](const YAML::Node& f, const std::string& entry) {
                s.core.faces.push_back(FaceParams{readVec2(f["from"], entry + ".from"),
                                                  readVec2(f["to"], entry + ".to")});
              });
}

YAML::Node writeFaces(const Scene& s) {
  YAML::Node list(YAML::NodeType::Sequence);
  for (const FaceParams& f : s.core.faces) {
    YAML::Node entry;
    entry["from"] = vec2(f.from_core);
    entry["to"] = vec2(f.to_core);
    list.push_back(entry);
  }
  return list;
}

void faceNumbers(const Scene& s, const std::string& key, const NumberVisitor& fn) {
  for (std::size_t i = 0; i < s.core.faces.size(); ++i) {
    visitVector(s.core.faces[i].from_core, entryKey(key, i) + ".from", fn);
    visitVector(s.core.faces[i].to_core, entryKey(key, i) + ".to", fn);
  }
}

void checkFaces(const Scene& s, const std::string& key) {
  for (std::size_t i = 0; i < s.core.faces.size(); ++i) {
    const std::string entry = entryKey(key, i);
    if (!((s.core.faces[i].to_core - s.core.faces[i].from_core).norm() > 0.0)) {
      throw SceneError(entry, entry + ".from and " + entry + ".to coincide");
    }
  }
}

// ---------------------------------------------------------------------------
// end.load: [{time [s], force [N], moment [N m]}, ...], at least one, times
// >= 0 and strictly increasing; force and moment optional.
void readLoad(const YAML::Node& n, const std::string& key, Scene& s) {
  s.end.load.clear();
  readEntries(n, key, {"time", "force", "moment"}, {"time"}, true,
              [&](const YAML::Node& k, const std::string& entry) {
                LoadKeyframe f;
                f.time = readDouble(k["time"], entry + ".time");
                if (k["force"]) f.force_world = readVec3(k["force"], entry + ".force");
                if (k["moment"]) f.moment_world = readVec3(k["moment"], entry + ".moment");
                s.end.load.push_back(f);
              });
}

YAML::Node writeLoad(const Scene& s) {
  YAML::Node list(YAML::NodeType::Sequence);
  for (const LoadKeyframe& k : s.end.load) {
    YAML::Node entry;
    entry["time"] = num(k.time);
    entry["force"] = vec3(k.force_world);
    entry["moment"] = vec3(k.moment_world);
    list.push_back(entry);
  }
  return list;
}

void loadNumbers(const Scene& s, const std::string& key, const NumberVisitor& fn) {
  for (std::size_t i = 0; i < s.end.load.size(); ++i) {
    fn(entryKey(key, i) + ".time", s.end.load[i].time);
    visitVector(s.end.load[i].force_world, entryKey(key, i) + ".force", fn);
    visitVector(s.end.load[i].moment_world, entryKey(key, i) + ".moment", fn);
  }
}

void checkLoad(const Scene& s, const std::string& key) {
  if (s.end.load.empty()) {
    throw SceneError(key, "needs at least one keyframe {time, force, moment}");
  }
  for (std::size_t i = 0; i < s.end.load.size(); ++i) {
    const std::string time = entryKey(key, i) + ".time";
    requireNonNegative(s.end.load[i].time, time);
    if (i > 0 && !(s.end.load[i].time > s.end.load[i - 1].time)) {
      throw SceneError(time, "keyframe times must increase strictly: " + fmt(s.end.load[i].time) +
                                 " s is not after " + entryKey(key, i - 1) +
                                 ".time = " + fmt(s.end.load[i - 1].time) + " s");
    }
  }
}

// ---------------------------------------------------------------------------
// process.commands: [{time [s], core_speed_rpm [rpm], tension [N]}, ...],
// each with time and at least one setpoint, times not decreasing; each
// setpoint within the process's limits (process.max_core_speed_rpm,
// process.max_tension), as the cell's own setpoints are.
void readCommands(const YAML::Node& n, const std::string& key, Scene& s) {
  s.process.commands.clear();
  readEntries(n, key, {"time", "core_speed_rpm", "tension"}, {"time"}, false,
              [&](const YAML::Node& c, const std::string& entry) {
                ProcessCommand pc;
                pc.time = readDouble(c["time"], entry + ".time");
                if (c["core_speed_rpm"]) {
                  pc.core_speed_rpm = readDouble(c["core_speed_rpm"], entry + ".core_speed_rpm");
                }
                if (c["tension"]) pc.tension = readDouble(c["tension"], entry + ".tension");
                if (!pc.core_speed_rpm && !pc.tension) {
                  throw SceneError(entry, "gives no setpoint: add core_speed_rpm or tension");
                }
                s.process.commands.push_back(pc);
              });
}

YAML::Node writeCommands(const Scene& s) {
  YAML::Node list(YAML::NodeType::Sequence);
  for (const ProcessCommand& c : s.process.commands) {
    YAML::Node entry;
    entry["time"] = num(c.time);
    if (c.core_speed_rpm) entry["core_speed_rpm"] = num(*c.core_speed_rpm);
    if (c.tension) entry["tension"] = num(*c.tension);
    list.push_back(entry);
  }
  return list;
}

void commandNumbers(const Scene& s, const std::string& key, const NumberVisitor& fn) {
  for (std::size_t i = 0; i < s.process.commands.size(); ++i) {
    const ProcessCommand& c = s.process.commands[i];
    fn(entryKey(key, i) + ".time", c.time);
    if (c.core_speed_rpm) fn(entryKey(key, i) + ".core_speed_rpm", *c.core_speed_rpm);
    if (c.tension) fn(entryKey(key, i) + ".tension", *c.tension);
  }
}

void checkCommands(const Scene& s, const std::string& key) {
  const ProcessParams& p = s.process;
  for (std::size_t i = 0; i < p.commands.size(); ++i) {
    const ProcessCommand& c = p.commands[i];
    const std::string time = entryKey(key, i) + ".time";
    requireNonNegative(c.time, time);
    if (i > 0 && c.time < p.commands[i - 1].time) {
      throw SceneError(time, "command times must not decrease: " + fmt(c.time) + " s is before " +
                                 entryKey(key, i - 1) + ".time = " + fmt(p.commands[i - 1].time) +
                                 " s");
    }
    if (c.core_speed_rpm && !p.duration) {
      throw SceneError(entryKey(key, i) + ".core_speed_rpm",
                       "changes the core speed, so process.turns does not say when the job "
                       "ends: give process.duration [s]");
    }
    if (c.core_speed_rpm && !(std::abs(*c.core_speed_rpm) <= p.max_core_speed_rpm)) {
      throw SceneError(entryKey(key, i) + ".core_speed_rpm",
                       fmt(*c.core_speed_rpm) + " rpm is beyond process.max_core_speed_rpm = " +
                           fmt(p.max_core_speed_rpm) + " rpm");
    }
    if (c.tension && !(*c.tension >= 0.0 && *c.tension <= p.max_tension)) {
      throw SceneError(entryKey(key, i) + ".tension",
                       fmt(*c.tension) +
                           " N is outside 0 to process.max_tension = " + fmt(p.max_tension) + " N");
    }
  }
}
}  // namespace

const ListKeyHandlers kCylinderList{readCylinders, writeCylinders, cylinderNumbers, checkCylinders};
const ListKeyHandlers kFaceList{readFaces, writeFaces, faceNumbers, checkFaces};
const ListKeyHandlers kLoadList{readLoad, writeLoad, loadNumbers, checkLoad};
const ListKeyHandlers kCommandList{readCommands, writeCommands, commandNumbers, checkCommands};

}  // namespace cws::detail
