// Buried wound wire retired from the live arrays (WireModel::
// retireBuriedWire): a run whose storage holds a fraction of its wire must
// wind the same coil as one that keeps every point live, point for point,
// with the same energy balance and reports, and continue exactly from a
// snapshot taken after a retirement.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "coil_winding_sim/core/run/coil_report.hpp"
#include "coil_winding_sim/core/run/quality_report.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"

#ifdef CWS_SOURCE_DIR
namespace {
const std::string kScenes = std::string(CWS_SOURCE_DIR) + "/config/scenes/";

// A 3-D coil of five layers on a narrow bobbin, Newton steps (the default
// method) with wire contact: six turns a layer, so 16 turns of carried wire
// stay live (WireModel::keepTurns) and the rest may retire. `points`: the
// live storage (0: the job's estimate, which holds every point).
cws::Scene narrowCoil(int points) {
  return cws::loadScene(kScenes + "two_layers.yaml",
                        {"process.winding_width=6e-3", "process.layers=5", "process.turns=27",
                         "core.flange_height=8e-3", "supply.max_points=" + std::to_string(points)});
}

// The planar paper case of the cell (eight turns stay live).
cws::Scene planarCoil(int points) {
  return cws::loadScene(kScenes + "winding_cell.yaml",
                        {"process.turns=20", "supply.max_points=" + std::to_string(points)});
}

// Every point of two runs of one coil: the same position in the core frame
// and stand-off (bit for bit, the clamp's to rounding), the same contact flags, the figures of the
// retired points as they were (the strains and curvatures to rounding:
// carried wire is placed anew in the world at each report).
void expectSameWire(const cws::WireModel& kept, const cws::WireModel& retired) {
  ASSERT_EQ(kept.wirePoints(), retired.wirePoints());
  ASSERT_EQ(kept.retiredPoints(), 0);
  for (int w = 0; w < kept.wirePoints(); ++w) {
    ASSERT_EQ(cws::wirePointCore(kept, w), cws::wirePointCore(retired, w)) << "point " << w;
    // (The clamp, point 0, is placed through the core's pose at the end in
    // the run that keeps it, and was stored at its retirement in the other:
    // the same to rounding.)
    if (w == 0) {
      ASSERT_NEAR(cws::standOff(kept, w), cws::standOff(retired, w), 1e-15);
    } else {
      ASSERT_EQ(cws::standOff(kept, w), cws::standOff(retired, w)) << "point " << w;
    }
    const cws::PointReport a = cws::wirePoint(kept, w), b = cws::wirePoint(retired, w);
    EXPECT_NEAR(a.p_world.x(), b.p_world.x(), 1e-15) << "point " << w;
    EXPECT_NEAR(a.p_world.y(), b.p_world.y(), 1e-15) << "point " << w;
    EXPECT_EQ(a.p_world.z(), b.p_world.z()) << "point " << w;
    EXPECT_NEAR(a.axial_force_N, b.axial_force_N, 1e-6) << "point " << w;
    EXPECT_NEAR(a.curvature_1pm, b.curvature_1pm, 1e-9 * (1.0 + a.curvature_1pm)) << "point " << w;
    EXPECT_EQ(a.plastic_curvature_1pm, b.plastic_curvature_1pm) << "point " << w;
    EXPECT_NEAR(a.twist_rad_per_m, b.twist_rad_per_m, 1e-9) << "point " << w;
    EXPECT_EQ(a.in_contact, b.in_contact) << "point " << w;
    EXPECT_EQ(a.stick, b.stick) << "point " << w;
    for (int s = 0; kept.contact() && s < kept.contact()->slots(); ++s) {
      EXPECT_EQ(kept.contactSurface(w, s), retired.contactSurface(w, s))
          << "point " << w << ", slot " << s;
    }
  }
}

void expectSameEnergy(const cws::Simulation& kept, const cws::Simulation& retired) {
  const cws::EnergyReport a = kept.energy(), b = retired.energy();
  // (Sums over other ranges of points: equal to rounding.)
  const double scale = 1e-12 * (std::abs(a.work_done) + 1.0);
  EXPECT_NEAR(a.kinetic, b.kinetic, scale);
  EXPECT_NEAR(a.elastic, b.elastic, scale);
  EXPECT_NEAR(a.plastic, b.plastic, scale);
  EXPECT_NEAR(a.viscous, b.viscous, scale);
  EXPECT_NEAR(a.work_done, b.work_done, scale);
}
}  // namespace

TEST(RetiredWire, CoilMatchesTheRunThatKeepsEveryPoint) {
  cws::Simulation kept(narrowCoil(0));
  kept.run();
  cws::Simulation retired(narrowCoil(1300));
  retired.run();
  // Storage for 1,300 points: wound wire retired at least twice.
  ASSERT_GT(kept.model().wirePoints(), 1300 + 600);
  EXPECT_GT(retired.model().retiredPoints(), 600);
  EXPECT_LE(retired.model().constants().capacity, 1300);
  EXPECT_EQ(kept.stepper().counts().accepted, retired.stepper().counts().accepted);
  EXPECT_EQ(kept.time(), retired.time());
  expectSameWire(kept.model(), retired.model());
  expectSameEnergy(kept, retired);
  // The coil's figures read the retired wire as the live.
  const cws::CoilReport a = cws::reportCoil(kept.model(), kept.scene());
  const cws::CoilReport b = cws::reportCoil(retired.model(), retired.scene());
  ASSERT_TRUE(a.valid && b.valid);
  EXPECT_EQ(a.layers, b.layers);
  EXPECT_EQ(a.turns.size(), b.turns.size());
  EXPECT_EQ(a.point_layer, b.point_layer);
  EXPECT_EQ(a.gaps, b.gaps);
  EXPECT_EQ(a.overlaps, b.overlaps);
  const cws::BulgeReport ba = cws::headlineBulging(kept.model(), kept.scene());
  const cws::BulgeReport bb = cws::headlineBulging(retired.model(), retired.scene());
  EXPECT_EQ(ba.height_m, bb.height_m);
  EXPECT_EQ(ba.build_up_m, bb.build_up_m);
  EXPECT_EQ(ba.index, bb.index);
  EXPECT_EQ(kept.maxPenetration(), retired.maxPenetration());
}

