// Shared by the scene fuzz tests (test_scene_fuzz.cpp, test_scene_fuzz_keys.cpp):
// a reproducible generator, the seed scenes, structured mutations of them,
// what a refusal must say, and the fixture.
#pragma once

#include <cxxabi.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <typeinfo>
#include <vector>

#include "coil_winding_sim/core/base/ode_system.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"
#include "temp_dir_test.hpp"

namespace scene_fuzz {

namespace fs = std::filesystem;

// splitmix64: the draws are the same with every standard library (the
// std:: distributions are not).
class Rng {
 public:
  Rng(std::uint64_t seed, std::uint64_t index) : s_(seed * 0x9e3779b97f4a7c15ULL + index) {
    next();
  }
  std::uint64_t next() {
    std::uint64_t z = (s_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  std::size_t below(std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(next() % n); }
  template <class T>
  const T& pick(const std::vector<T>& v) {
    return v[below(v.size())];
  }

 private:
  std::uint64_t s_;
};

inline std::uint64_t envOr(const char* name, std::uint64_t fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::strtoull(v, nullptr, 0) : fallback;
}

inline std::string readAll(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

inline std::string join(const std::string& prefix, const std::string& key) {
  return prefix.empty() ? key : prefix + "." + key;
}

// Text for a failure message: control characters and non-ASCII bytes
// escaped, long text cut short.
inline std::string shown(const std::string& text, std::size_t max = 200) {
  std::string out;
  for (const char ch : text.substr(0, max)) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (c < 0x20 || c >= 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    } else {
      out += ch;
    }
  }
  return text.size() > max ? out + "..." : out;
}

// ---------------------------------------------------------------------------
// The seeds: the package's scene files as they are, and the printed default
// scene (every key of the schema).
struct SeedScene {
  std::string name;
  std::string text;
  bool has_base = false;  // `base:` is resolved by loadScene only
  YAML::Node tree;
};

inline std::vector<SeedScene> seedScenes() {
  const fs::path root = CWS_SOURCE_DIR;
  std::vector<SeedScene> seeds;
  for (const char* rel : {"config/scenes/default.yaml", "config/scenes/cantilever_plastic.yaml",
                          "config/scenes/paper_case_3d.yaml", "test/scenes/spinning_wire.yaml"}) {
    const fs::path path = root / rel;
    SeedScene s;
    s.name = rel;
    s.text = readAll(path);
    // A relative base file would not be found from the temporary directory.
    const std::string tag = "base: ";
    const std::size_t at = s.text.find(tag);
    if (at != std::string::npos) {
      const std::size_t end = s.text.find('\n', at);
      const std::string base = s.text.substr(at + tag.size(), end - at - tag.size());
      const std::string abs = fs::weakly_canonical(path.parent_path() / base).string();
      s.text.replace(at + tag.size(), base.size(), abs);
      s.has_base = true;
    }
    s.tree = YAML::Load(s.text);
    seeds.push_back(s);
  }
  SeedScene printed;
  printed.name = "sceneToYamlText(Scene{})";
  printed.text = cws::sceneToYamlText(cws::Scene{});
  printed.tree = YAML::Load(printed.text);
  seeds.push_back(printed);
  return seeds;
}

// ---------------------------------------------------------------------------
// Structured mutations: one edit of the seed's tree at a key path, written
// back as flow-style YAML (which can also hold a key twice).
struct Mutation {
  enum Op { kReplace, kDelete, kDuplicate, kInsertUnknown, kAppend } op = kReplace;
  std::string path;   // the node edited (for kInsertUnknown: the new key)
  std::string value;  // YAML flow text: the new value, or the appended entry

  std::string describe() const {
    static const char* names[] = {"replace", "delete", "duplicate", "insert unknown key",
                                  "append to list"};
    std::string d = std::string(names[op]) + " at '" + path + "'";
    if (op == kReplace || op == kAppend || op == kInsertUnknown)
      d += " value '" + shown(value) + "'";
    return d;
  }
};

// Junk values, as YAML flow text: wrong types, empty and null, numbers that
// are huge, tiny, negative, zero, non-finite or beyond a double, and
// numbers in forms YAML or the C library might read differently.
inline const std::vector<std::string> kJunk = {
    "hello",  "\"\"",        "\"x y\"",      "~",           "null",
    "[]",     "[1, 2]",      "[1, 2, 3, 4]", "[[1, 2, 3]]", "{}",
    "{a: 1}", "{x: [1, 2]}", "true",         "false",       "yes",
    "0",      "-0",          "-1",           "1",           "1e12",
    "-1e12",  "1e308",       "-1e308",       "1e-308",      "5e-324",
    "1e400",  "-1e400",      "1e-400",       ".nan",        ".inf",
    "-.inf",  "nan",         "inf",          "2147483648",  "-2147483649",
    "0x10",   "1_000",       "\"1.5\"",      "!!str 3",     "1.5.2",
    "1e",     "\"\\t\"",     "\"\\x00\"",    "\"\\u00e9\"", "\"" + std::string(5000, 'x') + "\""};

struct Site {
  std::string path;
  enum Kind { kScalar, kMap, kList } kind = kScalar;
  bool map_key = false;  // a key of a map (not an entry of a list)
};

inline void collectSites(const YAML::Node& n, const std::string& path, bool map_key,
                         std::vector<Site>& out) {
  Site s;
  s.path = path;
  s.map_key = map_key;
  if (n.IsMap()) {
    s.kind = Site::kMap;
    for (const auto& kv : n) {
      const std::string key = kv.first.Scalar();
      if (path.empty() && key == "base") continue;  // a file reference, not a setting
      collectSites(kv.second, join(path, key), true, out);
    }
  } else if (n.IsSequence()) {
    s.kind = Site::kList;
    for (std::size_t i = 0; i < n.size(); ++i) {
      collectSites(n[i], path + "[" + std::to_string(i) + "]", false, out);
    }
  }
  out.push_back(s);
}

// A scalar as YAML flow text: plain if it can be, else double-quoted.
inline std::string scalarText(const YAML::Node& n) {
  if (n.IsNull()) return "~";
  const std::string& v = n.Scalar();
  bool plain = !v.empty();
  for (const char c : v) {
    plain = plain && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' ||
                      c == '-' || c == '+' || c == '/');
  }
  if (plain) return v;
  std::string q = "\"";
  for (const char c : v) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}

// The tree as flow-style YAML with mutation m applied.
inline std::string emit(const YAML::Node& n, const std::string& path, const Mutation& m) {
  std::string out;
  if (n.IsMap()) {
    out += "{";
    bool first = true;
    auto item = [&](const std::string& key, const std::string& value) {
      out += (first ? "" : ", ") + key + ": " + value;
      first = false;
    };
    for (const auto& kv : n) {
      const std::string key = kv.first.Scalar();
      const std::string child = join(path, key);
      if (m.op == Mutation::kDelete && child == m.path) continue;
      const std::string value =
          (m.op == Mutation::kReplace && child == m.path) ? m.value : emit(kv.second, child, m);
      item(key, value);
      if (m.op == Mutation::kDuplicate && child == m.path) item(key, value);
    }
    if (m.op == Mutation::kInsertUnknown && join(path, "bogus_key") == m.path) {
      item("bogus_key", m.value);
    }
    return out + "}";
  }
  if (n.IsSequence()) {
    out += "[";
    bool first = true;
    for (std::size_t i = 0; i < n.size(); ++i) {
      const std::string child = path + "[" + std::to_string(i) + "]";
      if (m.op == Mutation::kDelete && child == m.path) continue;
      out += (first ? "" : ", ") +
             ((m.op == Mutation::kReplace && child == m.path) ? m.value : emit(n[i], child, m));
      first = false;
    }
    if (m.op == Mutation::kAppend && path == m.path) out += (first ? "" : ", ") + m.value;
    return out + "]";
  }
  return scalarText(n);
}

// The node at a key path such as "core.cylinders[1].center" (keys hold no
// '.' or '[').
inline YAML::Node nodeAt(const YAML::Node& root, const std::string& path) {
  std::vector<YAML::Node> chain{root};
  std::size_t i = 0;
  while (i < path.size()) {
    const YAML::Node& here = chain.back();
    if (path[i] == '.') {
      ++i;
    } else if (path[i] == '[') {
      const std::size_t close = path.find(']', i);
      const YAML::Node next = here[std::stoul(path.substr(i + 1, close - i - 1))];
      chain.push_back(next);
      i = close + 1;
    } else {
      const std::size_t end = std::min(path.find_first_of(".[", i), path.size());
      const YAML::Node next = here[path.substr(i, end - i)];
      chain.push_back(next);
      i = end;
    }
  }
  return chain.back();
}

inline Mutation drawMutation(Rng& rng, const YAML::Node& tree, const std::vector<Site>& sites) {
  Mutation m;
  for (;;) {
    const Site& site = rng.pick(sites);
    switch (rng.below(6)) {
      case 0:
      case 1:
        if (site.path.empty()) continue;  // not the whole scene
        m.op = Mutation::kReplace;
        m.path = site.path;
        m.value = rng.pick(kJunk);
        return m;
      case 2:
        if (site.path.empty()) continue;
        m.op = Mutation::kDelete;
        m.path = site.path;
        return m;
      case 3:
        if (!site.map_key) continue;
        m.op = Mutation::kDuplicate;
        m.path = site.path;
        return m;
      case 4:
        if (site.kind != Site::kMap) continue;
        m.op = Mutation::kInsertUnknown;
        m.path = join(site.path, "bogus_key");
        m.value = rng.below(2) ? "1" : rng.pick(kJunk);
        return m;
      default: {
        if (site.kind != Site::kList) continue;
        m.op = Mutation::kAppend;
        m.path = site.path;
        // A copy of the first entry (a keyframe twice, a fourth vector
        // component, a cylinder more) or junk.
        const YAML::Node list = nodeAt(tree, site.path);
        m.value = (list.size() > 0 && rng.below(2)) ? emit(list[0], site.path + "[0]", Mutation{})
                                                    : rng.pick(kJunk);
        return m;
      }
    }
  }
}

// ---------------------------------------------------------------------------
// Outcomes and the checks on them.
struct Outcome {
  bool accepted = false;
  cws::Scene scene;
  std::string key, what;  // of the SceneError
  std::string foreign;    // any other exception: its type and message
};

// The exception's type, readable (YAML::InvalidNode, std::bad_alloc).
inline std::string typeName(const std::exception& e) {
  int status = 0;
  std::unique_ptr<char, void (*)(void*)> name(
      abi::__cxa_demangle(typeid(e).name(), nullptr, nullptr, &status), std::free);
  return status == 0 && name ? std::string(name.get()) : std::string(typeid(e).name());
}

template <class Fn>
inline Outcome attempt(Fn load) {
  Outcome o;
  try {
    o.scene = load();
    o.accepted = true;
  } catch (const cws::SceneError& e) {
    o.key = e.key();
    o.what = e.what();
  } catch (const std::exception& e) {
    o.foreign = "foreign exception " + typeName(e) + ": " + shown(e.what());
  } catch (...) {
    o.foreign = "an exception not derived from std::exception";
  }
  return o;
}

// A key path without its last component: "a.b[2].c" -> "a.b[2]" -> "a.b".
inline std::string parentOf(const std::string& path) {
  const std::size_t cut = path.find_last_of(".[");
  return cut == std::string::npos ? std::string() : path.substr(0, cut);
}

// The path up to its first list index: "core.cylinders[2].radius" ->
// "core.cylinders".
inline std::string listPathOf(const std::string& path) { return path.substr(0, path.find('[')); }

// Does the refusal of a mutation at `path` name it? The message must hold
// the path; a rule that involves a whole list (a port inside the hull of
// core.cylinders) may name the list instead of one entry's key; a deleted
// key may be named by its parent (a deleted vector component by the
// vector, a deleted required entry by its entry).
inline bool namesKey(const std::string& what, const std::string& path, bool deleted) {
  std::vector<std::string> names{path, listPathOf(path)};
  if (deleted) {
    names.push_back(parentOf(path));
    names.push_back(listPathOf(parentOf(path)));
  }
  for (const std::string& n : names) {
    if (!n.empty() && what.find(n) != std::string::npos) return true;
  }
  return false;
}

// Control characters in a message would garble a terminal or a log.
inline bool printableMessage(const std::string& what) {
  for (const char c : what) {
    if (static_cast<unsigned char>(c) < 0x20) return false;
  }
  return true;
}

// Builds a Simulation of an accepted scene and, when it is small, takes a
// few steps. An IntegrationError while stepping is the run failing (wire_sim
// exit 1), allowed; anything thrown by the construction, and any other
// exception, is a defect. Returns what went wrong, or "".
inline std::string exercise(const cws::Scene& s, int* built) {
  try {
    cws::Simulation sim(s);
    ++*built;
    if (s.pointCapacity() <= 2000) {
      for (int k = 0; k < 3 && sim.time() < sim.endTime(); ++k) {
        try {
          sim.step(sim.endTime());
        } catch (const cws::IntegrationError&) {
          break;
        }
      }
    }
  } catch (const cws::SceneError& e) {
    return std::string("Simulation refused a scene validateScene accepted: ") + e.what();
  } catch (const std::exception& e) {
    return "Simulation threw " + typeName(e) + ": " + shown(e.what());
  } catch (...) {
    return "Simulation threw an exception not derived from std::exception";
  }
  return "";
}

// Failures of one test, each with what repeats it.
class Failures {
 public:
  explicit Failures(std::uint64_t seed) : seed_(seed) {}
  void add(std::size_t i, const std::string& where, const std::string& what) {
    ++count_;
    if (lines_.size() < 25) {
      lines_.push_back("seed " + std::to_string(seed_) + " mutation " + std::to_string(i) + " (" +
                       where + "): " + what);
    }
  }
  void report() const {
    if (count_ == 0) return;
    std::string all;
    for (const std::string& l : lines_) all += l + "\n";
    ADD_FAILURE() << count_ << " failures (first " << lines_.size() << "):\n" << all;
  }

 private:
  std::uint64_t seed_;
  std::size_t count_ = 0;
  std::vector<std::string> lines_;
};

class SceneFuzz : public cws_test::TempDirTest {
 protected:
  void SetUp() override {
    cws_test::TempDirTest::SetUp();
    seeds_ = seedScenes();
    for (const SeedScene& s : seeds_) {
      // Every seed is a valid scene: the mutations start from real input.
      ASSERT_NO_THROW(loadSeed(s)) << s.name;
      std::vector<Site> sites;
      collectSites(s.tree, "", false, sites);
      sites_.push_back(sites);
    }
  }

  cws::Scene loadSeed(const SeedScene& s) { return cws::loadScene(write("seed.yaml", s.text), {}); }

  std::vector<SeedScene> seeds_;
  std::vector<std::vector<Site>> sites_;
};

}  // namespace scene_fuzz
