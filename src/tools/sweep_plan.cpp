#include "sweep_plan.hpp"

#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws_tools {

namespace {

std::string trim(const std::string& s) {
  const std::size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const std::size_t b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

// A number of a range; the message names the grid argument.
double rangeNumber(const std::string& text, const std::string& arg, const char* what) {
  try {
    std::size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size() && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  throw SweepError("--grid '" + arg + "': the range's " + what + " '" + text +
                   "' is not a finite number (a range is FROM:TO:COUNT)");
}

std::string formatValue(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.15g", v);
  return buf;
}

// Splits a CSV line; "..." quotes a field (with "" for a quote inside).
std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        out.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        out.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      out.emplace_back();
    } else {
      out.back() += c;
    }
  }
  for (std::string& f : out) f = trim(f);
  return out;
}

void checkKeys(const std::vector<std::string>& keys, const std::string& where) {
  std::set<std::string> seen;
  for (const std::string& k : keys) {
    if (k.empty()) throw SweepError(where + ": an empty key");
    if (!seen.insert(k).second) throw SweepError(where + ": key '" + k + "' comes twice");
  }
}

}  // namespace

GridAxis parseGridAxis(const std::string& arg) {
  const std::size_t eq = arg.find('=');
  if (eq == std::string::npos) {
    throw SweepError("--grid '" + arg + "': expected KEY=VALUES (FROM:TO:COUNT or V1,V2,...)");
  }
  GridAxis axis;
  axis.key = trim(arg.substr(0, eq));
  const std::string spec = trim(arg.substr(eq + 1));
  if (axis.key.empty()) throw SweepError("--grid '" + arg + "': no key before '='");
  if (spec.empty()) throw SweepError("--grid '" + arg + "': no values after '='");
  const std::size_t c1 = spec.find(':');
  if (c1 != std::string::npos && spec.find(',') == std::string::npos) {
    // FROM:TO:COUNT, both ends included.
    const std::size_t c2 = spec.find(':', c1 + 1);
    if (c2 == std::string::npos || spec.find(':', c2 + 1) != std::string::npos) {
      throw SweepError("--grid '" + arg + "': a range is FROM:TO:COUNT");
    }
    const double from = rangeNumber(trim(spec.substr(0, c1)), arg, "start");
    const double to = rangeNumber(trim(spec.substr(c1 + 1, c2 - c1 - 1)), arg, "end");
    const std::string count_text = trim(spec.substr(c2 + 1));
    int count = 0;
    try {
      std::size_t used = 0;
      count = std::stoi(count_text, &used);
      if (used != count_text.size()) count = 0;
    } catch (const std::exception&) {
      count = 0;
    }
    if (count < 1 || count > 100000) {
      throw SweepError("--grid '" + arg + "': the range's COUNT '" + count_text +
                       "' is not a whole number from 1 to 100000");
    }
    if (count == 1 && from != to) {
      throw SweepError("--grid '" + arg + "': one value from " + formatValue(from) + " to " +
                       formatValue(to) + " is ambiguous (give COUNT >= 2, or one value)");
    }
    for (int i = 0; i < count; ++i) {
      const double v = count == 1 ? from : from + (to - from) * i / (count - 1);
      axis.values.push_back(formatValue(i == count - 1 ? to : v));
    }
    return axis;
  }
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = spec.find(',', start);
    const std::string v =
        trim(spec.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (v.empty()) throw SweepError("--grid '" + arg + "': an empty value in the list");
    axis.values.push_back(v);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return axis;
}

std::vector<std::string> SweepPlan::caseOverrides(std::size_t i) const {
  std::vector<std::string> o = overrides;
  for (std::size_t k = 0; k < keys.size(); ++k) o.push_back(keys[k] + "=" + cases.at(i)[k]);
  return o;
}

std::string SweepPlan::caseLabel(std::size_t i) const {
  std::string s;
  for (std::size_t k = 0; k < keys.size(); ++k) {
    s += (k ? ", " : "") + keys[k] + "=" + cases.at(i)[k];
  }
  return s;
}

std::string SweepPlan::caseDir(std::size_t i) const {
  if (i < names.size()) return names[i];
  char buf[32];
  std::snprintf(buf, sizeof buf, "case_%04zu", i);
  return buf;
}

std::string SweepPlan::option(const std::string& key, const std::string& fallback) const {
  for (const auto& kv : options) {
    if (kv.first == key) return kv.second;
  }
  return fallback;
}

SweepPlan gridPlan(const std::string& scene, const std::vector<std::string>& overrides,
                   const std::vector<GridAxis>& axes) {
  SweepPlan p;
  p.scene = scene;
  p.overrides = overrides;
  for (const GridAxis& a : axes) p.keys.push_back(a.key);
  checkKeys(p.keys, "--grid");
  if (axes.empty()) return p;
  // Odometer over the axes, the last one turning fastest.
  std::vector<std::size_t> at(axes.size(), 0);
  for (;;) {
    std::vector<std::string> row;
    for (std::size_t k = 0; k < axes.size(); ++k) row.push_back(axes[k].values[at[k]]);
    p.cases.push_back(row);
    std::size_t k = axes.size();
    while (k > 0) {
      --k;
      if (++at[k] < axes[k].values.size()) break;
      at[k] = 0;
      if (k == 0) return p;
    }
  }
}

SweepPlan casesPlan(const std::string& scene, const std::vector<std::string>& overrides,
                    const std::string& csv_text, const std::string& file) {
  SweepPlan p;
  p.scene = scene;
  p.overrides = overrides;
  std::istringstream in(csv_text);
  std::string line;
  int number = 0;
  bool header = true;
  while (std::getline(in, line)) {
    ++number;
    if (trim(line).empty() || trim(line)[0] == '#') continue;
    std::vector<std::string> fields = splitCsv(line);
    if (header) {
      p.keys = fields;
      checkKeys(p.keys, file + " line " + std::to_string(number));
      header = false;
      continue;
    }
    if (fields.size() != p.keys.size()) {
      throw SweepError(file + " line " + std::to_string(number) + ": " +
                       std::to_string(fields.size()) + " values for " +
                       std::to_string(p.keys.size()) + " keys");
    }
    for (const std::string& f : fields) {
      if (f.empty())
        throw SweepError(file + " line " + std::to_string(number) + ": an empty value");
    }
    p.cases.push_back(fields);
  }
  if (header) throw SweepError(file + ": no header line of keys");
  return p;
}

namespace {
std::map<std::string, PlanKind>& planKinds() {
  static std::map<std::string, PlanKind> kinds;
  return kinds;
}
}  // namespace

bool registerPlanKind(const std::string& name, PlanKind kind) {
  planKinds()[name] = std::move(kind);
  return true;
}

const PlanKind* findPlanKind(const std::string& name) {
  const auto it = planKinds().find(name);
  return it == planKinds().end() ? nullptr : &it->second;
}

void checkPlan(const SweepPlan& plan) {
  if (plan.cases.empty()) {
    throw SweepError("the sweep has no cases (give --grid KEY=VALUES or a --cases file with rows)");
  }
  // (A kind whose refused scene is one of its results checks none.)
  const PlanKind* kind = findPlanKind(plan.kind);
  if (kind && !kind->check_scenes) return;
  for (std::size_t i = 0; i < plan.cases.size(); ++i) {
    try {
      (void)cws::loadScene(plan.scene, plan.caseOverrides(i));
    } catch (const cws::SceneError& e) {
      throw cws::SceneError(
          e.key(), e.why() + " (sweep case " + std::to_string(i) + ": " + plan.caseLabel(i) + ")");
    }
  }
}

std::string planText(const SweepPlan& plan) {
  std::ostringstream out;
  out << "# A sweep's plan, written by wire_sim sweep: the cases that wire_sim sweep-run\n"
         "# runs by index and wire_sim sweep-gather tabulates (tab-separated).\n";
  out << "kind\t" << plan.kind << "\n";
  out << "scene\t" << plan.scene << "\n";
  for (const auto& kv : plan.options) out << "option\t" << kv.first << "\t" << kv.second << "\n";
  for (const std::string& o : plan.overrides) out << "set\t" << o << "\n";
  out << "keys";
  for (const std::string& k : plan.keys) out << "\t" << k;
  out << "\n";
  for (const std::vector<std::string>& row : plan.cases) {
    out << "case";
    for (const std::string& v : row) out << "\t" << v;
    out << "\n";
  }
  if (!plan.names.empty()) {
    out << "names";
    for (const std::string& n : plan.names) out << "\t" << n;
    out << "\n";
  }
  return out.str();
}

SweepPlan parsePlanText(const std::string& text, const std::string& file) {
  SweepPlan p;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  bool have_scene = false, have_keys = false;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> f;
    std::size_t start = 0;
    for (;;) {
      const std::size_t tab = line.find('\t', start);
      f.push_back(line.substr(start, tab == std::string::npos ? std::string::npos : tab - start));
      if (tab == std::string::npos) break;
      start = tab + 1;
    }
    const std::string where = file + " line " + std::to_string(number);
    if (f[0] == "kind" && f.size() == 2) {
      if (f[1] != "sweep" && !findPlanKind(f[1])) {
        std::string known = "sweep";
        for (const auto& [name, k] : planKinds()) known += ", " + name;
        throw SweepError(where + ": unknown kind '" + f[1] + "' (" + known + ")");
      }
      p.kind = f[1];
    } else if (f[0] == "option" && f.size() == 3) {
      p.options.emplace_back(f[1], f[2]);
    } else if (f[0] == "names") {
      p.names.assign(f.begin() + 1, f.end());
    } else if (f[0] == "scene" && f.size() == 2) {
      p.scene = f[1];
      have_scene = true;
    } else if (f[0] == "set" && f.size() == 2) {
      p.overrides.push_back(f[1]);
    } else if (f[0] == "keys") {
      p.keys.assign(f.begin() + 1, f.end());
      have_keys = true;
    } else if (f[0] == "case" && have_keys && f.size() == p.keys.size() + 1) {
      p.cases.emplace_back(f.begin() + 1, f.end());
    } else {
      throw SweepError(where + ": not a line of a sweep plan");
    }
  }
  if (!have_scene || !have_keys) throw SweepError(file + ": not a sweep plan (no scene or keys)");
  if (!p.names.empty() && p.names.size() != p.cases.size()) {
    throw SweepError(file + ": " + std::to_string(p.names.size()) + " case names for " +
                     std::to_string(p.cases.size()) + " cases");
  }
  return p;
}

}  // namespace cws_tools
