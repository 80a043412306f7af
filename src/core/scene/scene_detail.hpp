// Internal helpers shared by the scene sources (not part of the public API):
// message text, YAML values, the table-driven conversions and checks.
#pragma once

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "coil_winding_sim/core/scene/scene.hpp"
#include "coil_winding_sim/core/scene/scene_keys.hpp"

namespace cws::detail {

// ---------------------------------------------------------------------------
// Message text (scene_text.cpp).

// "prefix.key", or "key" at the top.
std::string join(const std::string& prefix, const std::string& key);
// User text for a message: control characters and bytes that are not UTF-8
// escaped as \xNN, text longer than `max` bytes cut short.
std::string printable(const std::string& text, std::size_t max = 60);
// A number for a message: six significant digits.
std::string fmt(double v);
// What a node holds, for "expected ..., got ..." messages.
std::string describe(const YAML::Node& n);
// " (line N)" of a node in its text, or "" for a node built in code.
std::string lineOf(const YAML::Node& n, const char* what = "line");

// ---------------------------------------------------------------------------
// YAML values (scene_yaml.cpp); every reader names its key in its errors.

// A number as a plain scalar, as short as round-trips exactly.
YAML::Node num(double v);
YAML::Node vec2(const Eigen::Vector2d& v);  // flow list [x, y]
YAML::Node vec3(const Eigen::Vector3d& v);  // flow list [x, y, z]

double readDouble(const YAML::Node& n, const std::string& key);
std::string readString(const YAML::Node& n, const std::string& key);
// A whole number from 0 to `most`.
int readCount(const YAML::Node& n, const std::string& key, int most);
Eigen::Vector2d readVec2(const YAML::Node& n, const std::string& key);
Eigen::Vector3d readVec3(const YAML::Node& n, const std::string& key);

// The names of the keys of `map` (the map at `path`, "" at the top), in
// order; refuses a key that is not a plain name and a key given twice.
std::vector<std::string> keysOf(const YAML::Node& map, const std::string& path);

// Reads the list of maps at `key`, each entry with only the `allowed` keys
// and all of the `required` ones, calling read(entry, "key[i]").
void readEntries(const YAML::Node& list, const std::string& key,
                 const std::vector<std::string>& allowed, const std::vector<std::string>& required,
                 bool non_empty,
                 const std::function<void(const YAML::Node&, const std::string&)>& read);

// The scene as a YAML tree (every key, in table order) and back; fromYaml
// reads a tree that has every key (the defaults with a user's merged over).
YAML::Node toYaml(const Scene& s);
// The node at a dotted key name, and the value set there.
YAML::Node nodeAt(const YAML::Node& root, const std::string& name);
void setAt(YAML::Node root, const std::string& name, const YAML::Node& value);
Scene fromYaml(const YAML::Node& root);

// ---------------------------------------------------------------------------
// The table's checks (scene_keys.cpp).

// Every number of the scene, in table order (lists by entry).
void forEachNumber(const Scene& s, const NumberVisitor& fn);
// The range of one key; throws SceneError naming it.
void checkRange(const SceneKey& key, const Scene& s);
// Single values, for the lists' and the cross-key checks.
void requirePositive(double v, const std::string& key);
void requireNonNegative(double v, const std::string& key);

// The handlers of the list-valued keys (scene_lists.cpp).
extern const ListKeyHandlers kCylinderList;
extern const ListKeyHandlers kFaceList;
extern const ListKeyHandlers kLoadList;
extern const ListKeyHandlers kCommandList;

// ---------------------------------------------------------------------------
// Geometry of a scene at t = 0 (scene.cpp).

// The clamp (start.position) in the world frame at t = 0.
Eigen::Vector3d clampWorldAtStart(const Scene& s);
// A world point in the core frame at t = 0.
Eigen::Vector3d coreFrameAtStart(const Scene& s, const Eigen::Vector3d& p_world);

}  // namespace cws::detail
