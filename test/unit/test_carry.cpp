// solver.carry_stuck_wire: wound wire at rest and held by static friction
// leaves the integrated system and moves rigidly with the core. Checked
// against the full model (shape and bulging), for rigidity, for release
// when the wire slips, for the energy balance and for exact snapshots.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "coil_winding_sim/core/run/simulation.hpp"
#include "coil_winding_sim/core/scene/core_geometry.hpp"

#ifdef CWS_SOURCE_DIR
namespace {
const std::string kDefault = std::string(CWS_SOURCE_DIR) + "/config/scenes/default.yaml";

// The paper's case at 1200 rpm, 30 N, symplectic Euler, with segments of `segment` [m] stepped at
// `step` [s] (2 mm and 2e-7 s unless a test says otherwise).
std::vector<std::string> paperCaseKeys(double turns, bool carry,
                                       const std::string& segment = "2e-3",
                                       const std::string& step = "2e-7") {
  return {"process.core_speed_rpm=1200",
          "wire.segment_length=" + segment,
          "solver.integrator=symplectic_euler",
          "solver.fixed_step=" + step,
          "process.turns=" + std::to_string(turns),
          std::string("solver.carry_stuck_wire=") + (carry ? "true" : "false")};
}

cws::Scene paperCase(double turns, bool carry, const std::string& segment = "2e-3",
                     const std::string& step = "2e-7") {
  return cws::loadScene(kDefault, paperCaseKeys(turns, carry, segment, step));
}

void runTo(cws::Simulation& sim, double t) {
  while (sim.time() < t) sim.step(t);
}

// Every wound point's stand-off from its committed position, with no
// cache: what WireModel::liveStandOff() keeps for carried points, and the
// bulging height from it, must agree.
void expectStandOffAsRecomputed(const cws::Simulation& sim) {
  const cws::WireModel& m = sim.model();
  const cws::BulgeReport b = cws::bulging(m);
  if (!b.valid) return;
  const cws::CoreSection section(sim.scene().core);
  double height = 0.0;
  for (int i = 0; i < b.wound_points; ++i) {
    const Eigen::Vector3d p_core = m.core()->pointCore(sim.time(), m.committed().p_world.col(i));
    const double h = section.signedDistance(p_core.head<2>()) - m.constants().radius;
    EXPECT_NEAR(cws::standOff(m, i), h, 1e-15)
        << "point " << i << ", " << m.carriedPoints() << " carried";
    height = std::max(height, h);
  }
  EXPECT_NEAR(b.height_m, height, 1e-15) << m.carriedPoints() << " carried points";
}
}  // namespace

// At the default scene's 1 mm segments, where the full model is converged
// in its step (a quarter of it moves the shape by 0.002 d; at 2 mm by
// 0.019 d, more than the target below: docs/history/2026-11-27-damped-reference-model.md).
TEST(Carry, MatchesTheFullModel) {
  cws::Simulation full(paperCase(1.75, false, "1e-3", "1e-7"));
  full.run();
  cws::Simulation carried(paperCase(1.75, true, "1e-3", "1e-7"));
  carried.run();
  const cws::WireModel& a = full.model();
  const cws::WireModel& b = carried.model();
  ASSERT_EQ(a.constants().n, b.constants().n);
  double shape = 0.0;
  for (int i = 0; i < a.constants().n; ++i) {
    shape = std::max(shape, (a.committed().p_world.col(i) - b.committed().p_world.col(i)).norm());
  }
  const double d = 2.0 * a.constants().radius;
  const double bulge_full = cws::bulging(a).height_m, bulge_carried = cws::bulging(b).height_m;
  const double bulge_rel = std::abs(bulge_carried / bulge_full - 1.0);
  std::printf(
      "carry: %d of %d points carried at the end; shape difference %.2e d, bulging %.4f vs "
      "%.4f mm (%.2e); wall %.2f s vs %.2f s (%.2fx)\n",
      b.carriedPoints(), b.constants().n, shape / d, bulge_carried * 1e3, bulge_full * 1e3,
      bulge_rel, carried.wallTime(), full.wallTime(), full.wallTime() / carried.wallTime());
  EXPECT_GT(b.carriedPoints(), b.constants().n / 3) << "most wound wire should be carried";
  // The accuracy targets: shape within 1 % of d, bulging within 2 %.
  EXPECT_LT(shape / d, 1e-2);
  EXPECT_LT(bulge_rel, 2e-2);
  // Energy balance still closes (kinetic + elastic + dissipated = work).
  const cws::EnergyReport e = carried.energy();
  std::printf("carry: energy imbalance %.2e of %.2e J work done (full model %.2e)\n", e.imbalance(),
              e.work_done, full.energy().imbalance());
  EXPECT_LT(std::abs(e.imbalance()), 1e-3 * e.work_done);
}

