// The integration step allocates nothing once a run is under way: global
// operator new is counted while a flag is set (this test binary only).
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <string>

#include "coil_winding_sim/core/simulation.hpp"

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
TEST(Allocation, StepsAllocateNothing) {
  // The paper's case: contact, friction, plasticity and a growing wire (the
  // supply appends points during the counted steps).
  const std::string path = std::string(CWS_SOURCE_DIR) + "/config/scenes/default.yaml";
  cws::Simulation sim(cws::loadScene(path, {"process.turns=0.2"}));
  // Under way: let the first steps settle the step size.
  for (int i = 0; i < 100; ++i) sim.step(sim.endTime());
  const int n0 = sim.model().constants().n;
  // The counter counts: one allocation seen.
  allocations = 0;
  counting = true;
  delete new std::string(100, 'x');
  counting = false;
  ASSERT_GE(allocations.load(), 1);
  allocations = 0;
  counting = true;
  for (int i = 0; i < 20000 && sim.time() < sim.endTime(); ++i) sim.step(sim.endTime());
  counting = false;
  std::printf("allocation: %ld allocations in 20000 steps, %d -> %d points\n", allocations.load(),
              n0, sim.model().constants().n);
  EXPECT_EQ(allocations.load(), 0);
  EXPECT_GT(sim.model().constants().n, n0) << "the wire should have grown while counted";
}
#endif
