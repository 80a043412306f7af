// Fuzz tests of scene loading and validation (see test_scene_fuzz.cpp):
// key.path=value overrides, struct fields through validateScene, and
// absurd inputs, each refused by name.
#include "scene_fuzz_support.hpp"

namespace {

using namespace scene_fuzz;

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
  add("contact.damping_ratio", [](cws::Scene& s) -> double& { return s.contact.damping_ratio; });
  add("process.winding_width", [](cws::Scene& s) -> double& { return s.process.winding_width; });
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
      // (A byte mutation of the 3-D scene found it: a lone quote on the
      // last line reads as an empty key.)
      {"an empty key", "process: {tension: 40}\n'", "(top level)", "empty one (line 2"},
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
