// The slowest stretch of a run (pace_profile.hpp): stretches of
// PaceProfile::kStretch of simulated time, the slowest kept with the work
// done in it, and a short last stretch counted only where it is long enough
// or all there is. The counts are made up, so every figure is known.
#include <gtest/gtest.h>

#include "coil_winding_sim/core/run/pace_profile.hpp"

namespace {

using cws::PaceProfile;
using cws::WorkCount;

// The count at simulated time t [s] after wall time wall [s], with `steps`
// steps so far, each of 2 iterations and 1 factorization, one in ten
// retried.
WorkCount at(double t, double wall, long steps) {
  WorkCount c;
  c.t_s = t;
  c.wall_s = wall;
  c.steps = steps;
  c.rejected = steps / 10;
  c.iterations = 2 * steps;
  c.factorizations = steps;
  return c;
}

TEST(PaceProfile, KeepsTheStretchThatRanSlowest) {
  const double s = PaceProfile::kStretch;
  PaceProfile p;
  p.start(at(0.0, 0.0, 0));
  // First stretch at 2 x real time, the second at 0.25 x (in 40 steps),
  // the third at 1 x.
  p.record(at(0.5 * s, 0.25 * s, 10));
  p.record(at(s, 0.5 * s, 20));
  p.record(at(2.0 * s, 4.5 * s, 60));
  p.record(at(3.0 * s, 5.5 * s, 70));
  p.finish(at(3.0 * s, 5.5 * s, 70));
  const cws::PaceStretch& slow = p.slowest();
  ASSERT_TRUE(slow.valid);
  EXPECT_DOUBLE_EQ(slow.start_s, s);
  EXPECT_DOUBLE_EQ(slow.end_s, 2.0 * s);
  EXPECT_DOUBLE_EQ(slow.realTimeFactor(), 0.25);
  EXPECT_EQ(slow.steps, 40);
  EXPECT_EQ(slow.rejected, 4);
  EXPECT_EQ(slow.iterations, 80);
  EXPECT_EQ(slow.factorizations, 40);
}

TEST(PaceProfile, AShortLastStretchCountsOnlyWhenLongEnoughOrAlone) {
  const double s = PaceProfile::kStretch;
  // A last stretch of a tenth of kStretch, however slow, is noise: left out.
  PaceProfile p;
  p.start(at(0.0, 0.0, 0));
  p.record(at(s, s, 10));
  p.finish(at(1.1 * s, 2.0 * s, 11));
  EXPECT_DOUBLE_EQ(p.slowest().realTimeFactor(), 1.0);
  // One of half of it counts.
  PaceProfile q;
  q.start(at(0.0, 0.0, 0));
  q.record(at(s, s, 10));
  q.finish(at(1.5 * s, 2.0 * s, 15));
  EXPECT_DOUBLE_EQ(q.slowest().start_s, s);
  EXPECT_DOUBLE_EQ(q.slowest().realTimeFactor(), 0.5);
  // A run shorter than a stretch is its own slowest stretch.
  PaceProfile r;
  r.start(at(0.0, 0.0, 0));
  r.record(at(0.05 * s, 0.1 * s, 3));
  EXPECT_FALSE(r.slowest().valid);
  r.finish(at(0.05 * s, 0.1 * s, 3));
  ASSERT_TRUE(r.slowest().valid);
  EXPECT_DOUBLE_EQ(r.slowest().realTimeFactor(), 0.5);
  EXPECT_EQ(r.slowest().steps, 3);
}

}  // namespace
