// A coil's quality figures (run/quality_report) against closed forms: the
// permanent strain the two-line law leaves after a pull past yield, the
// bending strain of a wire on a cylinder, the enamel's limits by size, and
// the fill factor of a bobbin's window.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "coil_winding_sim/core/run/coil_report.hpp"
#include "coil_winding_sim/core/run/quality_report.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"
#include "wire_test_support.hpp"

namespace {
// The paper's case (planar, bdf2, 1 3/4 turns on four 2.5 mm cylinders).
const std::string kPaperScene = std::string(CWS_SOURCE_DIR) + "/config/scenes/default.yaml";
}  // namespace

TEST(QualityReport, APullPastYieldLeavesTheTwoLineLawsPermanentStrain) {
  // A straight wire pulled along its axis to F = 60 N, past its yield force
  // EA a = 39.1 N, slowly and damped: on the upper line F = kp x + C,
  // C = a (ke - kp); unloaded along ke it keeps x - F / ke.
  cws::Scene s = cws_test::rampedStatic(cws_test::cantilever(0.02, 10), {60.0, 0.0, 0.0},
                                        Eigen::Vector3d::Zero(), 0.02, 0.03);
  s.solver.integrator = "bdf2";
  cws::Simulation sim(s);
  sim.run();
  const cws::QualityReport q = cws::reportQuality(sim.model(), s, cws::CoilReport{});
  const double ke = 4.89e4, kp = 1.10e3, a = 8.0e-4, force = 60.0;
  const double x = (force - a * (ke - kp)) / kp;
  const double permanent = x - force / ke;
  EXPECT_NEAR(q.plastic_elongation, permanent, 0.02 * permanent);
  EXPECT_NEAR(q.cross_section_lost, q.plastic_elongation / (1.0 + q.plastic_elongation), 1e-15);
  EXPECT_GE(q.plastic_elongation_segment, 0);
  // No coil: no bending of wound wire, no window.
  EXPECT_EQ(q.bending_strain_point, -1);
  EXPECT_TRUE(std::isnan(q.fill_factor));
}

TEST(QualityReport, TheEnamelsLimitsBySize) {
  // A wrap on a mandrel of one diameter strains the surface by 1/2.
  EXPECT_EQ(cws::mandrelBendingLimit(0.63e-3), 0.5);
  EXPECT_EQ(cws::mandrelBendingLimit(0.1e-3), 0.0);
  EXPECT_EQ(cws::mandrelBendingLimit(2.0e-3), 0.0);
  EXPECT_DOUBLE_EQ(cws::elongationAtBreakLimit(0.63e-3), 0.27);
  EXPECT_DOUBLE_EQ(cws::elongationAtBreakLimit(1.0e-3), 0.30);
  EXPECT_DOUBLE_EQ(cws::elongationAtBreakLimit(0.2e-3), 0.21);
  EXPECT_EQ(cws::elongationAtBreakLimit(2.0e-3), 0.0);
}

TEST(QualityReport, WireWoundOnACylinderIsBentByItsRadius) {
  // The paper's case: 1 mm wire on cylinders of 2.5 mm radius, its centre
  // line at 3.0 mm: a surface strain of 0.5 / 3.0 where it lies on them.
  const cws::Scene s = cws::loadScene(kPaperScene, {});
  cws::Simulation sim(s);
  sim.run();
  const cws::CoilReport coil = cws::reportCoil(sim.model(), s);
  ASSERT_TRUE(coil.valid);
  const cws::QualityReport q = cws::reportQuality(sim.model(), s, coil);
  EXPECT_NEAR(q.bending_strain, 0.5 / 3.0, 0.1 * 0.5 / 3.0);
  // Bare wire: no enamel, no limits, no turn flagged.
  EXPECT_EQ(q.bending_limit, 0.0);
  EXPECT_TRUE(q.turns_past_limits.empty());
}

