// newtonSolve's flag rounds on a problem small enough to solve by hand: one
// unknown x [m] and one flag that picks the law, as a contact or a
// hysteresis line does. Flag 0 holds for x <= 0.5, flag 1 beyond:
//   flag 0: r(x) = x^3 + x - 3,     root 1.2134... (beyond 0.5: the flag changes)
//   flag 1: r(x) = x^3 + 2 x - 1.5, root 0.6265... (within its range)
// so a solve from x = 0 converges on flag 0, finds flag 1 and solves again.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "coil_winding_sim/core/implicit/newton_iteration.hpp"

namespace {

struct TwoLawProblem {
  bool costly = false;  // a factorization that costs many solves
  int flag = 0;
  double x = 0.0, x_kept = 0.0, dx = 0.0;
  double r = 0.0, slope = 0.0, factored_slope = 0.0;
  int rechecks = 0;

  double residual(bool jacobian, int /*top*/ = -1) {
    r = flag == 0 ? x * x * x + x - 3.0 : x * x * x + 2.0 * x - 1.5;
    if (jacobian) slope = 3.0 * x * x + (flag == 0 ? 1.0 : 2.0);
    return std::abs(r);
  }
  bool factor() {
    factored_slope = slope;
    return slope != 0.0;
  }
  int changedTop() const { return -1; }
  double direction() {
    dx = -r / factored_slope;
    return std::abs(dx);
  }
  void keepStart() { x_kept = x; }
  void returnMapping(bool) {}
  bool costlyFactor() const { return costly; }
  void moveAlong(double s) { x = x_kept + s * dx; }
  void forgetSteps() {}
  bool keepStep() { return true; }
  bool recheckFlags() {
    ++rechecks;
    const int holds = x > 0.5 ? 1 : 0;
    if (holds == flag) return false;
    flag = holds;
    return true;
  }
};

// The root of flag 1's law, by bisection (independent of Newton).
double rootOfFlagOne() {
  double lo = 0.5, hi = 1.0;
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    (mid * mid * mid + 2.0 * mid - 1.5 > 0.0 ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

cws::NewtonStats solveFromZero(double flag_check_tol, TwoLawProblem& p) {
  cws::NewtonSettings s;
  s.tol = 1e-12;
  s.flag_check_tol = flag_check_tol;
  bool have_factor = false;
  return cws::newtonSolve(p, s, have_factor);
}

// Rechecking the flags before full convergence ends at the same root, on
// the same flag, with fewer iterations: the first solve stops at the
// looser bound, since its flag no longer holds there.
TEST(NewtonIteration, FlagsRecheckedEarlyGiveTheSameSolution) {
  TwoLawProblem late, early;
  const cws::NewtonStats st_late = solveFromZero(0.0, late);
  const cws::NewtonStats st_early = solveFromZero(1e-3, early);
  ASSERT_TRUE(st_late.converged);
  ASSERT_TRUE(st_early.converged);
  const double root = rootOfFlagOne();
  EXPECT_EQ(late.flag, 1);
  EXPECT_EQ(early.flag, 1);
  EXPECT_NEAR(late.x, root, 1e-11);
  EXPECT_NEAR(early.x, root, 1e-11);
  EXPECT_EQ(st_late.flag_rounds, 1);
  EXPECT_EQ(st_early.flag_rounds, 1);
  EXPECT_LT(st_early.iterations, st_late.iterations);
}

// A flag that holds at the early check is checked again at convergence,
// and no solve is repeated.
TEST(NewtonIteration, AnEarlyCheckThatHoldsIsRepeatedAtConvergence) {
  TwoLawProblem p;
  p.flag = 1;
  p.x = 0.7;  // flag 1 holds all the way to its root
  const cws::NewtonStats st = solveFromZero(1e-3, p);
  ASSERT_TRUE(st.converged);
  EXPECT_EQ(st.flag_rounds, 0);
  EXPECT_EQ(p.rechecks, 2);  // once early, once converged
  EXPECT_NEAR(p.x, rootOfFlagOne(), 1e-11);
}

// A factorization that costs many solves (SpatialFormulation: many pairs of
// free segments) serves on into the next flag round and while its steps
// shrink by a fifth: the same root on the same flag, from fewer
// factorizations (the flag-0 slope, 5.4 at its root, against flag 1's 3.2,
// contracts the steps by 0.41 each).
TEST(NewtonIteration, ACostlyFactorizationServesIntoTheNextRound) {
  TwoLawProblem plain, costly;
  costly.costly = true;
  cws::NewtonSettings s;
  s.tol = 1e-12;
  s.max_iterations = 100;
  bool have_plain = false, have_costly = false;
  const cws::NewtonStats st_plain = cws::newtonSolve(plain, s, have_plain);
  const cws::NewtonStats st_costly = cws::newtonSolve(costly, s, have_costly);
  ASSERT_TRUE(st_plain.converged);
  ASSERT_TRUE(st_costly.converged);
  EXPECT_EQ(plain.flag, 1);
  EXPECT_EQ(costly.flag, 1);
  EXPECT_NEAR(plain.x, rootOfFlagOne(), 1e-11);
  EXPECT_NEAR(costly.x, rootOfFlagOne(), 1e-11);
  EXPECT_EQ(st_costly.flag_rounds, 1);
  EXPECT_LT(st_costly.factorizations, st_plain.factorizations);
  EXPECT_GT(st_costly.iterations, st_plain.iterations);
  std::printf("factorizations %d -> %d, iterations %d -> %d\n", st_plain.factorizations,
              st_costly.factorizations, st_plain.iterations, st_costly.iterations);
}

// A law with three kinks, continuous and softening (slopes 8, 4, 2, 1 of g
// between the kinks at 0.5, 1 and 1.5), as a two-line law's yield is:
//   r(x) = x + g(x) - 9.5,  root x = 2 on the last line.
// Each frozen line's extension stops short, on the next line but one, so
// frozen rounds walk 0 -> 2 -> 3 and need two rounds after the first
// solve; a return-mapped round takes the line x lies on at every
// evaluation and needs none after it.
struct KinkedLawProblem {
  int line = 0;
  bool mapped = false;
  double x = 0.0, x_kept = 0.0, dx = 0.0;
  double r = 0.0, slope = 0.0, factored_slope = 0.0;

  static int lineOf(double x) { return x <= 0.5 ? 0 : x <= 1.0 ? 1 : x <= 1.5 ? 2 : 3; }
  double residual(bool jacobian, int /*top*/ = -1) {
    static const double start[4] = {0.0, 0.5, 1.0, 1.5}, g0[4] = {0.0, 4.0, 6.0, 7.0},
                        k[4] = {8.0, 4.0, 2.0, 1.0};
    const int l = mapped ? lineOf(x) : line;
    r = x + g0[l] + k[l] * (x - start[l]) - 9.5;
    if (jacobian) slope = 1.0 + k[l];
    return std::abs(r);
  }
  bool factor() {
    factored_slope = slope;
    return true;
  }
  int changedTop() const { return -1; }
  double direction() {
    dx = -r / factored_slope;
    return std::abs(dx);
  }
  void keepStart() { x_kept = x; }
  void moveAlong(double s) { x = x_kept + s * dx; }
  void forgetSteps() {}
  bool keepStep() { return true; }
  void returnMapping(bool on) { mapped = on; }
  bool costlyFactor() const { return false; }
  bool recheckFlags() {
    const int holds = lineOf(x);
    if (mapped || holds == line) {
      line = holds;
      return false;
    }
    line = holds;
    return true;
  }
};

cws::NewtonStats solveKinked(int flag_rounds, int return_mapping_round, KinkedLawProblem& p) {
  cws::NewtonSettings s;
  s.tol = 1e-12;
  s.flag_rounds = flag_rounds;
  s.return_mapping_round = return_mapping_round;
  bool have_factor = false;
  return cws::newtonSolve(p, s, have_factor);
}

// Frozen lines need two rounds; with one allowed, the solve fails (and its
// step would be retried smaller).
TEST(NewtonIteration, FrozenLinesNeedARoundPerLineTheyMissed) {
  KinkedLawProblem enough, short_of_rounds;
  const cws::NewtonStats st = solveKinked(2, 1000, enough);
  ASSERT_TRUE(st.converged);
  EXPECT_EQ(st.flag_rounds, 2);
  EXPECT_NEAR(enough.x, 2.0, 1e-12);
  EXPECT_EQ(enough.line, 3);
  EXPECT_FALSE(solveKinked(1, 1000, short_of_rounds).converged);
}

// From the return-mapping round on, the solve crosses the remaining kinks
// itself: one round suffices, at the same root, and the recheck records
// the line the root lies on.
TEST(NewtonIteration, ReturnMappedRoundsCrossTheKinksWithinOneSolve) {
  KinkedLawProblem p;
  const cws::NewtonStats st = solveKinked(1, 1, p);
  ASSERT_TRUE(st.converged);
  EXPECT_EQ(st.flag_rounds, 1);
  EXPECT_NEAR(p.x, 2.0, 1e-12);
  EXPECT_EQ(p.line, 3);
  // Return-mapped from the first solve: no round at all.
  KinkedLawProblem q;
  const cws::NewtonStats st0 = solveKinked(0, 0, q);
  ASSERT_TRUE(st0.converged);
  EXPECT_EQ(st0.flag_rounds, 0);
  EXPECT_NEAR(q.x, 2.0, 1e-12);
}

}  // namespace
