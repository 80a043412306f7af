// The traverse of a linear winding machine (TraverseProfile) against its
// closed form, a triangle wave of the core angle, and the supply's port
// following it through a 3-D run with a reversal.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "coil_winding_sim/core/external_forces/supply.hpp"
#include "coil_winding_sim/core/machine/traverse_profile.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"

namespace {
constexpr double kTurn = 2.0 * M_PI;  // [rad]
}  // namespace

TEST(TraverseProfile, NoWidthIsASpiral) {
  const cws::TraverseProfile p{1e-3, 0.0, 0};
  EXPECT_DOUBLE_EQ(p.at(3.5 * kTurn).offset, 3.5e-3);
  EXPECT_DOUBLE_EQ(p.at(3.5 * kTurn).per_rad, 1e-3 / kTurn);
  // A core turned back past its start: the line goes on.
  EXPECT_DOUBLE_EQ(p.at(-0.5 * kTurn).offset, -0.5e-3);
  EXPECT_EQ(p.at(3.5 * kTurn).layer, 0);
}

TEST(TraverseProfile, ReversesAtTheEndsLayerAfterLayer) {
  // 1 mm per turn over a travel of 4 mm: out in 4 turns, back in the next 4.
  const cws::TraverseProfile p{1e-3, 4e-3, 3};
  struct Expect {
    double turns, offset_m, per_turn_m;
    int layer;
  };
  for (const Expect& e :
       {Expect{0.0, 0.0, 1e-3, 0}, Expect{2.5, 2.5e-3, 1e-3, 0}, Expect{4.5, 3.5e-3, -1e-3, 1},
        Expect{7.25, 0.75e-3, -1e-3, 1}, Expect{9.0, 1.0e-3, 1e-3, 2},
        // After three passes the port stays at the far end.
        Expect{12.5, 4.0e-3, 0.0, 2}, Expect{40.0, 4.0e-3, 0.0, 2}}) {
    const cws::TraverseProfile::Position q = p.at(e.turns * kTurn);
    EXPECT_NEAR(q.offset, e.offset_m, 1e-15) << e.turns << " turns";
    EXPECT_NEAR(q.per_rad * kTurn, e.per_turn_m, 1e-15) << e.turns << " turns";
    EXPECT_EQ(q.layer, e.layer) << e.turns << " turns";
  }
}

TEST(TraverseProfile, ANegativePitchStartsTheOtherWay) {
  const cws::TraverseProfile p{-1e-3, 2e-3, 0};
  EXPECT_NEAR(p.at(1.0 * kTurn).offset, -1e-3, 1e-15);
  EXPECT_NEAR(p.at(3.0 * kTurn).offset, -1e-3, 1e-15);
  EXPECT_NEAR(p.at(3.0 * kTurn).per_rad * kTurn, 1e-3, 1e-15);
}

#ifdef CWS_SOURCE_DIR
TEST(TraverseProfile, ThePortReversesInA3dRun) {
  // The paper's 3-D spiral in a winding width of d + 1 mm: the port goes
  // 1 mm out in the first turn and comes back 0.75 mm in the next 3/4.
  const std::string scene = std::string(CWS_SOURCE_DIR) + "/config/scenes/paper_case_3d.yaml";
  const cws::Scene s0 = cws::loadScene(scene, {});
  const double width = s0.wire.diameter + 1e-3;
  const cws::Scene s = cws::loadScene(scene, {"process.winding_width=" + std::to_string(width),
                                              "process.layers=2", "solver.integrator=bdf2"});
  cws::Simulation sim(s);
  sim.run();
  const Eigen::Vector3d axis = s.core.axis_world.normalized();
  const double turned = sim.model().core()->angle(sim.time()) / kTurn;
  ASSERT_NEAR(turned, 1.75, 1e-6);
  const double offset =
      (sim.model().supply()->port(sim.time()).p_world - s.supply.port_position_world).dot(axis);
  EXPECT_NEAR(offset, 0.25e-3, 1e-9);
  // The wire follows: its last point lies on the port's line, within a few
  // wire diameters of the port along the axis.
  const cws::WireKinematics& k = sim.model().committed();
  const int last = sim.model().constants().n - 1;
  const double z_last = (k.p_world.col(last) - s.supply.port_position_world).dot(axis);
  EXPECT_NEAR(z_last, offset, 2.0 * s.wire.diameter);
}
#endif
