// Scene <-> YAML tree, key by key from the table (scene_keys.cpp), with the
// readers of single values; every conversion names its key.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <variant>

#include "scene_detail.hpp"

namespace cws::detail {

// ---------------------------------------------------------------------------
// Values -> YAML. Numbers as plain scalars, as short as round-trips exactly
// (so that a printed scene, and a snapshot's scene, load back bit-identical).
YAML::Node num(double v) {
  char buf[32];
  for (int digits = 10; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return YAML::Node(std::string(buf));
}

YAML::Node vec2(const Eigen::Vector2d& v) {
  YAML::Node n(YAML::NodeType::Sequence);
  n.SetStyle(YAML::EmitterStyle::Flow);
  for (int i = 0; i < 2; ++i) n.push_back(num(v[i]));
  return n;
}

YAML::Node vec3(const Eigen::Vector3d& v) {
  YAML::Node n(YAML::NodeType::Sequence);
  n.SetStyle(YAML::EmitterStyle::Flow);
  for (int i = 0; i < 3; ++i) n.push_back(num(v[i]));
  return n;
}

// ---------------------------------------------------------------------------
// YAML -> values.
// A scalar that spells a number beyond the range of a double (1e400).
static bool rangeError(const YAML::Node& n) {
  errno = 0;
  char* end = nullptr;
  const char* text = n.Scalar().c_str();
  std::strtod(text, &end);
  return end != text && *end == '\0' && errno == ERANGE;
}

double readDouble(const YAML::Node& n, const std::string& key) {
  if (!n.IsScalar()) throw SceneError(key, "expected a number, got " + describe(n));
  double v = 0.0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    // A number beyond the range of a double (1e400) is a number, but too
    // large (or too small) to use: say so rather than "not a number".
    if (rangeError(n)) {
      throw SceneError(key, describe(n) + " is beyond the range of a double");
    }
    throw SceneError(key, "expected a number, got " + describe(n));
  }
  if (!std::isfinite(v)) {
    throw SceneError(key, "must be a finite number, got " + printable(n.Scalar()));
  }
  return v;
}

namespace {
bool readBool(const YAML::Node& n, const std::string& key) {
  if (!n.IsScalar()) throw SceneError(key, "expected true or false, got " + describe(n));
  try {
    return n.as<bool>();
  } catch (const YAML::Exception&) {
    throw SceneError(key, "expected true or false, got " + describe(n));
  }
}

}  // namespace

std::string readString(const YAML::Node& n, const std::string& key) {
  if (!n.IsScalar()) throw SceneError(key, "expected a word, got " + describe(n));
  return n.Scalar();
}

namespace {
// A count of points: only what the conversion to int needs; validateScene
// checks the range.
int readPointCount(const YAML::Node& n, const std::string& key) {
  const double v = readDouble(n, key);
  if (v != std::floor(v)) throw SceneError(key, "must be a whole number, got " + fmt(v));
  if (std::abs(v) > kMaxScenePoints + 1.0) {  // far beyond the limit: no int for it
    throw SceneError(
        key, fmt(v) + " is above the limit of " + std::to_string(kMaxScenePoints) + " points");
  }
  return static_cast<int>(v);
}

}  // namespace

// A whole number from 0 to `most`.
int readCount(const YAML::Node& n, const std::string& key, int most) {
  const double v = readDouble(n, key);
  if (v != std::floor(v) || v < 0.0 || v > most) {
    throw SceneError(key, "must be a whole number from 0 to " + std::to_string(most) + ", got " +
                              printable(n.Scalar()));
  }
  return static_cast<int>(v);
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

// A key given twice is refused: YAML forbids the second, and silently
// keeping either value would hide a mistake.
std::vector<std::string> keysOf(const YAML::Node& map, const std::string& path) {
  std::vector<std::string> names;
  for (const auto& kv : map) {
    if (!kv.first.IsScalar()) {
      throw SceneError(path.empty() ? "(top level)" : path,
                       "a key must be a name, got " + describe(kv.first) + lineOf(kv.first));
    }
    if (kv.first.Scalar().empty()) {
      throw SceneError(path.empty() ? "(top level)" : path,
                       "a key must be a name, got an empty one" + lineOf(kv.first));
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

// Every refusal names the entry or its key.
void readEntries(const YAML::Node& list, const std::string& key,
                 const std::vector<std::string>& allowed, const std::vector<std::string>& required,
                 bool non_empty,
                 const std::function<void(const YAML::Node&, const std::string&)>& read) {
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

// ---------------------------------------------------------------------------
// The whole scene, from the table.
namespace {
std::vector<std::string> splitDotted(const std::string& name) {
  std::vector<std::string> parts;
  for (std::size_t at = 0;;) {
    const std::size_t dot = name.find('.', at);
    parts.push_back(name.substr(at, dot - at));
    if (dot == std::string::npos) return parts;
    at = dot + 1;
  }
}

}  // namespace

// A chain of nodes rather than one reassigned variable: assigning to a
// yaml-cpp node overwrites the node it refers to.
void setAt(YAML::Node root, const std::string& name, const YAML::Node& value) {
  const std::vector<std::string> parts = splitDotted(name);
  std::vector<YAML::Node> chain{root};
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) chain.push_back(chain.back()[parts[i]]);
  chain.back()[parts.back()] = value;
}

YAML::Node nodeAt(const YAML::Node& root, const std::string& name) {
  std::vector<YAML::Node> chain{root};
  for (const std::string& part : splitDotted(name)) {
    const YAML::Node& here = chain.back();
    chain.push_back(here[part]);
  }
  return chain.back();
}

namespace {
// One key's value as YAML.
struct ValueToYaml {
  const Scene& s;
  const SceneKey& k;
  YAML::Node operator()(const KeyField<double>& f) const { return num(f.get(s)); }
  YAML::Node operator()(const KeyField<std::optional<double>>& f) const {
    const std::optional<double>& v = f.get(s);
    if (v) return num(*v);
    return k.range.unset_word.empty() ? YAML::Node(YAML::NodeType::Null)
                                      : YAML::Node(k.range.unset_word);
  }
  YAML::Node operator()(const KeyField<Eigen::Vector3d>& f) const { return vec3(f.get(s)); }
  YAML::Node operator()(const KeyField<bool>& f) const { return YAML::Node(f.get(s)); }
  YAML::Node operator()(const KeyField<std::string>& f) const { return YAML::Node(f.get(s)); }
  YAML::Node operator()(const KeyField<int>& f) const { return YAML::Node(f.get(s)); }
  YAML::Node operator()(const ListKeyHandlers* list) const { return list->write(s); }
};

// One key's value from YAML into the scene.
struct ValueFromYaml {
  const YAML::Node& n;
  const SceneKey& k;
  Scene& s;
  const std::string& key = k.name;
  void operator()(const KeyField<double>& f) const { f.ref(s) = readDouble(n, key); }
  void operator()(const KeyField<std::optional<double>>& f) const {
    const std::string& word = k.range.unset_word;
    if (word.empty()) {
      f.ref(s) = n.IsNull() ? std::nullopt : std::optional<double>(readDouble(n, key));
    } else if (n.IsScalar() && n.Scalar() == word) {
      f.ref(s) = std::nullopt;
    } else {
      // Anything else must be a number: a stray word names both choices.
      double v = 0.0;
      if (!n.IsScalar() || (!YAML::convert<double>::decode(n, v) && !rangeError(n))) {
        throw SceneError(key, "expected a number or '" + word + "', got " + describe(n));
      }
      f.ref(s) = readDouble(n, key);
    }
  }
  void operator()(const KeyField<Eigen::Vector3d>& f) const { f.ref(s) = readVec3(n, key); }
  void operator()(const KeyField<bool>& f) const { f.ref(s) = readBool(n, key); }
  void operator()(const KeyField<std::string>& f) const { f.ref(s) = readString(n, key); }
  void operator()(const KeyField<int>& f) const {
    f.ref(s) =
        k.range.kind == KeyRange::kCount ? readCount(n, key, k.range.most) : readPointCount(n, key);
  }
  void operator()(const ListKeyHandlers* list) const { list->read(n, key, s); }
};
}  // namespace

YAML::Node toYaml(const Scene& s) {
  // A map from the start: a copy of a null node would not share its children.
  YAML::Node root(YAML::NodeType::Map);
  for (const SceneKey& k : sceneKeys())
    setAt(root, k.name, std::visit(ValueToYaml{s, k}, k.access));
  return root;
}

Scene fromYaml(const YAML::Node& root) {
  Scene s;
  for (const SceneKey& k : sceneKeys()) {
    const YAML::Node n = nodeAt(root, k.name);
    std::visit(ValueFromYaml{n, k, s}, k.access);
  }
  return s;
}

}  // namespace cws::detail
