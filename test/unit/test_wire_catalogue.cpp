// Wire from a material and a size (wire.material, wire.nominal_diameter,
// wire.insulation_grade) against the closed forms worked out here from the
// values docs/MODEL.md documents: E A, E pi d^4 / 64, G pi d^4 / 32, first
// yield at the surface, and IEC 60317-0-1's overall diameters.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "coil_winding_sim/core/scene/core_geometry.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace {
// docs/MODEL.md's annealed copper: E, G [Pa], density [kg/m^3], 0.2 % proof
// stress, tangent modulus [Pa]; the enamel's density [kg/m^3].
constexpr double kE = 117e9, kG = 44e9, kRho = 8890.0, kProof = 50e6, kTangent = 0.30e9;
constexpr double kEnamel = 1410.0;

cws::Scene copper(const std::string& more = "") {
  return cws::sceneFromYamlText(
      "wire: {material: annealed_copper, nominal_diameter: 0.00063, insulation_grade: 2" + more +
      "}");
}

std::string refusedKey(const std::string& text) {
  try {
    cws::sceneFromYamlText(text);
  } catch (const cws::SceneError& e) {
    return e.key();
  }
  return "(accepted)";
}
}  // namespace

TEST(WireCatalogue, RigiditiesAndYieldsFollowTheMaterialsValues) {
  const cws::Scene s = copper();
  const double d = 0.63e-3, pi = std::acos(-1.0);
  const double area = pi * d * d / 4.0, second = pi * std::pow(d, 4) / 64.0;
  const double polar = pi * std::pow(d, 4) / 32.0;
  auto within = [](double made, double expected) {
    return std::abs(made - expected) <= 0.005 * std::abs(expected);
  };
  EXPECT_TRUE(within(s.wire.stretch.elastic_rigidity, kE * area))
      << s.wire.stretch.elastic_rigidity;
  EXPECT_TRUE(within(s.wire.bend.elastic_rigidity, kE * second)) << s.wire.bend.elastic_rigidity;
  EXPECT_TRUE(within(s.wire.torsion.elastic_rigidity, kG * polar))
      << s.wire.torsion.elastic_rigidity;
  // First yield where the surface reaches the proof stress: strain
  // sigma / E, curvature sigma / (E r), twist (sigma / sqrt 3) / (G r).
  EXPECT_TRUE(within(s.wire.stretch.yield, kProof / kE));
  EXPECT_TRUE(within(s.wire.bend.yield, kProof / (kE * 0.5 * d)));
  EXPECT_TRUE(within(s.wire.torsion.yield, kProof / std::sqrt(3.0) / (kG * 0.5 * d)));
  // Beyond yield: the tangent modulus on the section; in shear the plastic
  // modulus H = E Et / (E - Et) acts as H / 3 in series with G.
  EXPECT_TRUE(within(s.wire.stretch.plastic_rigidity, kTangent * area));
  EXPECT_TRUE(within(s.wire.bend.plastic_rigidity, kTangent * second));
  const double h = kE * kTangent / (kE - kTangent);
  EXPECT_TRUE(within(s.wire.torsion.plastic_rigidity, polar / (1.0 / kG + 3.0 / h)));
  // Contact and layers: grade 2's largest overall diameter, 0.704 mm; the
  // mass: copper and enamel.
  EXPECT_DOUBLE_EQ(s.wire.diameter, 0.704e-3);
  const double overall = 0.704e-3;
  EXPECT_TRUE(
      within(s.wire.line_density, kRho * area + kEnamel * pi * (overall * overall - d * d) / 4.0));
  EXPECT_EQ(s.made_keys.size(), 11u);
}

TEST(WireCatalogue, GradesAndMaterialsChangeWhatTheyShould) {
  // Grade 0: bare, the nominal diameter; grades 1 and 3: the table's.
  EXPECT_DOUBLE_EQ(copper().wire.diameter, 0.704e-3);
  const cws::Scene bare = cws::sceneFromYamlText(
      "wire: {material: annealed_copper, nominal_diameter: 0.00063, insulation_grade: 0}");
  EXPECT_DOUBLE_EQ(bare.wire.diameter, 0.63e-3);
  EXPECT_LT(bare.wire.line_density, copper().wire.line_density);
  EXPECT_EQ(bare.wire.bend.elastic_rigidity, copper().wire.bend.elastic_rigidity);
  const cws::Scene thick = cws::sceneFromYamlText(
      "wire: {material: annealed_copper, nominal_diameter: 0.001, insulation_grade: 3}");
  EXPECT_DOUBLE_EQ(thick.wire.diameter, 1.124e-3);
  // Aluminium of the same size: the ratio of the moduli, 69 / 117.
  const cws::Scene al = cws::sceneFromYamlText(
      "wire: {material: aluminium_1350, nominal_diameter: 0.00063, insulation_grade: 2}");
  EXPECT_NEAR(al.wire.bend.elastic_rigidity / copper().wire.bend.elastic_rigidity, 69.0 / 117.0,
              1e-12);
}

