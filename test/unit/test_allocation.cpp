// The integration step allocates nothing once a run is under way: global
// operator new is counted while a flag is set (this test binary only).
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <memory>
#include <new>
#include <string>

#include "coil_winding_sim/core/assembly/spatial_assembly.hpp"
#include "coil_winding_sim/core/external_forces/free_wire_contact.hpp"
#include "coil_winding_sim/core/implicit/pair_coupling_solve.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"

// GCC sees the replaced operator delete free() what operator new got from
// malloc() through inlining and warns; the pair is consistent.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

namespace {
std::atomic<bool> counting{false};
std::atomic<long> allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  if (counting.load(std::memory_order_relaxed)) allocations.fetch_add(1);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

#ifdef CWS_SOURCE_DIR
namespace {
// Steps of the paper's case with `integrator`: contact, friction, plasticity
// and a growing wire (the supply appends points during the counted steps).
// With `command_port` the port follows commanded samples queued ahead of
// the counted steps (a velocity kink every 20 us).
void expectStepsAllocateNothing(const std::string& integrator, int steps, bool command_port = false,
                                const char* scene = "default.yaml") {
  const std::string path = std::string(CWS_SOURCE_DIR) + "/config/scenes/" + scene;
  cws::Simulation sim(cws::loadScene(
      path, {"process.turns=0.2", "solver.integrator=" + integrator, "solver.atol=1e-8"}));
  // Under way: let the first steps settle the step size.
  for (int i = 0; i < 100; ++i) sim.step(sim.endTime());
  const int n0 = sim.model().constants().n;
  if (command_port) {
    const Eigen::Vector3d p0_world = sim.model().supply()->port(sim.time()).p_world;
    for (int k = 1; k <= 200; ++k) {
      // Away from the core (in the plane): more wire is drawn in.
      sim.apply(cws::Setpoint::portPosition(p0_world + Eigen::Vector3d(0.0, -1e-5 * k, 0.0),
                                            sim.time() + 2e-5 * k));
    }
  }
  // The counter counts: one allocation seen.
  allocations = 0;
  counting = true;
  delete new std::string(100, 'x');
  counting = false;
  ASSERT_GE(allocations.load(), 1);
  allocations = 0;
  counting = true;
  for (int i = 0; i < steps && sim.time() < sim.endTime(); ++i) sim.step(sim.endTime());
  counting = false;
  std::printf("allocation: %s, %ld allocations in %d steps, %d -> %d points\n", integrator.c_str(),
              allocations.load(), steps, n0, sim.model().constants().n);
  EXPECT_EQ(allocations.load(), 0);
  EXPECT_GT(sim.model().constants().n, n0) << "the wire should have grown while counted";
}
}  // namespace

TEST(Allocation, StepsAllocateNothing) { expectStepsAllocateNothing("symplectic_euler", 20000); }

// Steps that end at commanded port samples and drop the passed ones.
TEST(Allocation, CommandedPortStepsAllocateNothing) {
  expectStepsAllocateNothing("symplectic_euler", 20000, true);
}
#endif

#ifdef CWS_SOURCE_DIR
// Newton steps, flag rounds, retried steps and the supply's new points.
TEST(Allocation, NewtonStepsAllocateNothing) {
  expectStepsAllocateNothing("implicit_euler", 300);
  expectStepsAllocateNothing("bdf2", 300);
  // The 3-D formulation (the spiral, with torsion).
  expectStepsAllocateNothing("bdf2", 300, false, "paper_case_3d.yaml");
}
#endif

#ifdef CWS_SOURCE_DIR
// Contact against the wound wire: a two-layer coil (flanges, wire on wire)
// past its first turn, counted while the core takes on wire (each new
// carried segment hashed into the broad phase) and the free wire lands on
// the turn before.
TEST(Allocation, WireContactStepsAllocateNothing) {
  cws::Simulation sim(cws::loadScene(std::string(CWS_SOURCE_DIR) + "/config/scenes/two_layers.yaml",
                                     {"process.turns=4"}));
  while (sim.time() < 0.06) sim.step(sim.endTime());  // 1.2 turns at 1200 rpm
  const int carried0 = sim.model().carriedPoints();
  allocations = 0;
  counting = true;
  for (int i = 0; i < 1500; ++i) sim.step(sim.endTime());
  counting = false;
  std::printf("allocation: two layers, %ld allocations in 1500 steps, carried %d -> %d\n",
              allocations.load(), carried0, sim.model().carriedPoints());
  EXPECT_EQ(allocations.load(), 0);
  EXPECT_GT(sim.model().carriedPoints(), carried0 + 50) << "the core should take on wire";
}

// Steps through which buried wire retires from the live arrays (a live
// storage of 1,300 points on a five-layer coil, RetiredWire.*): the
// retired wire's records were reserved for the job, the rest moves in place.
TEST(Allocation, RetiringStepsAllocateNothing) {
  cws::Simulation sim(
      cws::loadScene(std::string(CWS_SOURCE_DIR) + "/config/scenes/two_layers.yaml",
                     {"process.winding_width=6e-3", "process.layers=5", "process.turns=27",
                      "core.flange_height=8e-3", "supply.max_points=1300"}));
  while (sim.model().constants().n < 1200) sim.step(sim.endTime());
  ASSERT_EQ(sim.model().retiredPoints(), 0);
  allocations = 0;
  counting = true;
  while (sim.model().retiredPoints() == 0 && sim.time() < sim.endTime()) sim.step(sim.endTime());
  for (int i = 0; i < 500; ++i) sim.step(sim.endTime());
  counting = false;
  std::printf("allocation: retiring, %ld allocations, %d points retired\n", allocations.load(),
              sim.model().retiredPoints());
  EXPECT_GT(sim.model().retiredPoints(), 0);
  EXPECT_EQ(allocations.load(), 0);
}

// The same after a restore from a snapshot taken once wire had retired:
// the restored store is reserved as the job's was, so the next retirement
// allocates nothing either.
TEST(Allocation, RetiringStepsAfterARestoreAllocateNothing) {
  cws::Simulation sim(
      cws::loadScene(std::string(CWS_SOURCE_DIR) + "/config/scenes/two_layers.yaml",
                     {"process.winding_width=6e-3", "process.layers=5", "process.turns=27",
                      "core.flange_height=8e-3", "supply.max_points=1300"}));
  while (sim.model().retiredPoints() == 0 && sim.time() < sim.endTime()) sim.step(sim.endTime());
  ASSERT_GT(sim.model().retiredPoints(), 0);
  const std::unique_ptr<cws::Simulation> restored = cws::Simulation::fromState(sim.saveState());
  const int retired0 = restored->model().retiredPoints();
  for (int i = 0; i < 100; ++i) restored->step(restored->endTime());  // under way again
  allocations = 0;
  counting = true;
  while (restored->model().retiredPoints() == retired0 && restored->time() < restored->endTime())
    restored->step(restored->endTime());
  for (int i = 0; i < 100; ++i) restored->step(restored->endTime());
  counting = false;
  std::printf("allocation: retiring after a restore, %ld allocations, %d -> %d points retired\n",
              allocations.load(), retired0, restored->model().retiredPoints());
  EXPECT_GT(restored->model().retiredPoints(), retired0);
  EXPECT_EQ(allocations.load(), 0);
}

// Contact between free segments in a Newton step (the couplings outside
// the band, solved through the Woodbury identity): implicit_euler on the
// stability matrix's two-layer coil, whose third turn lands on the second
// while that is still free: the core takes on no wire (a stick speed of
// 1e-9 m/s, which no point at rest on the turning core keeps to).
TEST(Allocation, FreeWireContactStepsAllocateNothing) {
  cws::Simulation sim(cws::loadScene(
      std::string(CWS_SOURCE_DIR) + "/config/scenes/default.yaml",
      {"wire.segment_length=1e-3", "process.core_speed_rpm=1200", "physics.planar=false",
       "physics.torsion=true", "process.traverse_pitch=1e-3", "process.winding_width=5e-3",
       "process.layers=2", "physics.flanges=true", "physics.wire_contact=true", "process.turns=8",
       "solver.integrator=implicit_euler", "contact.stick_speed=1e-9"}));
  // Up to the first free pair that touches.
  const cws::FreeWireContact* free = sim.model().freeWireContact();
  ASSERT_NE(free, nullptr);
  while (free->touching() == 0 && sim.time() < sim.endTime()) sim.step(sim.endTime());
  ASSERT_GT(free->touching(), 0) << "no free pair touched";
  int touching_steps = 0;
  allocations = 0;
  counting = true;
  for (int i = 0; i < 300; ++i) {
    sim.step(sim.endTime());
    touching_steps += free->touching() > 0;
  }
  counting = false;
  std::printf("allocation: free pairs touching in %d of 300 steps, %ld allocations\n",
              touching_steps, allocations.load());
  EXPECT_EQ(allocations.load(), 0);
  EXPECT_GT(touching_steps, 0);
}
#endif

// Many touching free pairs (88, as wire released onto free wire gives):
// once the storage has grown to them, a factorization and a solve allocate
// nothing.
TEST(Allocation, ManyPairCouplingsAllocateNothing) {
  using A = cws::SpatialAssembly;
  // (Points 0..kPoints-1: the last pair's point, 61 + 2 * 87 = 235, is one
  // of them.)
  constexpr int kPoints = 240;
  A a;
  a.resize(kPoints);
  a.begin(0, kPoints, true, true, 1e4);
  for (int x = 0; x < 88; ++x) {
    const int pa = 61 + x * 2;
    ASSERT_LT(pa, kPoints);
    a.addPairCoupling(pa, pa - 60, 0.3, Eigen::Matrix3d::Identity() * 2e6);
  }
  const int unknowns = a.unknowns(), blocks = (unknowns + A::kPerPoint - 1) / A::kPerPoint;
  for (int bi = 0; bi < blocks; ++bi) {
    a.matrix().blockAt(bi, bi).diagonal().setConstant(2e7);
    if (bi > 0) a.matrix().blockAt(bi, bi - 1)(0, 0) = 1e6;
  }
  ASSERT_TRUE(a.matrix().factor());
  cws::PairCouplingSolve pairs;
  pairs.resize(unknowns);
  ASSERT_TRUE(pairs.factor(a));  // (grows its storage to 88 pairs)
  Eigen::VectorXd x = Eigen::VectorXd::Ones(unknowns);
  allocations = 0;
  counting = true;
  const bool factored = pairs.factor(a);
  a.matrix().solve(x);
  pairs.correct(a, x);
  counting = false;
  ASSERT_TRUE(factored);
  EXPECT_EQ(pairs.pairs(), 88);
  EXPECT_EQ(allocations.load(), 0);
  EXPECT_TRUE(x.allFinite());
}
