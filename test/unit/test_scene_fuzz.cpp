// Fuzz tests of scene loading and validation: seeded random mutations of the
// package's real scene files, structured (at a known key path) and byte-level,
// through every entry point: loadScene (files and key.path=value overrides),
// sceneFromYamlText, validateScene on structs, and a Simulation built (and
// stepped a little) from every accepted scene.
//
// What must hold: nothing crashes or hangs; every refusal is a cws::SceneError
// (no yaml-cpp exception, std::bad_alloc, std::length_error ... leaks out);
// a refusal of a structured mutation at key K names K (see namesKey); a
// refusal of broken YAML names the file, line and column.
//
// Reproducible: mutation i of a test draws only from Rng(seed, i), a fully
// specified generator, so "seed S mutation i" in a failure repeats it.
// CWS_FUZZ_SEED and CWS_FUZZ_COUNT (environment variables) run other seeds
// and more mutations, for exploring beyond the fixed ones.
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

#include "coil_winding_sim/core/scene.hpp"
#include "coil_winding_sim/core/simulation.hpp"
#include "coil_winding_sim/core/time_steppers/ode_system.hpp"
#include "temp_dir_test.hpp"

namespace {

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

std::uint64_t envOr(const char* name, std::uint64_t fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::strtoull(v, nullptr, 0) : fallback;
}

std::string readAll(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

std::string join(const std::string& prefix, const std::string& key) {
  return prefix.empty() ? key : prefix + "." + key;
}

// Text for a failure message: control characters and non-ASCII bytes
// escaped, long text cut short.
std::string shown(const std::string& text, std::size_t max = 200) {
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

std::vector<SeedScene> seedScenes() {
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
const std::vector<std::string> kJunk = {
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

void collectSites(const YAML::Node& n, const std::string& path, bool map_key,
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
std::string scalarText(const YAML::Node& n) {
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
std::string emit(const YAML::Node& n, const std::string& path, const Mutation& m) {
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
YAML::Node nodeAt(const YAML::Node& root, const std::string& path) {
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

Mutation drawMutation(Rng& rng, const YAML::Node& tree, const std::vector<Site>& sites) {
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
std::string typeName(const std::exception& e) {
  int status = 0;
  std::unique_ptr<char, void (*)(void*)> name(
      abi::__cxa_demangle(typeid(e).name(), nullptr, nullptr, &status), std::free);
  return status == 0 && name ? std::string(name.get()) : std::string(typeid(e).name());
}

template <class Fn>
Outcome attempt(Fn load) {
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
std::string parentOf(const std::string& path) {
  const std::size_t cut = path.find_last_of(".[");
  return cut == std::string::npos ? std::string() : path.substr(0, cut);
}

// The path up to its first list index: "core.cylinders[2].radius" ->
// "core.cylinders".
std::string listPathOf(const std::string& path) { return path.substr(0, path.find('[')); }

// Does the refusal of a mutation at `path` name it? The message must hold
// the path; a rule that involves a whole list (a port inside the hull of
// core.cylinders) may name the list instead of one entry's key; a deleted
// key may be named by its parent (a deleted vector component by the
// vector, a deleted required entry by its entry).
bool namesKey(const std::string& what, const std::string& path, bool deleted) {
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
bool printableMessage(const std::string& what) {
  for (const char c : what) {
    if (static_cast<unsigned char>(c) < 0x20) return false;
  }
  return true;
}

// Builds a Simulation of an accepted scene and, when it is small, takes a
// few steps. An IntegrationError while stepping is the run failing (wire_sim
// exit 1), allowed; anything thrown by the construction, and any other
// exception, is a defect. Returns what went wrong, or "".
std::string exercise(const cws::Scene& s, int* built) {
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

// ---------------------------------------------------------------------------
// Structured mutations, through a file (loadScene) and as text
// (sceneFromYamlText); both must agree.
TEST_F(SceneFuzz, StructuredMutationsNameTheKey) {
  const std::uint64_t seed = envOr("CWS_FUZZ_SEED", 20240601);
  const std::size_t count = envOr("CWS_FUZZ_COUNT", 1000);
  Failures failures(seed);
  int accepted = 0, built = 0;
  for (std::size_t i = 0; i < count; ++i) {
    Rng rng(seed, i);
    const std::size_t k = rng.below(seeds_.size());
    const SeedScene& base = seeds_[k];
    const Mutation m = drawMutation(rng, base.tree, sites_[k]);
    const std::string where = base.name + ", " + m.describe();
    const std::string text = emit(base.tree, "", m);
    const std::string path = write("mutated.yaml", text);

    const Outcome file = attempt([&] { return cws::loadScene(path, {}); });
    std::vector<const Outcome*> outcomes{&file};
    Outcome from_text;
    if (!base.has_base) {
      from_text = attempt([&] { return cws::sceneFromYamlText(text); });
      outcomes.push_back(&from_text);
      if (from_text.accepted != file.accepted) {
        failures.add(
            i, where,
            "loadScene and sceneFromYamlText disagree: " + file.what + " | " + from_text.what);
      } else if (file.accepted &&
                 cws::sceneToYamlText(file.scene) != cws::sceneToYamlText(from_text.scene)) {
        failures.add(i, where, "loadScene and sceneFromYamlText give different scenes");
      }
    }
    for (const Outcome* o : outcomes) {
      if (!o->foreign.empty()) {
        failures.add(i, where, o->foreign);
      } else if (!o->accepted && !namesKey(o->what, m.path, m.op == Mutation::kDelete)) {
        failures.add(i, where, "the refusal does not name the key: " + shown(o->what));
      } else if (!o->accepted && !printableMessage(o->what)) {
        failures.add(i, where, "control characters in the message: " + shown(o->what));
      }
    }
    if (file.accepted) {
      ++accepted;
      const std::string problem = exercise(file.scene, &built);
      if (!problem.empty()) failures.add(i, where, problem);
    }
  }
  failures.report();
  std::cout << "[ SceneFuzz ] seed " << seed << ": " << count << " structured mutations, "
            << accepted << " accepted, " << built << " simulations built\n";
  // The mutations must reach both outcomes, or they test too little.
  EXPECT_GT(accepted, 0);
  EXPECT_LT(accepted, static_cast<int>(count));
}

// ---------------------------------------------------------------------------
// Byte-level mutations of the scene files' text.
std::string mutateBytes(Rng& rng, std::string text) {
  static const std::vector<std::string> kSyntax = {
      "[", "]", "{", "}", "\"", "'", ":",  ": ", "- ",    "&a ",   "*a", "!",   "!!",
      "%", "|", ">", "#", "@",  "`", "? ", ",",  "---\n", "...\n", "\\", "<<: "};
  static const std::vector<std::string> kBadBytes = {
      std::string("\xff"),         std::string("\xc3"),         std::string("\x80"),
      std::string("\xed\xa0\x80"), std::string("\xef\xbb\xbf"), std::string("\xfe\xff"),
      std::string(1, '\0'),        std::string("\x1b[31m"),     std::string("\r"),
      std::string("\x7f")};
  const std::size_t edits = 1 + rng.below(3);
  for (std::size_t e = 0; e < edits; ++e) {
    const std::size_t at = rng.below(text.size() + 1);
    // Line starts, for the line-wise edits.
    std::vector<std::size_t> starts{0};
    for (std::size_t p = 0; p < text.size(); ++p) {
      if (text[p] == '\n') starts.push_back(p + 1);
    }
    const std::size_t line = rng.pick(starts);
    const std::size_t line_end = std::min(text.find('\n', line), text.size());
    switch (rng.below(12)) {
      case 0:  // a printable character
        text.insert(at, 1, static_cast<char>(0x20 + rng.below(0x5f)));
        break;
      case 1:  // any byte
        text.insert(at, 1, static_cast<char>(rng.below(256)));
        break;
      case 2:  // delete a few bytes
        text.erase(at, 1 + rng.below(8));
        break;
      case 3:  // flip one bit
        if (!text.empty()) text[at % text.size()] ^= static_cast<char>(1u << rng.below(8));
        break;
      case 4:  // truncate
        text.resize(at);
        break;
      case 5:  // a tab in the indentation
        text.insert(line, "\t");
        break;
      case 6:  // syntax characters, unbalanced brackets
        text.insert(at, rng.pick(kSyntax));
        break;
      case 7:  // bytes that are not UTF-8, NUL, escape sequences
        text.insert(at, rng.pick(kBadBytes));
        break;
      case 8:  // a line twice
        text.insert(line, text.substr(line, line_end - line) + "\n");
        break;
      case 9:  // a line deleted
        text.erase(line, line_end - line + 1);
        break;
      case 10:  // indentation one more or one less
        if (rng.below(2)) {
          text.insert(line, " ");
        } else if (line < text.size() && text[line] == ' ') {
          text.erase(line, 1);
        }
        break;
      default:  // a line moved to another place
      {
        const std::string moved = text.substr(line, line_end - line + 1);
        text.erase(line, moved.size());
        text.insert(std::min(at, text.size()), moved);
        break;
      }
    }
  }
  return text;
}

TEST_F(SceneFuzz, ByteMutationsAreRefusedWithFileLineOrKey) {
  const std::uint64_t seed = envOr("CWS_FUZZ_SEED", 20240602);
  const std::size_t count = envOr("CWS_FUZZ_COUNT", 1000);
  Failures failures(seed);
  int accepted = 0, built = 0, not_yaml = 0;
  for (std::size_t i = 0; i < count; ++i) {
    Rng rng(seed, i);
    const SeedScene& base = rng.pick(seeds_);
    const std::string text = mutateBytes(rng, base.text);
    const std::string where = base.name + ", bytes now '" + shown(text, 10000) + "'";
    const std::string path = write("mutated.yaml", text);

    const Outcome file = attempt([&] { return cws::loadScene(path, {}); });
    std::vector<const Outcome*> outcomes{&file};
    Outcome from_text;
    if (!base.has_base) {
      from_text = attempt([&] { return cws::sceneFromYamlText(text); });
      outcomes.push_back(&from_text);
      // The same text must get the same answer, but for an empty file
      // (refused; empty text is the defaults).
      const bool empty_file =
          file.key == "(file)" && file.what.find("no settings") != std::string::npos;
      if (!empty_file && from_text.accepted != file.accepted) {
        failures.add(
            i, where,
            "loadScene and sceneFromYamlText disagree: " + file.what + " | " + from_text.what);
      } else if (!file.accepted && !from_text.accepted && !empty_file) {
        const bool same =
            file.key == from_text.key || (file.key == "(file)" && from_text.key == "(text)");
        if (!same) failures.add(i, where, "different keys: " + file.key + " | " + from_text.key);
      }
    }
    for (const Outcome* o : outcomes) {
      if (!o->foreign.empty()) {
        failures.add(i, where, o->foreign);
        continue;
      }
      if (o->accepted) continue;
      if (!printableMessage(o->what)) {
        failures.add(i, where, "control characters in the message: " + shown(o->what));
      }
      if (o->key.empty()) failures.add(i, where, "a refusal without a key: " + o->what);
      // Broken YAML: the file (for loadScene), line and column are named.
      if (o->what.find("not valid YAML") != std::string::npos) {
        if (o == &file) ++not_yaml;
        const bool located = o->what.find("line ") != std::string::npos &&
                             o->what.find("column ") != std::string::npos;
        if (!located) failures.add(i, where, "no line and column: " + shown(o->what));
      }
      if (o->key == "(file)" && o->what.find(path) == std::string::npos) {
        failures.add(i, where, "the file is not named: " + shown(o->what));
      }
    }
    if (file.accepted) {
      ++accepted;
      const std::string problem = exercise(file.scene, &built);
      if (!problem.empty()) failures.add(i, where, problem);
    }
  }
  failures.report();
  std::cout << "[ SceneFuzz ] seed " << seed << ": " << count << " byte mutations, " << accepted
            << " accepted, " << not_yaml << " not YAML, " << built << " simulations built\n";
  EXPECT_GT(accepted, 0);
  EXPECT_GT(not_yaml, 0);
}

// ---------------------------------------------------------------------------
// key.path=value overrides (wire_sim --set) over the real files: junk values
// and malformed paths.
TEST_F(SceneFuzz, OverrideMutationsNameTheKey) {
  const std::uint64_t seed = envOr("CWS_FUZZ_SEED", 20240603);
  const std::size_t count = envOr("CWS_FUZZ_COUNT", 1000);
  const fs::path root = CWS_SOURCE_DIR;
  const std::vector<std::string> files = {(root / "config/scenes/default.yaml").string(),
                                          (root / "config/scenes/cantilever_plastic.yaml").string(),
                                          (root / "config/scenes/paper_case_3d.yaml").string(),
                                          (root / "test/scenes/spinning_wire.yaml").string(), ""};
  // Keys an override can reach: map keys, no list entries.
  std::vector<std::string> keys;
  for (const std::vector<Site>& sites : sites_) {
    for (const Site& s : sites) {
      if (s.map_key && s.path.find('[') == std::string::npos) keys.push_back(s.path);
    }
  }
  Failures failures(seed);
  int accepted = 0, built = 0;
  for (std::size_t i = 0; i < count; ++i) {
    Rng rng(seed, i);
    const std::string& file = rng.pick(files);
    const std::string& key = rng.pick(keys);
    const std::string& junk = rng.pick(kJunk);
    // The override, and the text its refusal must name.
    std::string text, named;
    switch (rng.below(8)) {
      case 0:  // no '='
        text = key;
        named = key;
        break;
      case 1:  // a path below the key (into a value, or unknown)
        text = key + ".sub=" + junk;
        named = key;
        break;
      case 2:  // an empty component
        text = key + ".=" + junk;
        named = key;
        break;
      case 3:  // an empty key
        text = "=" + junk;
        named = text;
        break;
      default:
        text = key + "=" + junk;
        named = key;
        break;
    }
    const std::string where = "file '" + file + "', --set '" + shown(text) + "'";
    const Outcome o = attempt([&] { return cws::loadScene(file, {text}); });
    if (!o.foreign.empty()) {
      failures.add(i, where, o.foreign);
    } else if (!o.accepted && o.what.find(named) == std::string::npos &&
               !namesKey(o.what, key, false)) {
      failures.add(i, where, "the refusal does not name the key: " + shown(o.what));
    } else if (!o.accepted && !printableMessage(o.what)) {
      failures.add(i, where, "control characters in the message: " + shown(o.what));
    }
    if (o.accepted) {
      ++accepted;
      const std::string problem = exercise(o.scene, &built);
      if (!problem.empty()) failures.add(i, where, problem);
    }
  }
  failures.report();
  std::cout << "[ SceneFuzz ] seed " << seed << ": " << count << " overrides, " << accepted
            << " accepted, " << built << " simulations built\n";
  EXPECT_GT(accepted, 0);
}

// ---------------------------------------------------------------------------
// validateScene on structs built in code (the ROS node and tests do that):
// values YAML cannot carry (NaN, infinities) and absurd ones.
struct Field {
  std::string key;
  std::function<double&(cws::Scene&)> ref;
};

std::vector<Field> numberFields(const cws::Scene& like) {
  std::vector<Field> f;
  auto add = [&](const std::string& key, std::function<double&(cws::Scene&)> ref) {
    f.push_back({key, std::move(ref)});
  };
  auto vec = [&](const std::string& key, int size, std::function<double&(cws::Scene&, int)> ref) {
    for (int i = 0; i < size; ++i) {
      add(key + "[" + std::to_string(i) + "]",
          [ref, i](cws::Scene& s) -> double& { return ref(s, i); });
    }
  };
  auto law = [&](const std::string& key, const char* yield,
                 cws::HysteresisParams cws::WireParams::*member) {
    add(key + ".elastic_rigidity",
        [member](cws::Scene& s) -> double& { return (s.wire.*member).elastic_rigidity; });
    add(key + ".plastic_rigidity",
        [member](cws::Scene& s) -> double& { return (s.wire.*member).plastic_rigidity; });
    add(key + "." + yield, [member](cws::Scene& s) -> double& { return (s.wire.*member).yield; });
  };
  add("wire.diameter", [](cws::Scene& s) -> double& { return s.wire.diameter; });
  add("wire.line_density", [](cws::Scene& s) -> double& { return s.wire.line_density; });
  add("wire.length", [](cws::Scene& s) -> double& { return s.wire.length; });
  add("wire.segment_length", [](cws::Scene& s) -> double& { return s.wire.segment_length; });
  law("wire.stretch", "yield_strain", &cws::WireParams::stretch);
  law("wire.bend", "yield_curvature", &cws::WireParams::bend);
  law("wire.torsion", "yield_twist", &cws::WireParams::torsion);
  add("contact.static_friction",
      [](cws::Scene& s) -> double& { return s.contact.static_friction; });
  add("contact.kinetic_friction",
      [](cws::Scene& s) -> double& { return s.contact.kinetic_friction; });
  add("contact.stiffness", [](cws::Scene& s) -> double& { return s.contact.stiffness; });
  add("contact.stick_stiffness",
      [](cws::Scene& s) -> double& { return s.contact.stick_stiffness; });
  add("contact.stick_speed", [](cws::Scene& s) -> double& { return s.contact.stick_speed; });
  vec("core.position", 3, [](cws::Scene& s, int i) -> double& { return s.core.position_world[i]; });
  vec("core.axis", 3, [](cws::Scene& s, int i) -> double& { return s.core.axis_world[i]; });
  add("core.max_angular_acceleration",
      [](cws::Scene& s) -> double& { return s.core.max_angular_acceleration; });
  for (std::size_t c = 0; c < like.core.cylinders.size(); ++c) {
    const std::string key = "core.cylinders[" + std::to_string(c) + "]";
    vec(key + ".center", 2,
        [c](cws::Scene& s, int i) -> double& { return s.core.cylinders[c].center_core[i]; });
    add(key + ".radius", [c](cws::Scene& s) -> double& { return s.core.cylinders[c].radius; });
  }
  vec("supply.port_position", 3,
      [](cws::Scene& s, int i) -> double& { return s.supply.port_position_world[i]; });
  add("process.core_speed_rpm", [](cws::Scene& s) -> double& { return s.process.core_speed_rpm; });
  add("process.tension", [](cws::Scene& s) -> double& { return s.process.tension; });
  add("process.traverse_pitch", [](cws::Scene& s) -> double& { return s.process.traverse_pitch; });
  add("process.max_core_speed_rpm",
      [](cws::Scene& s) -> double& { return s.process.max_core_speed_rpm; });
  add("process.max_tension", [](cws::Scene& s) -> double& { return s.process.max_tension; });
  add("process.turns", [](cws::Scene& s) -> double& { return s.process.turns; });
  if (like.process.duration) {
    add("process.duration", [](cws::Scene& s) -> double& { return *s.process.duration; });
  }
  add("solver.rtol", [](cws::Scene& s) -> double& { return s.solver.rtol; });
  add("solver.atol", [](cws::Scene& s) -> double& { return s.solver.atol; });
  add("solver.min_step", [](cws::Scene& s) -> double& { return s.solver.min_step; });
  add("solver.max_step", [](cws::Scene& s) -> double& { return s.solver.max_step; });
  add("solver.initial_step", [](cws::Scene& s) -> double& { return s.solver.initial_step; });
  if (like.solver.fixed_step) {
    add("solver.fixed_step", [](cws::Scene& s) -> double& { return *s.solver.fixed_step; });
  }
  add("solver.baumgarte_nu", [](cws::Scene& s) -> double& { return s.solver.baumgarte_nu; });
  vec("gravity.acceleration", 3,
      [](cws::Scene& s, int i) -> double& { return s.gravity.acceleration_world[i]; });
  add("damping.translational", [](cws::Scene& s) -> double& { return s.damping.translational; });
  add("damping.rotational", [](cws::Scene& s) -> double& { return s.damping.rotational; });
  vec("start.position", 3, [](cws::Scene& s, int i) -> double& { return s.start.position[i]; });
  vec("start.direction", 3, [](cws::Scene& s, int i) -> double& { return s.start.direction[i]; });
  for (std::size_t k = 0; k < like.end.load.size(); ++k) {
    const std::string key = "end.load[" + std::to_string(k) + "]";
    add(key + ".time", [k](cws::Scene& s) -> double& { return s.end.load[k].time; });
    vec(key + ".force", 3,
        [k](cws::Scene& s, int i) -> double& { return s.end.load[k].force_world[i]; });
    vec(key + ".moment", 3,
        [k](cws::Scene& s, int i) -> double& { return s.end.load[k].moment_world[i]; });
  }
  add("output.progress_interval_s",
      [](cws::Scene& s) -> double& { return s.output.progress_interval_s; });
  return f;
}

TEST_F(SceneFuzz, StructMutationsThroughValidateScene) {
  const std::uint64_t seed = envOr("CWS_FUZZ_SEED", 20240604);
  const std::size_t count = envOr("CWS_FUZZ_COUNT", 1500);
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> values = {nan,  inf,  -inf, 1e308, -1e308, 1e-308, 5e-324, 0.0,
                                      -0.0, -1.0, 1.0,  1e12,  -1e12,  2.2e9,  1e-12,  1e6};
  const std::vector<std::string> words = {"",
                                          "rkf45",
                                          "core",
                                          "world",
                                          "clamped",
                                          "free",
                                          "RKF45",
                                          "x\ty",
                                          std::string(1000, 'w'),
                                          std::string("\x01\x02")};
  std::vector<cws::Scene> bases;
  for (const SeedScene& s : seeds_) bases.push_back(loadSeed(s));
  Failures failures(seed);
  int accepted = 0, built = 0;
  for (std::size_t i = 0; i < count; ++i) {
    Rng rng(seed, i);
    cws::Scene s = rng.pick(bases);
    std::string key, where;
    bool must_name_exactly = false;
    switch (rng.below(8)) {
      case 0: {  // a word
        const std::string w = rng.pick(words);
        const std::size_t which = rng.below(4);
        std::string* target = which == 0   ? &s.solver.integrator
                              : which == 1 ? &s.start.type
                              : which == 2 ? &s.start.frame
                                           : &s.end.type;
        key = which == 0   ? "solver.integrator"
              : which == 1 ? "start.type"
              : which == 2 ? "start.frame"
                           : "end.type";
        *target = w;
        where = key + " = '" + shown(w) + "'";
        break;
      }
      case 1: {  // list lengths
        const std::size_t which = rng.below(4);
        if (which == 0) {
          s.end.load.clear();
          key = "end.load";
        } else if (which == 1) {
          s.core.cylinders.clear();
          key = "core.cylinders";
        } else if (which == 2) {
          s.end.load.push_back(s.end.load.empty() ? cws::LoadKeyframe{} : s.end.load.back());
          key = "end.load";
        } else {
          s.core.faces.push_back(cws::FaceParams{});  // from == to
          key = "core.faces";
        }
        where = "list " + key + " changed";
        break;
      }
      case 2:  // supply.max_points
        s.supply.max_points =
            rng.pick(std::vector<int>{-1, 0, 1, 100000, 100001, 2147483647, -2147483647});
        key = "supply.max_points";
        where = key + " = " + std::to_string(s.supply.max_points);
        break;
      default: {  // a number
        const std::vector<Field> fields = numberFields(s);
        const Field& f = rng.pick(fields);
        const double v = rng.pick(values);
        f.ref(s) = v;
        key = f.key;
        must_name_exactly = !std::isfinite(v);
        std::ostringstream w;
        w << key << " = " << v;
        where = w.str();
        break;
      }
    }
    const Outcome o = attempt([&] {
      cws::validateScene(s);
      return s;
    });
    if (!o.foreign.empty()) {
      failures.add(i, where, o.foreign);
    } else if (!o.accepted && must_name_exactly && o.key != key) {
      failures.add(i, where, "a non-finite value is not refused by its key: " + shown(o.what));
    } else if (!o.accepted && !namesKey(o.what, key, false)) {
      failures.add(i, where, "the refusal does not name the key: " + shown(o.what));
    } else if (!o.accepted && !printableMessage(o.what)) {
      failures.add(i, where, "control characters in the message: " + shown(o.what));
    }
    if (o.accepted) {
      ++accepted;
      const std::string problem = exercise(s, &built);
      if (!problem.empty()) failures.add(i, where, problem);
    }
  }
  failures.report();
  std::cout << "[ SceneFuzz ] seed " << seed << ": " << count << " struct mutations, " << accepted
            << " accepted, " << built << " simulations built\n";
  EXPECT_GT(accepted, 0);
}

// ---------------------------------------------------------------------------
// Inputs built to exhaust a parser: deep nesting, huge files and scalars,
// aliases that refer to themselves or fan out.
TEST_F(SceneFuzz, AbsurdInputsAreRefusedByName) {
  struct Case {
    std::string name, text, key, why;
  };
  std::string fan = "end:\n  load: [&l0 [0, 0, 0, 0, 0, 0, 0, 0, 0, 0]";
  for (int k = 1; k < 9; ++k) {
    fan += ", &l" + std::to_string(k) + " [";
    for (int j = 0; j < 10; ++j) fan += (j ? ", *l" : "*l") + std::to_string(k - 1);
    fan += "]";
  }
  fan += "]\n";
  // A scene file over the package's winding scene (supply and contact).
  const std::string winding =
      "base: " + (fs::path(CWS_SOURCE_DIR) / "config/scenes/default.yaml").string() + "\n";
  std::string indented = "wire:\n";
  for (int d = 0; d < 3000; ++d) indented += std::string(2 * d + 2, ' ') + "k:\n";
  const std::vector<Case> cases = {
      {"100000 nested lists", "wire: " + std::string(100000, '['), "(file)", "line"},
      {"3000 nested maps", indented, "(file)", "line"},
      {"a 1 MB scalar", "wire: {diameter: " + std::string(1 << 20, '9') + "x}\n", "wire.diameter",
       "number"},
      {"a list that holds itself", "core: {cylinders: &a [*a]}\n", "core.cylinders[0]", "map"},
      {"a map that holds itself", "wire: &w {stretch: *w}\n", "wire.stretch.stretch",
       "unknown key"},
      {"aliases fanning out to 1e9 entries", fan, "end.load[0]", "map"},
      {"two documents", "process: {tension: 40}\n---\nprocess: {tension: 50}\n", "(file)",
       "more than one YAML document"},
      // yaml-cpp 0.7 cannot read on after these; YAML::Load drops the rest
      // silently and YAML::LoadAll loops, allocating until memory runs out.
      {"a stray comma", ",\n\tc:\n", "(file)", "cannot be read on"},
      {"junk after a flow map", "{process: {tension: 40}}, junk\n", "(file)", "line 1, column 25"},
      {"a merge key", "wire: {<<: {diameter: 2.0e-3}}\n", "wire.<<", "unknown key"},
      {"a key given twice", "wire: {diameter: 1.0e-3, diameter: 2.0e-3}\n", "wire.diameter",
       "twice"},
      {"a list as a key", "? [wire]\n: 1\n", "(top level)", "name"},
      {"a null key", "wire: {~: 1}\n", "wire", "name"},
      {"a cylinder without center", "core: {cylinders: [{radius: 1.0e-3}]}\n",
       "core.cylinders[0].center", "missing"},
      {"a keyframe without time", "end: {load: [{force: [0, 0, 1]}]}\n", "end.load[0].time",
       "missing"},
      {"a face without to", "core: {faces: [{from: [0, 0]}]}\n", "core.faces[0].to", "missing"},
      {"a number beyond a double", "wire: {length: 1e400}\n", "wire.length", "range"},
      {"supply.max_points far beyond memory", "supply: {max_points: 1.0e12}\n", "supply.max_points",
       "above the limit of 100000"},
      {"supply.max_points not whole", "supply: {max_points: 10.5}\n", "supply.max_points",
       "whole number"},
      // Values that asked for absurd storage or overflowed a count (the
      // winding scene: a supply, so the points grow with the run).
      {"1e12 segments", "wire: {segment_length: 5.0e-14}\n", "wire.segment_length", "limit"},
      {"1e12 turns of winding", winding + "process: {turns: 1.0e12}\n", "process.turns", "limit"},
      {"a port 1e300 m away", winding + "supply: {port_position: [1.0e300, 0, 0]}\n",
       "supply.port_position", "limit"},
      {"a core speed of 1e-320 rpm", winding + "process: {core_speed_rpm: 1.0e-320}\n",
       "process.turns", "longer than any time"},
      {"an axis whose length overflows", "core: {axis: [1.0e300, 1.0e300, 0]}\n", "core.axis",
       "overflow"},
  };
  for (const Case& c : cases) {
    const std::string path = write("absurd.yaml", c.text);
    const Outcome o = attempt([&] { return cws::loadScene(path, {}); });
    EXPECT_TRUE(o.foreign.empty()) << c.name << ": " << o.foreign;
    EXPECT_FALSE(o.accepted) << c.name;
    EXPECT_EQ(o.key, c.key) << c.name << ": " << shown(o.what);
    EXPECT_NE(o.what.find(c.why), std::string::npos) << c.name << ": " << shown(o.what);
    EXPECT_LT(o.what.size(), 1000u) << c.name << ": the message should be short";
    if (c.key == "(file)") {
      EXPECT_NE(o.what.find(path), std::string::npos) << c.name;
    }
  }
  // Files that are not scene files at all.
  const std::string big = write("big.yaml", std::string(17 << 20, '#'));
  for (const std::string& path : {big, std::string("/dev/zero"), dir_.string()}) {
    const Outcome o = attempt([&] { return cws::loadScene(path, {}); });
    EXPECT_TRUE(o.foreign.empty()) << path << ": " << o.foreign;
    EXPECT_EQ(o.key, "(file)") << path << ": " << shown(o.what);
    EXPECT_NE(o.what.find(path), std::string::npos) << shown(o.what);
  }
}

}  // namespace