TEST(Carry, CarriedPointsMoveRigidlyWithTheCore) {
  cws::Simulation sim(paperCase(1.0, true));
  runTo(sim, 0.035);
  const cws::WireModel& m = sim.model();
  const int carried = m.carriedPoints();
  ASSERT_GT(carried, 5);
  std::vector<Eigen::Vector3d> before;
  for (int i = 1; i <= carried; ++i) {
    before.push_back(m.core()->pointCore(sim.time(), m.committed().p_world.col(i)));
  }
  const double t0 = sim.time();
  runTo(sim, t0 + 0.005);  // a tenth of a turn
  ASSERT_GE(m.carriedPoints(), carried);
  double drift = 0.0, speed = 0.0;
  for (int i = 1; i <= carried; ++i) {
    const Eigen::Vector3d p = m.committed().p_world.col(i);
    drift = std::max(drift, (m.core()->pointCore(sim.time(), p) - before[i - 1]).norm());
    speed = std::max(
        speed, (m.committed().v_world.col(i) - m.core()->velocityWorld(sim.time(), p)).norm());
  }
  std::printf("carry: %d carried points drift %.1e m in the core frame, relative speed %.1e m/s\n",
              carried, drift, speed);
  EXPECT_LT(drift, 1e-12);
  EXPECT_LT(speed, 1e-9);
}

// Wound at 30 N, then the supply pulls at 300 N: the static limit of the
// groups on the core is exceeded, they slip, and the core lets go of the
// wire behind them. Returns the carried points before the jump and the
// fewest after it, over 5 ms.
std::pair<int, int> carriedAroundATensionJump(const std::string& damping_ratio) {
  std::vector<std::string> keys = paperCaseKeys(1.0, true);
  keys.push_back("contact.damping_ratio=" + damping_ratio);
  keys.push_back("contact.friction_law=stick_speed");
  cws::Simulation sim(cws::loadScene(kDefault, keys));
  runTo(sim, 0.035);
  const int carried = sim.model().carriedPoints();
  sim.apply(cws::Setpoint::supplyTension(300.0));
  int least = carried;
  for (double t = sim.time(); t < 0.040; t += 1e-4) {
    runTo(sim, t);
    least = std::min(least, sim.model().carriedPoints());
    expectStandOffAsRecomputed(sim);  // points released, some carried again
  }
  std::printf(
      "carry (damping ratio %s): %d carried points at 30 N, down to %d after the tension "
      "jump to 300 N\n",
      damping_ratio.c_str(), carried, least);
  return {carried, least};
}

// With the paper's undamped springs and the stick_speed law.
TEST(Carry, ReleasedWhenTheWireSlips) {
  const auto [carried, least] = carriedAroundATensionJump("0");
  ASSERT_GT(carried, 5);
  EXPECT_LT(least, carried);
}

// A known defect, left for the engine's issue (39): with damped contact the
// jump leaves fewer than two stuck groups in the integrated wire, the
// release rule has no limit to scan up to, and the carried wire stays on
// the core while the full model's wound wire slides by millimetres. Under
// elastic slip (contact.friction_law) the same holds with the undamped
// springs too: the full model's wound points slide 0.5-5.9 mm in the 5 ms
// after the jump under either law and either damping ratio, and with
// elastic slip none is released. A rule
// that released there made the late-reversal coil crawl
// (docs/history/2026-11-27-damped-reference-model.md).
TEST(Carry, DISABLED_ReleasedWhenTheWireSlipsWithDampedContact) {
  const auto [carried, least] = carriedAroundATensionJump("1");
  ASSERT_GT(carried, 5);
  EXPECT_LT(least, carried);
}

TEST(Carry, ContinuedRunMatchesTheOriginal) {
  cws::Simulation a(paperCase(1.0, true));
  runTo(a, 0.03);
  ASSERT_GT(a.model().carriedPoints(), 0);
  const cws::SimulationState st = a.saveState();
  auto b = cws::Simulation::fromState(st);
  EXPECT_EQ(b->model().carriedPoints(), a.model().carriedPoints());
  runTo(a, 0.033);
  runTo(*b, 0.033);
  const int size = a.model().size();
  ASSERT_EQ(size, b->model().size());
  EXPECT_EQ(a.state().head(size), b->state().head(size));
  EXPECT_EQ(a.model().carriedPoints(), b->model().carriedPoints());
}