TEST(WireCatalogue, AGivenNumberOverridesTheMadeOne) {
  const cws::Scene s = copper(", bend: {elastic_rigidity: 1.0e-3}");
  EXPECT_EQ(s.wire.bend.elastic_rigidity, 1.0e-3);
  EXPECT_EQ(s.made_keys.size(), 10u);
  EXPECT_EQ(std::count(s.made_keys.begin(), s.made_keys.end(), "wire.bend.elastic_rigidity"), 0);
  // And the printed scene says what was made, from what.
  const std::string text = cws::sceneToYamlText(s);
  EXPECT_NE(text.find("wire.material annealed_copper, wire.nominal_diameter 0.00063 m, "
                      "wire.insulation_grade 2"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("wire.bend.plastic_rigidity"), std::string::npos);
  // A printed scene read again is the same scene, its numbers now given.
  const cws::Scene again = cws::sceneFromYamlText(text);
  EXPECT_EQ(cws::sceneToYamlText(again).substr(0, text.find('#')), text.substr(0, text.find('#')));
}

TEST(WireCatalogue, ThePapersWireIsTable1) {
  const cws::Scene s = cws::sceneFromYamlText("wire: {material: paper_table_1}");
  EXPECT_EQ(s.wire.diameter, 1.0e-3);
  EXPECT_EQ(s.wire.line_density, 7.02e-3);
  EXPECT_EQ(s.wire.stretch.elastic_rigidity, 4.89e4);
  EXPECT_EQ(s.wire.bend.plastic_rigidity, 1.13e-4);
  EXPECT_EQ(s.wire.torsion.yield, 1.31);
}

TEST(WireCatalogue, WhatCannotBeMadeIsRefusedByItsKey) {
  // A size the grade table does not hold, and grade 3 at 1.6 mm.
  EXPECT_EQ(refusedKey("wire: {material: annealed_copper, nominal_diameter: 0.00065, "
                       "insulation_grade: 2}"),
            "wire.insulation_grade");
  EXPECT_EQ(refusedKey("wire: {material: annealed_copper, nominal_diameter: 0.0016, "
                       "insulation_grade: 3}"),
            "wire.insulation_grade");
  // With the overall diameter given, any size is made.
  EXPECT_EQ(refusedKey("wire: {material: annealed_copper, nominal_diameter: 0.00065, "
                       "insulation_grade: 2, diameter: 0.00072}"),
            "(accepted)");
  EXPECT_EQ(refusedKey("wire: {material: annealed_copper}"), "wire.nominal_diameter");
  EXPECT_EQ(refusedKey("wire: {material: brass, nominal_diameter: 0.001}"), "wire.material");
  EXPECT_EQ(refusedKey("wire: {material: annealed_copper, nominal_diameter: 0.001, "
                       "insulation_grade: 4}"),
            "wire.insulation_grade");
  // The paper's measured wire has one size and no enamel grade.
  EXPECT_EQ(refusedKey("wire: {nominal_diameter: 0.00063}"), "wire.nominal_diameter");
  EXPECT_EQ(refusedKey("wire: {insulation_grade: 1}"), "wire.insulation_grade");
}

TEST(WireCatalogue, TheUsersCoilSceneIsItsWireOnItsBobbin) {
  const cws::Scene s =
      cws::loadScene(std::string(CWS_SOURCE_DIR) + "/config/scenes/user_coil.yaml", {});
  EXPECT_DOUBLE_EQ(s.wire.diameter, 0.704e-3);
  EXPECT_EQ(s.made_keys.size(), 11u);
  ASSERT_EQ(s.core.cylinders.size(), 4u);
  EXPECT_EQ(s.core.cylinders[0].center_core, Eigen::Vector2d(5e-3, 3e-3));
  EXPECT_EQ(s.core.cylinders[0].radius, 1e-3);
  EXPECT_TRUE(s.core.hull_faces);
  // The clamp holds the wire on the bobbin: its centre half the overall
  // diameter above the flat side.
  EXPECT_NEAR(cws::CoreSection(s.core).signedDistance(s.start.position.head<2>()), 0.352e-3, 1e-9);
}