TEST(RetiredWire, PlanarCoilMatchesTheRunThatKeepsEveryPoint) {
  cws::Simulation kept(planarCoil(0));
  kept.run();
  cws::Simulation retired(planarCoil(700));
  retired.run();
  ASSERT_GT(kept.model().wirePoints(), 700 + 400);
  EXPECT_GT(retired.model().retiredPoints(), 400);
  EXPECT_EQ(kept.stepper().counts().accepted, retired.stepper().counts().accepted);
  expectSameWire(kept.model(), retired.model());
  expectSameEnergy(kept, retired);
  EXPECT_EQ(cws::bulging(kept.model()).height_m, cws::bulging(retired.model()).height_m);
}

TEST(RetiredWire, RetiredWireKeepsItsPermanentElongation) {
  // At 45 N the paper's wire arrives yielded (its yield force is 39 N): the
  // quality figures read the retired wire's permanent strain as the live.
  auto coil = [](int points) {
    cws::Scene s = planarCoil(points);
    s.process.tension = 45.0;
    return s;
  };
  cws::Simulation kept(coil(0));
  kept.run();
  cws::Simulation retired(coil(700));
  retired.run();
  ASSERT_GT(retired.model().retiredPoints(), 400);
  // Each retired segment's strain as the run that keeps it has it.
  double most_retired = 0.0;
  for (int w = 0; w < retired.model().retiredPoints(); ++w) {
    const double eps = retired.model().retiredWire()[w].segment_plastic_strain;
    most_retired = std::max(most_retired, eps);
    ASSERT_NEAR(eps, kept.model().stretching().plasticStrain(w), 1e-15) << "segment " << w;
  }
  EXPECT_GT(most_retired, 1e-4);
  const cws::QualityReport a =
      cws::reportQuality(kept.model(), kept.scene(), cws::reportCoil(kept.model(), kept.scene()));
  const cws::QualityReport b = cws::reportQuality(
      retired.model(), retired.scene(), cws::reportCoil(retired.model(), retired.scene()));
  EXPECT_EQ(a.plastic_elongation, b.plastic_elongation);
  EXPECT_EQ(a.plastic_elongation_segment, b.plastic_elongation_segment);
  EXPECT_GE(a.plastic_elongation, most_retired);
}

// A snapshot after a retirement carries the retired wire: the continued run
// ends where the uninterrupted one does (the restart's first step is
// backward Euler, as after any restore: to the Newton tolerance, not bit
// for bit).
TEST(RetiredWire, SnapshotAfterARetirementContinues) {
  cws::Simulation a(narrowCoil(1300));
  while (a.model().retiredPoints() == 0) a.step(a.endTime());
  const cws::SimulationState st = a.saveState();
  EXPECT_GT(st.model.retired, 0);
  auto b = cws::Simulation::fromState(st);
  EXPECT_EQ(b->model().retiredPoints(), a.model().retiredPoints());
  EXPECT_EQ(b->model().wirePoints(), a.model().wirePoints());
  for (int w = 0; w < a.model().wirePoints(); ++w) {
    ASSERT_EQ(cws::wirePointCore(a.model(), w), cws::wirePointCore(b->model(), w)) << "point " << w;
    ASSERT_NEAR(cws::wirePoint(a.model(), w).axial_force_N,
                cws::wirePoint(b->model(), w).axial_force_N, 1e-6)
        << w;
  }
  EXPECT_NEAR(a.energy().imbalance(), b->energy().imbalance(), 1e-12);
  const double t_end = a.time() + 0.05;
  while (a.time() < t_end) a.step(t_end);
  while (b->time() < t_end) b->step(t_end);
  double largest = 0.0;
  for (int w = 0; w < std::min(a.model().wirePoints(), b->model().wirePoints()); ++w) {
    largest = std::max(
        largest, (cws::wirePointCore(a.model(), w) - cws::wirePointCore(b->model(), w)).norm());
  }
  // 50 ms of winding on: within a hundredth of the wire's diameter.
  EXPECT_LT(largest, 1e-5);
}

// A scene that carries no wound wire refuses a snapshot with retired wire,
// naming it.
TEST(RetiredWire, ASceneThatCarriesNothingRefusesRetiredWire) {
  cws::Simulation a(narrowCoil(1300));
  while (a.model().retiredPoints() == 0) a.step(a.endTime());
  cws::SimulationState st = a.saveState();
  cws::Scene other = narrowCoil(1300);
  other.solver.carry_stuck_wire = false;
  other.physics.wire_contact = false;  // (it needs carried wire)
  cws::Simulation b(other);
  cws::ModelState m = st.model;
  m.carried = 0;  // (what it carries live is refused first)
  m.carried_pose.clear();
  Eigen::VectorXd y = Eigen::VectorXd::Zero(b.model().capacity());
  try {
    b.model().restoreState(m, y);
    FAIL() << "restored retired wire into a scene that carries none";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("retired points"), std::string::npos) << e.what();
  }
  // A retired-wire record of the wrong length is refused too.
  st.model.retired_points.pop_back();
  try {
    cws::Simulation::fromState(st);
    FAIL() << "restored a short retired-wire record";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("retired-wire values"), std::string::npos) << e.what();
  }
}
#endif
