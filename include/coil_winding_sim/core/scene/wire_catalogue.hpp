// Wire from what a user knows: a material and a nominal size with its
// enamel grade, made into the scene's wire keys (docs/MODEL.md, "Wire from
// a material and a size"). Mechanics use the bare conductor; contact and
// the layers' geometry the overall diameter of the enamelled wire.
#pragma once

#include <string>
#include <vector>

#include "coil_winding_sim/core/base/hysteresis.hpp"

namespace cws {

// A conductor material's handbook values, each with its source in
// docs/MODEL.md.
struct WireMaterial {
  const char* name;
  double young_modulus;    // E [Pa]
  double shear_modulus;    // G [Pa]
  double density;          // [kg/m^3]
  double proof_stress;     // 0.2 % proof stress, the first yield [Pa]
  double tangent_modulus;  // stress over total strain beyond yield [Pa]
};

// The materials wire.material names beside paper_table_1 (the paper's
// measured wire, Table 1 as printed: no material values).
const std::vector<WireMaterial>& wireMaterials();
// paper_table_1 and the materials' names, for wire.material.
std::vector<std::string> wireMaterialNames();

// The wire's keys made from a material, a nominal bare diameter d [m] and
// an IEC 60317-0-1 grade (1-3; 0: bare).
struct MadeWire {
  double diameter;      // overall [m]: the grade's largest overall diameter
  double line_density;  // conductor and enamel [kg/m]
  HysteresisParams stretch, bend, torsion;
};

// Density of the enamel [kg/m^3] (polyamide-imide).
constexpr double kEnamelDensity = 1.41e3;

// `overall_diameter` [m] above 0: the overall diameter given (wire.diameter),
// which the grade's table entry then need not give. Throws SceneError naming
// the key that cannot be used: an unknown material (wire.material), a
// diameter that is not above 0 (wire.nominal_diameter), a grade the table
// does not list for that size (wire.insulation_grade). paper_table_1 gives
// Table 1's numbers and takes no size or grade.
MadeWire makeWire(const std::string& material, double nominal_diameter, int insulation_grade,
                  double overall_diameter = 0.0);

// The largest overall diameter [m] of an enamelled round copper wire of
// nominal diameter d [m] and grade 1-3 (IEC 60317-0-1, Table 1); 0 where the
// table has no such entry. Grade 0: d.
double overallDiameter(double nominal_diameter, int insulation_grade);

}  // namespace cws