TEST(QualityReport, EnamelledWireBentPastItsLimitsIsFlagged) {
  // 1.0 mm grade 2 copper (overall 1.094 mm) on the paper's core: its
  // surface bent 0.5 / (2.5 + 0.547) = 0.16 on the cylinders, below the
  // 30 % elongation at break; on cylinders of 0.5 mm radius 0.5 / 1.047 =
  // 0.48, past it, and the turns on them are flagged.
  auto quality = [](const std::string& radius) {
    std::vector<std::string> keys{"wire.material=annealed_copper", "wire.nominal_diameter=0.001",
                                  "wire.insulation_grade=2", "wire.segment_length=0.0005"};
    const std::string r = ", radius: " + radius + "}";
    keys.push_back("core.cylinders=[{center: [0.0075, 0.0025]" + r +
                   ", {center: [-0.0075, 0.0025]" + r + ", {center: [-0.0075, -0.0025]" + r +
                   ", {center: [0.0075, -0.0025]" + r + "]");
    const cws::Scene s = cws::loadScene(kPaperScene, keys);
    cws::Simulation sim(s);
    sim.run();
    const cws::QualityReport q =
        cws::reportQuality(sim.model(), s, cws::reportCoil(sim.model(), s));
    // The share of the limits used where the wire is bent most (rviz's
    // enamel_risk colours).
    return std::make_pair(q, cws::enamelRisk(sim.model(), s, q.bending_strain_point));
  };
  const auto [wide, wide_risk] = quality("0.0025");
  EXPECT_DOUBLE_EQ(wide.elongation_limit, 0.30);
  EXPECT_EQ(wide.bending_limit, 0.5);
  EXPECT_NEAR(wide.bending_strain, 0.5 / 3.047, 0.1 * 0.5 / 3.047);
  EXPECT_TRUE(wide.turns_past_limits.empty());
  // The surface strain over the elongation limit (the axial strain at 30 N
  // is 3e-4): 0.164 / 0.30.
  EXPECT_NEAR(wide_risk, 0.5 / 3.047 / 0.30, 0.1 * 0.5 / 3.047 / 0.30);
  const auto [sharp, sharp_risk] = quality("0.0005");
  EXPECT_GT(sharp_risk, 1.0);
  EXPECT_NEAR(sharp.bending_strain, 0.5 / 1.047, 0.1 * 0.5 / 1.047);
  EXPECT_FALSE(sharp.turns_past_limits.empty());
  EXPECT_EQ(sharp.turns_past_limits.front(), 1);
}

TEST(QualityReport, AHelixOnARoundCoreClimbsOverEightTenthsOfATurn) {
  // One layer on a round core of 5 mm radius, laid as the traverse moves
  // by 1.5 wire diameters per turn (turns apart: none pushes on the one
  // before): a helix, whose axial position climbs evenly with the angle,
  // from 0.1 to 0.9 of its step over 0.8 x 2 pi.
  const cws::Scene s = cws::loadScene(
      std::string(CWS_SOURCE_DIR) + "/config/scenes/two_layers.yaml",
      {"core.shape={kind: rounded_rectangle, width: 0.010, height: 0.010, corner_radius: 0.005}",
       "start.position=[0.0, -0.0055, 0.0]", "process.turns=15", "process.layers=1",
       "process.traverse_pitch=0.0015"});
  ASSERT_EQ(s.core.cylinders.size(), 1u);
  cws::Simulation sim(s);
  sim.run();
  const cws::CoilReport coil = cws::reportCoil(sim.model(), s);
  const cws::QualityReport q = cws::reportQuality(sim.model(), s, coil);
  ASSERT_EQ(q.crossover_per_layer_rad.size(), 1u);
  const double helix = 0.8 * 2.0 * M_PI;
  std::printf("crossover: %.4f rad, a helix's %.4f rad\n", q.crossover_per_layer_rad[0], helix);
  EXPECT_NEAR(q.crossover_per_layer_rad[0], helix, 0.05 * helix);
  // The turns of 1 mm wire over the 26 mm x 3 mm window.
  EXPECT_NEAR(q.fill_factor, coil.turns_wound * M_PI * 1e-6 / 4.0 / (26e-3 * 3e-3), 1e-12);
}
