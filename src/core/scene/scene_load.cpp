// Loading scenes: user YAML merged over the defaults (the tree the key table
// writes, which is also the schema), key=value overrides, scene files with
// their base files, and the public entry points loadScene,
// sceneFromYamlText and sceneToYamlText.
#include <yaml-cpp/eventhandler.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <memory>
#include <sstream>

#include "coil_winding_sim/core/scene/core_geometry.hpp"
#include "coil_winding_sim/core/scene/wire_catalogue.hpp"
#include "scene_detail.hpp"

namespace cws {

namespace {
using detail::describe;
using detail::join;
using detail::keysOf;
using detail::printable;

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
      if (const char* why = removedSceneKey(path)) throw SceneError(path, why);
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

// ---------------------------------------------------------------------------
// Scene files and text.

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
    const int error = errno;
    // A relative path is the working directory's: say which file that was.
    std::string tried;
    if (!std::filesystem::path(path).is_absolute()) {
      tried = " (tried " +
              printable(std::filesystem::absolute(path, ec).lexically_normal().string(), 4096) +
              ")";
    }
    throw SceneError(
        "(file)", "cannot open scene file '" + shown + "'" + tried + ": " + std::strerror(error));
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

// ---------------------------------------------------------------------------
// The public entry points: defaults, then the user's keys, then what other
// keys make, then validation.
namespace {
// The wire's keys that wire.material and its size make where they are
// given as `auto`.
const char* const kMadeWireKeys[] = {
    "wire.diameter",
    "wire.line_density",
    "wire.stretch.elastic_rigidity",
    "wire.stretch.plastic_rigidity",
    "wire.stretch.yield_strain",
    "wire.bend.elastic_rigidity",
    "wire.bend.plastic_rigidity",
    "wire.bend.yield_curvature",
    "wire.torsion.elastic_rigidity",
    "wire.torsion.plastic_rigidity",
    "wire.torsion.yield_twist",
};

// The built-in defaults as the tree a scene's keys merge into: the wire's
// made keys at `auto` (paper_table_1 makes the defaults' values).
YAML::Node defaultsTree() {
  const Scene defaults;
  YAML::Node root = detail::toYaml(defaults);
  for (const char* key : kMadeWireKeys) detail::setAt(root, key, YAML::Node("auto"));
  return root;
}

// Writes the made values into the tree where it holds `auto`; the keys it
// made, and from what.
std::vector<std::string> makeWireKeys(YAML::Node& root, std::string& made_from) {
  auto isAuto = [&](const char* key) {
    const YAML::Node n = detail::nodeAt(root, key);
    return n.IsScalar() && n.Scalar() == "auto";
  };
  if (std::none_of(std::begin(kMadeWireKeys), std::end(kMadeWireKeys), isAuto)) return {};
  const std::string material =
      detail::readString(detail::nodeAt(root, "wire.material"), "wire.material");
  const double nominal =
      detail::readDouble(detail::nodeAt(root, "wire.nominal_diameter"), "wire.nominal_diameter");
  const int grade =
      detail::readCount(detail::nodeAt(root, "wire.insulation_grade"), "wire.insulation_grade", 3);
  // A given overall diameter serves for the enamel's mass.
  const double overall =
      isAuto("wire.diameter")
          ? 0.0
          : detail::readDouble(detail::nodeAt(root, "wire.diameter"), "wire.diameter");
  const MadeWire w = makeWire(material, nominal, grade, overall);
  // In the order of kMadeWireKeys.
  const double values[] = {w.diameter,
                           w.line_density,
                           w.stretch.elastic_rigidity,
                           w.stretch.plastic_rigidity,
                           w.stretch.yield,
                           w.bend.elastic_rigidity,
                           w.bend.plastic_rigidity,
                           w.bend.yield,
                           w.torsion.elastic_rigidity,
                           w.torsion.plastic_rigidity,
                           w.torsion.yield};
  static_assert(std::size(values) == std::size(kMadeWireKeys));
  std::vector<std::string> made;
  for (std::size_t k = 0; k < std::size(kMadeWireKeys); ++k) {
    if (!isAuto(kMadeWireKeys[k])) continue;
    detail::setAt(root, kMadeWireKeys[k], detail::num(values[k]));
    made.emplace_back(kMadeWireKeys[k]);
  }
  made_from = "wire.material " + material;
  if (material != "paper_table_1") {
    made_from += ", wire.nominal_diameter " + detail::fmt(nominal) + " m, wire.insulation_grade " +
                 std::to_string(grade);
  }
  return made;
}

// The merged tree made a scene: the values made from other keys (the
// wire's, the core's shape), its keys read, then every rule checked.
Scene sceneOf(YAML::Node root) {
  std::string made_from;
  std::vector<std::string> made = makeWireKeys(root, made_from);
  Scene s = detail::fromYaml(root);
  s.made_keys = std::move(made);
  s.made_from = std::move(made_from);
  applyCoreShape(s.core);
  validateScene(s);
  return s;
}
}  // namespace

Scene loadScene(const std::string& path, const std::vector<std::string>& overrides) {
  YAML::Node root = defaultsTree();
  if (!path.empty()) mergeFile(root, path, 0);
  for (const std::string& o : overrides) applyOverride(root, o);
  return sceneOf(root);
}

Scene sceneFromYamlText(const std::string& text) {
  YAML::Node root = defaultsTree();
  const YAML::Node user = parseOne(text, "(text)", "the scene text");
  if (!user.IsNull()) mergeChecked(root, user, "");
  return sceneOf(root);
}

std::string sceneToYamlText(const Scene& scene) {
  YAML::Emitter out;
  out.SetDoublePrecision(10);
  out << detail::toYaml(scene);
  std::string text = std::string(out.c_str()) + "\n";
  // What the scene made from other keys, for the reader.
  if (!scene.made_keys.empty()) {
    text += "# made from " + scene.made_from +
            " (docs/MODEL.md, \"Wire from a material and a size\"):\n";
    for (const std::string& key : scene.made_keys) text += "#   " + key + "\n";
  }
  return text;
}

}  // namespace cws
