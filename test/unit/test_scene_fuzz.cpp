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
#include "scene_fuzz_support.hpp"

namespace {

using namespace scene_fuzz;

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

}  // namespace
