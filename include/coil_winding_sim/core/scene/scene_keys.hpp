// The scene keys: one declaration per key of the YAML schema.
//
// Every key of a scene file is declared once, in the table of
// src/core/scene/scene_keys.cpp, with its dotted name, unit, allowed range, one
// line of documentation and its field of the Scene struct. Reading YAML,
// writing it (sceneToYamlText), the key=value overrides and the single-key
// range checks of validateScene all walk that table, in its order (which is
// the order of the printed scene). Rules that relate several keys are
// written by hand in src/core/scene/scene_validation.cpp.
//
// Adding a key: a field in scene.hpp and one line in the table (plus, when
// it constrains other keys, one cross-key rule).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "coil_winding_sim/core/scene/scene.hpp"

namespace YAML {
class Node;
}

namespace cws {

// The values a key allows beyond its type. Every number must also be
// finite; a list checks its entries itself (ListKeyHandlers::check).
struct KeyRange {
  enum Kind {
    kAny,          // any value of the type
    kPositive,     // > 0
    kNonNegative,  // >= 0
    kDirection,    // a vector of length above 1e-12 whose length does not overflow
    kOneOf,        // one of `words`
    kPointCount,   // a whole number of points; beyond +-(kMaxScenePoints + 1) no int holds it
    kCount,        // a whole number from 0 to `most` (read), at least `least` (validated)
  };
  Kind kind = kAny;
  std::vector<std::string> words;  // kOneOf: the allowed words
  int most = 0;                    // kCount
  std::optional<int> least;        // kCount: checked by validateScene when set
  // An optional number: the word for "unset" in a scene file (e.g. `auto`);
  // empty: YAML's null (~).
  std::string unset_word;
};

// Calls fn(key, value) for each number of a scene, vectors by component
// ("core.axis[2]").
using NumberVisitor = std::function<void(const std::string& key, double value)>;

// A list-valued key (core.cylinders, core.faces, end.load): hand-written
// handlers for what the table does for the other keys. `key` is the list's
// dotted name, for messages.
struct ListKeyHandlers {
  // Reads the whole list from `node`, the value at `key` of a merged scene.
  void (*read)(const YAML::Node& node, const std::string& key, Scene& s);
  YAML::Node (*write)(const Scene& s);
  void (*forEachNumber)(const Scene& s, const std::string& key, const NumberVisitor& fn);
  // The entries' own ranges; throws SceneError naming the entry's key.
  void (*check)(const Scene& s, const std::string& key);
};

// Typed access to the field of one key in a Scene.
template <class T>
struct KeyField {
  T& (*ref)(Scene&);
  const T& (*get)(const Scene&);
};

using KeyAccess =
    std::variant<KeyField<double>, KeyField<std::optional<double>>, KeyField<Eigen::Vector3d>,
                 KeyField<bool>, KeyField<std::string>, KeyField<int>, const ListKeyHandlers*>;

struct SceneKey {
  std::string name;  // dotted path, e.g. "contact.stick_speed"
  std::string unit;  // e.g. "m/s"; "-" dimensionless; "" for words, switches and lists
  KeyRange range;
  std::string doc;  // one line
  KeyAccess access;

  // The value's kind as a word: number, optional number, vector, switch,
  // word, count or list.
  const char* type() const;
};

// Every key, in the order of the printed scene.
const std::vector<SceneKey>& sceneKeys();

// The key named `name` (dotted), or nullptr.
const SceneKey* findSceneKey(const std::string& name);

// Why the key named `name` (dotted) is no longer a scene key and what
// took its place, or nullptr: a scene file that sets it is refused with
// this.
const char* removedSceneKey(const std::string& name);
// The same for a value of a word key that went (an integrator): why, or
// nullptr.
const char* removedSceneWord(const std::string& key, const std::string& value);

}  // namespace cws