// The Newton-step methods place the carried wire only when it is read
// (WireModel::setCarriedDeferred): run for run, the state and the committed
// kinematics of the whole wire equal those of placing it after every step,
// to the last bit, while wire is taken on, and after the core reverses and
// the supply takes wire back (a point leaving books the energy of the whole
// wire); a snapshot holds the whole wire. (The release of carried wire,
// which places it too, is not reached here: at large steps the stuck groups
// hold where the explicit methods' ring and slip,
// docs/history/2026-11-23-accuracy-gap-planar.md.)
TEST(Carry, DeferredPlacementEqualsPlacingEveryStep) {
  const cws::Scene s = cws::loadScene(
      kDefault, {"process.core_speed_rpm=1200", "solver.integrator=bdf2", "process.turns=1.5"});
  cws::Simulation deferred(s), eager(s);
  eager.model().setCarriedDeferred(false);
  int most = 0, most_points = 0, fewest_points_after = 1 << 30;
  auto same = [&](double t) {
    runTo(deferred, t);
    runTo(eager, t);
    const int size = deferred.model().size();
    ASSERT_EQ(size, eager.model().size());
    ASSERT_EQ(deferred.model().carriedPoints(), eager.model().carriedPoints());
    most = std::max(most, deferred.model().carriedPoints());
    const cws::WireKinematics& a = deferred.model().committed();
    const cws::WireKinematics& b = eager.model().committed();
    const int n = deferred.model().constants().n;
    EXPECT_EQ(a.p_world.leftCols(n), b.p_world.leftCols(n)) << "t = " << t;
    EXPECT_EQ(a.q.leftCols(n), b.q.leftCols(n)) << "t = " << t;
    EXPECT_EQ(deferred.state().head(size), eager.state().head(size)) << "t = " << t;
    EXPECT_EQ(deferred.energy().kinetic, eager.energy().kinetic) << "t = " << t;
    expectStandOffAsRecomputed(deferred);
  };
  // Read every 0.2 ms (each read places the deferred wire).
  for (double t = 2e-4; t < 0.0601; t += 2e-4) same(t);
  most_points = deferred.model().constants().n;
  deferred.apply(cws::Setpoint::coreSpeed(-1200.0 * M_PI / 30.0));
  eager.apply(cws::Setpoint::coreSpeed(-1200.0 * M_PI / 30.0));
  for (double t = 0.0602; t < 0.090; t += 2e-4) {
    same(t);
    fewest_points_after = std::min(fewest_points_after, deferred.model().constants().n);
  }
  std::printf(
      "carry (bdf2, deferred): up to %d carried points; %d points before the reversal, "
      "down to %d after\n",
      most, most_points, fewest_points_after);
  EXPECT_GT(most, 20);
  EXPECT_LT(fewest_points_after, most_points);  // wire went back out through the port
  const cws::SimulationState a = deferred.saveState(), b = eager.saveState();
  EXPECT_EQ(a.model.y, b.model.y);
  EXPECT_EQ(a.model.carried_pose, b.model.carried_pose);
}

// A Newton step's velocity of a point at rest on the turning core is off
// the core material's exact velocity by the scheme's error, for BDF2
// h^2 omega^3 r / 3: at 3000 rpm (314 rad/s), 2e-4 s and r = 8-13 mm,
// 3.3-5.4 mm/s, several times contact.stick_speed (1 mm/s). Wire at rest
// must still be taken on, and a point that slid must stick again, both
// judged against the core material's velocity by the same scheme. Judged
// against the exact velocity, the integrated wire grew turn by turn: 103
// integrated points at 0.3 s with neither mended, 116 with the take-on
// mended but not the contact's re-stick.
TEST(Carry, TakesOnWireAtRestUnderNewtonStepsAtHighSpeed) {
  const std::string two_layers = std::string(CWS_SOURCE_DIR) + "/config/scenes/two_layers.yaml";
  cws::Simulation sim(
      cws::loadScene(two_layers, {"process.core_speed_rpm=3000", "solver.implicit_step=2e-4",
                                  "solver.steps_per_revolution=0", "process.turns=20"}));
  runTo(sim, 0.3);
  const int integrated = sim.model().constants().n - 1 - sim.model().carriedPoints();
  std::printf("carry at 3000 rpm, bdf2 at 2e-4 s: %d of %d points integrated at t = 0.3 s\n",
              integrated, sim.model().constants().n);
  // The free span from the port to the core (about 30 points) and the
  // last turn's stuck groups: well under a turn of wound wire (about 60).
  EXPECT_LT(integrated, 60);
}

