// The core library's folders form layers: each includes only folders below
// it (docs/develop.md, "Layout"). This test reads every source and
// header of the core and fails on an include that runs back up or sideways,
// on a folder missing from the table below, and on a file outside every
// folder.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

// Bottom to top. Folders of one layer do not include each other.
const std::vector<std::vector<std::string>> kLayers = {
    {"base", "linear_algebra"},           // types and small maths
    {"scene"},                            // the plain scene and its checks
    {"machine"},                          // the core's and traverse's prescribed motion
    {"assembly"},                         // the Newton system's sinks
    {"constraints"},                      // the frame constraints
    {"inner_forces", "external_forces"},  // the effects
    {"model"},                            // the wire: layout, effects, carried and retired wire
    {"implicit"},                         // the Newton formulations
    {"time_steppers"},                    // the integrators
    {"run"},                              // the simulation, its input and its output
};

std::map<std::string, int> layerOf() {
  std::map<std::string, int> rank;
  for (std::size_t k = 0; k < kLayers.size(); ++k) {
    for (const std::string& folder : kLayers[k]) rank[folder] = static_cast<int>(k);
  }
  return rank;
}

// The core's files: (its folder, its path).
std::vector<std::pair<std::string, fs::path>> coreFiles() {
  std::vector<std::pair<std::string, fs::path>> files;
  const fs::path source = CWS_SOURCE_DIR;
  for (const fs::path& root :
       {source / "include" / "coil_winding_sim" / "core", source / "src" / "core"}) {
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(root)) {
      if (!e.is_regular_file()) continue;
      const std::string ext = e.path().extension().string();
      if (ext != ".hpp" && ext != ".cpp" && ext != ".h") continue;
      const fs::path rel = fs::relative(e.path(), root);
      const std::string folder = rel.has_parent_path() ? rel.begin()->string() : "";
      files.emplace_back(folder, e.path());
    }
  }
  return files;
}

// What is wrong with the includes of a file in `folder`, one line each
// (empty: nothing).
std::string wrongIncludes(const std::string& where, const std::string& folder, std::istream& in) {
  static const std::map<std::string, int> rank = layerOf();
  static const std::regex include_re(
      "^\\s*#\\s*include\\s*\"coil_winding_sim/core/([^/\"]+)(/[^\"]*)?\"");
  std::ostringstream wrong;
  if (folder.empty()) return where + ": outside every folder of the core\n";
  const auto own = rank.find(folder);
  if (own == rank.end()) {
    return where + ": folder '" + folder + "' is in no layer of this test's table\n";
  }
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    std::smatch m;
    if (!std::regex_search(line, m, include_re)) continue;
    const std::string target = m[2].matched ? m[1].str() : "";
    if (target == folder) continue;
    const auto other = rank.find(target);
    if (other == rank.end()) {
      wrong << where << ":" << number << ": includes " << m[0].str()
            << ", outside every folder of the table\n";
    } else if (other->second >= own->second) {
      wrong << where << ":" << number << ": " << folder << " (layer " << own->second
            << ") includes " << target << " (layer " << other->second << ")\n";
    }
  }
  return wrong.str();
}

TEST(IncludeLayers, EveryCoreFolderIncludesOnlyFoldersBelowIt) {
  const std::vector<std::pair<std::string, fs::path>> files = coreFiles();
  ASSERT_GT(files.size(), 50u) << "the core's sources were not found under " << CWS_SOURCE_DIR;
  std::string wrong;
  for (const auto& [folder, path] : files) {
    std::ifstream in(path);
    wrong += wrongIncludes(path.string(), folder, in);
  }
  EXPECT_EQ(wrong, "") << "includes that run back up the layers";
}

// The check finds an include upwards, sideways and out of the table, and
// passes one downwards and one within the folder.
TEST(IncludeLayers, TheCheckSeesWhatRunsBackUp) {
  auto check = [](const std::string& folder, const std::string& text) {
    std::istringstream in(text);
    return wrongIncludes("f.cpp", folder, in);
  };
  EXPECT_EQ(check("scene", "#include \"coil_winding_sim/core/model/wire_model.hpp\"\n"),
            "f.cpp:1: scene (layer 1) includes model (layer 6)\n");
  EXPECT_NE(
      check("inner_forces",
            "#include <cmath>\n#include \"coil_winding_sim/core/external_forces/contact.hpp\"\n"),
      "");
  EXPECT_NE(check("run", "#include \"coil_winding_sim/core/loose.hpp\"\n"), "");
  EXPECT_NE(check("nowhere", ""), "");
  EXPECT_EQ(check("model",
                  "#include \"coil_winding_sim/core/base/quaternion.hpp\"\n"
                  "  #  include \"coil_winding_sim/core/model/wire_model.hpp\"\n"),
            "");
}

}  // namespace
