// Unit tests of the scene key table (cws::sceneKeys): the documented schema
// config/scenes/default.yaml holds exactly the declared keys, the printed
// scene writes them in table order, and every key can be set by an override
// and has its range checked under its own name.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <set>
#include <string>
#include <variant>
#include <vector>

#include "coil_winding_sim/core/scene/scene.hpp"
#include "coil_winding_sim/core/scene/scene_keys.hpp"

namespace {

// The leaves of a YAML tree as dotted names, in order: every value that is
// not a map (a number, a word, a vector, a list of entries, null).
void leaves(const YAML::Node& n, const std::string& path, std::vector<std::string>& out) {
  if (!n.IsMap()) {
    out.push_back(path);
    return;
  }
  for (const auto& kv : n) {
    const std::string key = kv.first.as<std::string>();
    leaves(kv.second, path.empty() ? key : path + "." + key, out);
  }
}

std::vector<std::string> declaredNames() {
  std::vector<std::string> names;
  for (const cws::SceneKey& k : cws::sceneKeys()) names.push_back(k.name);
  return names;
}

// The names of `a` that `b` lacks, one per line.
std::string missingFrom(const std::vector<std::string>& a, const std::vector<std::string>& b) {
  const std::set<std::string> in_b(b.begin(), b.end());
  std::string out;
  for (const std::string& name : a) {
    if (!in_b.count(name)) out += "  " + name + "\n";
  }
  return out;
}

// The documented schema: every declared key is in default.yaml, and nothing
// else is.
TEST(SceneKeys, DefaultYamlDocumentsExactlyTheDeclaredKeys) {
  const std::string path = std::string(CWS_SOURCE_DIR) + "/config/scenes/default.yaml";
  std::vector<std::string> documented;
  leaves(YAML::LoadFile(path), "", documented);
  const std::vector<std::string> declared = declaredNames();
  EXPECT_EQ(missingFrom(declared, documented), "")
      << "declared scene keys that " << path << " does not document";
  EXPECT_EQ(missingFrom(documented, declared), "")
      << "keys in " << path << " that no scene key declares";
}

// The printed scene is written from the table: the same keys, in its order.
TEST(SceneKeys, PrintedSceneHasTheDeclaredKeysInOrder) {
  std::vector<std::string> printed;
  leaves(YAML::Load(cws::sceneToYamlText(cws::Scene{})), "", printed);
  EXPECT_EQ(printed, declaredNames());
}

TEST(SceneKeys, EveryKeyIsDescribed) {
  ASSERT_FALSE(cws::sceneKeys().empty());
  for (const cws::SceneKey& k : cws::sceneKeys()) {
    EXPECT_FALSE(k.doc.empty()) << k.name;
    const std::string type = k.type();
    if (type == "number" || type == "optional number" || type == "vector") {
      EXPECT_FALSE(k.unit.empty()) << k.name << ": a " << type << " needs a unit";
    }
    if (k.range.kind == cws::KeyRange::kOneOf) {
      EXPECT_FALSE(k.range.words.empty()) << k.name;
    }
    EXPECT_EQ(cws::findSceneKey(k.name), &k) << k.name;
  }
  EXPECT_EQ(cws::findSceneKey("wire.no_such_key"), nullptr);
}

// Each key can be set by a key=value override (here to its printed default
// value), through the same table.
TEST(SceneKeys, EveryKeyTakesAnOverride) {
  const YAML::Node printed = YAML::Load(cws::sceneToYamlText(cws::Scene{}));
  for (const cws::SceneKey& k : cws::sceneKeys()) {
    std::vector<YAML::Node> chain{printed};
    std::string rest = k.name;
    for (std::size_t dot; (dot = rest.find('.')) != std::string::npos;
         rest = rest.substr(dot + 1)) {
      chain.push_back(chain.back()[rest.substr(0, dot)]);
    }
    YAML::Emitter out;
    out << YAML::Flow << chain.back()[rest];
    const std::string text = out.c_str();
    EXPECT_NO_THROW(cws::loadScene("", {k.name + "=" + text})) << k.name << "=" << text;
  }
}

// Each single-key range refuses a value outside it by the key's name.
struct OutOfRange {
  const cws::SceneKey& k;
  cws::Scene& s;
  bool operator()(const cws::KeyField<double>& f) const { return number(f.ref(s)); }
  bool operator()(const cws::KeyField<std::optional<double>>& f) const {
    f.ref(s) = 1.0;
    return number(*f.ref(s));
  }
  bool operator()(const cws::KeyField<Eigen::Vector3d>& f) const {
    if (k.range.kind != cws::KeyRange::kDirection) return false;
    f.ref(s) = Eigen::Vector3d::Zero();
    return true;
  }
  bool operator()(const cws::KeyField<std::string>& f) const {
    f.ref(s) = "no_such_" + k.name;
    return true;
  }
  bool operator()(const cws::KeyField<bool>&) const { return false; }
  bool operator()(const cws::KeyField<int>&) const { return false; }
  bool operator()(const cws::ListKeyHandlers*) const { return false; }
  bool number(double& v) const {
    if (k.range.kind == cws::KeyRange::kPositive) v = 0.0;
    if (k.range.kind == cws::KeyRange::kNonNegative) v = -1.0;
    return k.range.kind == cws::KeyRange::kPositive || k.range.kind == cws::KeyRange::kNonNegative;
  }
};

TEST(SceneKeys, RangesRefuseByTheKeysName) {
  int checked = 0;
  for (const cws::SceneKey& k : cws::sceneKeys()) {
    cws::Scene s;
    if (!std::visit(OutOfRange{k, s}, k.access)) continue;
    ++checked;
    try {
      cws::validateScene(s);
      ADD_FAILURE() << k.name << ": a value out of its range was accepted";
    } catch (const cws::SceneError& e) {
      EXPECT_EQ(e.key(), k.name) << e.what();
    }
  }
  EXPECT_GT(checked, 30);
}

}  // namespace
