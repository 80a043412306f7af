#include "coil_winding_sim/core/scene/wire_catalogue.hpp"

#include <cmath>

#include "coil_winding_sim/core/scene/scene.hpp"
#include "scene_detail.hpp"

namespace cws {

using detail::fmt;

const std::vector<WireMaterial>& wireMaterials() {
  // E, G, density, 0.2 % proof stress, tangent modulus; sources in
  // docs/MODEL.md ("Wire from a material and a size").
  static const std::vector<WireMaterial> materials{
      {"annealed_copper", 117e9, 44e9, 8890.0, 50e6, 0.30e9},
      {"aluminium_1350", 69e9, 26e9, 2700.0, 28e6, 0.24e9},
  };
  return materials;
}

std::vector<std::string> wireMaterialNames() {
  std::vector<std::string> names{"paper_table_1"};
  for (const WireMaterial& m : wireMaterials()) names.push_back(m.name);
  return names;
}

namespace {
// IEC 60317-0-1, Table 1: nominal conductor diameter and the largest
// overall diameter of grades 1, 2 and 3 [mm] (0: not tabulated here).
struct EnamelRow {
  double nominal, grade[3];
};
constexpr EnamelRow kEnamelTable[] = {
    {0.200, {0.226, 0.239, 0.252}}, {0.250, {0.281, 0.297, 0.312}}, {0.315, {0.349, 0.367, 0.384}},
    {0.400, {0.439, 0.459, 0.478}}, {0.500, {0.544, 0.566, 0.587}}, {0.630, {0.679, 0.704, 0.728}},
    {0.710, {0.762, 0.789, 0.814}}, {0.800, {0.855, 0.884, 0.911}}, {1.000, {1.062, 1.094, 1.124}},
    {1.250, {1.316, 1.349, 1.381}}, {1.600, {1.670, 1.706, 0.0}},
};

std::string tabulatedSizes() {
  std::string out;
  for (const EnamelRow& row : kEnamelTable) out += (out.empty() ? "" : ", ") + fmt(row.nominal);
  return out + " mm";
}
}  // namespace

double overallDiameter(double nominal_diameter, int insulation_grade) {
  if (insulation_grade == 0) return nominal_diameter;
  if (insulation_grade < 1 || insulation_grade > 3) return 0.0;
  for (const EnamelRow& row : kEnamelTable) {
    if (std::abs(nominal_diameter - 1e-3 * row.nominal) <= 1e-9 * row.nominal) {
      return 1e-3 * row.grade[insulation_grade - 1];
    }
  }
  return 0.0;
}

MadeWire makeWire(const std::string& material, double nominal_diameter, int insulation_grade,
                  double overall_diameter) {
  // The paper's measured wire: Table 1 as the built-in defaults hold it.
  if (material == "paper_table_1") {
    const WireParams paper;
    if (nominal_diameter != 0.0 && nominal_diameter != paper.diameter) {
      throw SceneError("wire.nominal_diameter", "paper_table_1 is the paper's " +
                                                    fmt(paper.diameter) +
                                                    " m wire; give 0 (or that size), or a material "
                                                    "(annealed_copper, aluminium_1350) for " +
                                                    fmt(nominal_diameter) + " m");
    }
    if (insulation_grade != 0) {
      throw SceneError("wire.insulation_grade",
                       "paper_table_1 is the paper's wire as measured, with no enamel grade; "
                       "give 0, or a material for an enamelled wire");
    }
    return {paper.diameter, paper.line_density, paper.stretch, paper.bend, paper.torsion};
  }
  const WireMaterial* m = nullptr;
  for (const WireMaterial& candidate : wireMaterials()) {
    if (material == candidate.name) m = &candidate;
  }
  if (!m) {
    std::string names;
    for (const std::string& n : wireMaterialNames()) names += (names.empty() ? "" : ", ") + n;
    throw SceneError("wire.material", "unknown material '" + material + "'; one of " + names);
  }
  const double d = nominal_diameter;
  if (!(d > 0.0)) {
    throw SceneError(
        "wire.nominal_diameter",
        "wire.material " + material + " needs the bare conductor's diameter [m], got " + fmt(d));
  }
  const double overall =
      overall_diameter > 0.0 ? overall_diameter : overallDiameter(d, insulation_grade);
  if (!(overall > 0.0)) {
    throw SceneError("wire.insulation_grade",
                     "grade " + std::to_string(insulation_grade) + " of a " + fmt(1e3 * d) +
                         " mm wire is not in the IEC 60317-0-1 table held here (grades 1-3 of " +
                         tabulatedSizes() +
                         "; grade 3 not at 1.6 mm); give wire.diameter, the overall diameter [m]");
  }
  // Sections of the bare conductor: area, second moment, polar moment.
  const double area = M_PI * d * d / 4.0;
  const double inertia = M_PI * std::pow(d, 4) / 64.0;
  const double polar = 2.0 * inertia;
  const double E = m->young_modulus, G = m->shear_modulus, sy = m->proof_stress;
  // Beyond yield in shear (von Mises, linear hardening): the plastic modulus
  // H = E Et / (E - Et) acts as H / 3 on the shear strain, in series with G.
  const double H = E * m->tangent_modulus / (E - m->tangent_modulus);
  const double shear_tangent = 1.0 / (1.0 / G + 3.0 / H);
  MadeWire w;
  w.diameter = overall;
  w.line_density = m->density * area + kEnamelDensity * M_PI * (overall * overall - d * d) / 4.0;
  // First yield at the surface: strain sy / E; curvature sy / (E r); twist
  // tau_y / (G r) with tau_y = sy / sqrt(3).
  w.stretch = {E * area, m->tangent_modulus * area, sy / E};
  w.bend = {E * inertia, m->tangent_modulus * inertia, 2.0 * sy / (E * d)};
  w.torsion = {G * polar, shear_tangent * polar, 2.0 * sy / (std::sqrt(3.0) * G * d)};
  return w;
}

}  // namespace cws