// Robustness coil 23 (issue 57: 84.6 N, 1230 rpm, four layers, undamped
// contact). After the span strikes the wound wire, the first integrated
// points, held by the boundary point, slip at step after step. Until
// 2026-12-07 each such slip released one stuck group further back
// (CarriedWire::decide), through wire that stayed stuck: 124-171
// integrated points, the last two turns lying side by side in 33-128 pairs
// of free segments, a stretch at 0.036 of real time. Carried wire now goes
// only where its group's static friction cannot hold the tension
// difference across the boundary (here 0.01-7 N against 1.5-100 N); the
// release after a tension jump, which it cannot hold, is
// ReleasedWhenTheWireSlips above.
TEST(Carry, AStrikeDoesNotReleaseStuckTurns) {
  const std::string two_layers = std::string(CWS_SOURCE_DIR) + "/config/scenes/two_layers.yaml";
  cws::Simulation sim(cws::loadScene(
      two_layers,
      {"process.tension=84.6", "process.core_speed_rpm=1230", "process.traverse_pitch=0.001121",
       "process.winding_width=0.0191", "process.layers=4", "process.turns=50.4",
       "contact.static_friction=0.292", "contact.kinetic_friction=0.216", "contact.damping_ratio=0",
       "physics.flanges=true", "core.flange_height=0.004098"}));
  runTo(sim, 2.38);
  int widest = 0;
  while (sim.time() < 2.46) {
    sim.step(2.46);
    widest = std::max(widest, sim.model().constants().n - 1 - sim.model().carriedPoints());
  }
  std::printf("robustness coil 23, 2.38-2.46 s: at most %d points integrated\n", widest);
  // The free span (about 30 points) and the last turn (about 65).
  EXPECT_LT(widest, 100);
}

// The core's work on the wire it carries while it speeds up: the explicit
// model books it as the carried points' power, a Newton step from their
// kinetic energy before and after the step (WireModel::
// carriedEnergyChange). The paper's case at 6000 rpm, where the core is
// still speeding up when the first wound wire is carried, bdf2 at 1e-5 s:
// measured 2026-11-28, the work booked with the carried wire 0.21154 J
// against 0.21168 J without it; before the Newton steps booked it, 0.20764 J,
// and 1.35 % of the work showed as energy created.
TEST(Carry, NewtonStepsBookTheCoreWorkOnCarriedWire) {
  auto run = [](bool carry) {
    cws::Simulation sim(cws::loadScene(
        kDefault,
        {"process.core_speed_rpm=6000", "solver.integrator=bdf2", "solver.implicit_step=1e-5",
         std::string("solver.carry_stuck_wire=") + (carry ? "true" : "false")}));
    sim.run();
    return sim;
  };
  const cws::Simulation with = run(true);
  const cws::Simulation without = run(false);
  ASSERT_GT(with.model().carriedPoints(), 20);
  const cws::EnergyReport e_with = with.energy();
  const cws::EnergyReport e_without = without.energy();
  std::printf("6000 rpm, bdf2 at 1e-5 s: work %.5f J carried, %.5f J not; imbalance %.2e J\n",
              e_with.work_done, e_without.work_done, e_with.imbalance());
  // The same work within the runs' own difference in motion (kinetic and
  // dissipated energy agree within 0.1 %), ...
  EXPECT_NEAR(e_with.work_done, e_without.work_done, 2e-3 * e_without.work_done);
  // ... and no energy created: a Newton step only loses energy.
  EXPECT_LT(e_with.imbalance(), 1e-3 * e_with.work_done);
}

TEST(Carry, NoEffectWhereNothingCanBeCarried) {
  // Without friction nothing holds wire on the core: the option is inert and
  // the run is the full model's, number for number.
  cws::Scene s = paperCase(0.2, true);
  s.physics.friction = false;
  cws::Simulation with(s);
  s.solver.carry_stuck_wire = false;
  cws::Simulation without(s);
  with.run();
  without.run();
  EXPECT_EQ(with.model().carriedPoints(), 0);
  const int size = with.model().size();
  ASSERT_EQ(size, without.model().size());
  EXPECT_EQ(with.state().head(size), without.state().head(size));
}
#endif
