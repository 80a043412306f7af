// Unit tests of cws::TwoLineLaw, the paper's two-line hysteresis (eqs. 7-15).
//
// Evidence used, none of it the law's own earlier output:
//  * an independent reference: classical 1-D rate-independent plasticity with
//    linear kinematic hardening, integrated by return mapping
//    (s = k_e (x - x_p), backstress beta = H x_p, H = k_e k_p / (k_e - k_p),
//    yield |s - beta| <= k_e a);
//  * closed-form landmarks of the bilinear law (first yield, slopes, yield
//    points moving together 2a apart, plastic strain, loop area);
//  * numerical quadrature of stress() for work();
//  * the energy identity W = s^2/(2 k_e) + H x_p^2 / 2 + k_e a sum|dx_p|.
//
// Parameters are Table 1 of the paper (typed here, not taken from the scene
// defaults) with the yields of shared/reference/wire-data.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <string>
#include <vector>

#include "coil_winding_sim/core/base/hysteresis.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace {

using cws::HysteresisParams;
using cws::TwoLineLaw;

struct LawCase {
  const char* name;
  HysteresisParams p;
};

// gtest prints a parameter with this (instead of its bytes).
void PrintTo(const LawCase& c, std::ostream* os) { *os << c.name; }

// Table 1 (elastic / plastic rigidity) and the yields of wire-data.md.
const LawCase kStretch{"stretch", {4.89e4, 1.10e3, 8.0e-4}};  // EA [N], strain
const LawCase kBend{"bend", {3.06e-3, 1.13e-4, 1.6}};         // EI [N m^2], 1/m
const LawCase kTorsion{"torsion", {4.32e-3, 9.0e-5, 1.31}};   // GJ [N m^2], rad/m

// ---------------------------------------------------------------------------
// Independent reference: return mapping for 1-D plasticity with linear
// kinematic hardening. The state is the plastic strain x_p; the backstress is
// beta = H x_p. Exact for any strain increment in 1-D (the trial state and
// the projection are linear).
class KinematicHardeningReference {
 public:
  KinematicHardeningReference(double k_e, double k_p, double a)
      : k_e_(k_e), H_(k_e * k_p / (k_e - k_p)), radius_(k_e * a), a_(a) {}

  // Moves the material to total strain x (and commits); returns the stress.
  double advance(double x) {
    const double s_trial = k_e_ * (x - x_p_);
    const double xi = s_trial - H_ * x_p_;  // relative stress s - beta
    const double f = std::abs(xi) - radius_;
    if (f > 0.0) {
      const double dgamma = f / (k_e_ + H_);
      x_p_ += (xi > 0.0 ? 1.0 : -1.0) * dgamma;
      dissipated_ += radius_ * dgamma;
      last_was_plastic_ = true;
      last_sign_ = xi > 0.0 ? 1 : -1;
    } else {
      last_was_plastic_ = false;
      last_sign_ = 0;
    }
    s_ = k_e_ * (x - x_p_);
    return s_;
  }

  double stress() const { return s_; }
  double plasticStrain() const { return x_p_; }
  double backstress() const { return H_ * x_p_; }
  // Upper yield point in strain: where the current elastic line reaches
  // s - beta = +k_e a.
  double upperYieldStrain() const { return x_p_ + (H_ * x_p_ + radius_) / k_e_; }
  double lowerYieldStrain() const { return x_p_ + (H_ * x_p_ - radius_) / k_e_; }
  // Work done on the material, by the energy identity (no path integral).
  double workByEnergyIdentity() const {
    return 0.5 * s_ * s_ / k_e_ + 0.5 * H_ * x_p_ * x_p_ + dissipated_;
  }
  double dissipated() const { return dissipated_; }
  bool lastWasPlastic() const { return last_was_plastic_; }
  int lastSign() const { return last_sign_; }
  double a() const { return a_; }

 private:
  double k_e_, H_, radius_, a_;
  double x_p_ = 0.0;
  double s_ = 0.0;
  double dissipated_ = 0.0;
  bool last_was_plastic_ = false;
  int last_sign_ = 0;
};

// Strain path through the waypoints (in units of the yield a), `per_leg`
// equally spaced points per leg, the start point excluded.
std::vector<double> strainPath(const std::vector<double>& waypoints_in_a, double a, int per_leg) {
  std::vector<double> x;
  for (std::size_t leg = 0; leg + 1 < waypoints_in_a.size(); ++leg) {
    const double x0 = waypoints_in_a[leg] * a;
    const double x1 = waypoints_in_a[leg + 1] * a;
    for (int i = 1; i <= per_leg; ++i) x.push_back(x0 + (x1 - x0) * i / per_leg);
  }
  return x;
}

// Load past yield (4.3a), unload and reverse past the reverse yield (which is
// at 4.3a - 2a = 2.3a) to -3.7a, reload past the new yield (-3.7a + 2a =
// -1.7a) to 5.1a, then an inner elastic unload to 3.6a and a reload past the
// yield point left at 5.1a to 6.2a. 80 points per leg: 400 points, the yield
// points falling between samples.
const std::vector<double> kWaypoints{0.0, 4.3, -3.7, 5.1, 3.6, 6.2};
constexpr int kPerLeg = 80;

// The law driven like the simulation drives it: trial stress(x, x_u) at a
// point, then x_u = movedUpper(x, x_u) as the commit of an accepted step.
struct Driven {
  explicit Driven(const TwoLineLaw& l) : law(l), x_u(l.initialUpper()) {}
  double go(double x) {
    const double s = law.stress(x, x_u);
    w += law.work(x_prev, x, x_u);
    x_u = law.movedUpper(x, x_u);
    x_prev = x;
    return s;
  }
  TwoLineLaw law;
  double x_u;
  double x_prev = 0.0;
  double w = 0.0;  // accumulated work by the law's work()
};

// Compares the law and the reference point by point along the path.
// Returns the counts of (elastic, upper plastic, lower plastic) points so that
// callers can check the path really crossed every branch.
struct BranchCounts {
  int elastic = 0, upper = 0, lower = 0;
};

BranchCounts comparePath(const HysteresisParams& p, const std::vector<double>& path) {
  const TwoLineLaw law(p);
  KinematicHardeningReference ref(p.elastic_rigidity, p.plastic_rigidity, p.yield);
  Driven d(law);
  BranchCounts counts;
  const double k_e = p.elastic_rigidity;
  const double a = p.yield;
  for (std::size_t i = 0; i < path.size(); ++i) {
    const double x = path[i];
    const double s_law = d.go(x);
    const double s_ref = ref.advance(x);
    const double scale = k_e * std::max(std::abs(x), a);  // stress scale [N] or [N m]
    SCOPED_TRACE("point " + std::to_string(i) + ", x = " + std::to_string(x / a) + " a");
    EXPECT_NEAR(s_law, s_ref, 1e-12 * scale);
    EXPECT_NEAR(d.x_u, ref.upperYieldStrain(), 1e-12 * std::max(std::abs(x), a));
    EXPECT_NEAR(law.plasticStrain(d.x_u), ref.plasticStrain(), 1e-12 * std::max(std::abs(x), a));
    // The yield points stay 2a apart (Fig. 5).
    EXPECT_NEAR(ref.upperYieldStrain() - ref.lowerYieldStrain(), 2.0 * a, 1e-12 * a);
    // Work by the law's exact integral equals the reference's energy identity.
    EXPECT_NEAR(d.w, ref.workByEnergyIdentity(), 1e-11 * scale * std::max(std::abs(x), a));
    if (!ref.lastWasPlastic()) {
      ++counts.elastic;
    } else if (ref.lastSign() > 0) {
      ++counts.upper;
    } else {
      ++counts.lower;
    }
  }
  return counts;
}

// Numerical quadrature of stress(x, x_u) from x0 to x1 (either direction):
// composite trapezoid rule on n cells with Kahan summation. The integrand is
// piecewise linear, so the rule is exact except in the (at most two) cells
// that contain a kink; there the error is at most |slope jump| h^2 / 8.
double trapezoid(const TwoLineLaw& law, double x_u, double x0, double x1, int n) {
  const double h = (x1 - x0) / n;
  double sum = 0.0, comp = 0.0;
  double f_prev = law.stress(x0, x_u);
  for (int i = 1; i <= n; ++i) {
    const double x = (i == n) ? x1 : x0 + h * i;
    const double f = law.stress(x, x_u);
    const double term = 0.5 * (f_prev + f) * h - comp;
    const double t = sum + term;
    comp = (t - sum) - term;
    sum = t;
    f_prev = f;
  }
  return sum;
}

class TwoLineLawTable1 : public ::testing::TestWithParam<LawCase> {};

std::string lawName(const ::testing::TestParamInfo<LawCase>& info) { return info.param.name; }

// ---------------------------------------------------------------------------
// Against the return-mapping reference along load / unload / reverse / reload.
TEST_P(TwoLineLawTable1, MatchesReturnMappingAlongCyclicPath) {
  const HysteresisParams& p = GetParam().p;
  const std::vector<double> path = strainPath(kWaypoints, p.yield, kPerLeg);
  ASSERT_EQ(path.size(), 400u);
  const BranchCounts c = comparePath(p, path);
  // The path must have exercised all three branches of the law.
  EXPECT_GT(c.elastic, 50);
  EXPECT_GT(c.upper, 50);
  EXPECT_GT(c.lower, 50);
}

// Virgin material: elastic between -a and a, first yield at x = a with
// s = k_e a (and at -a with -k_e a), plastic slope k_p beyond.
TEST_P(TwoLineLawTable1, FirstYieldAtYieldStrainWithElasticStress) {
  const HysteresisParams& p = GetParam().p;
  const TwoLineLaw law(p);
  const double k_e = p.elastic_rigidity, k_p = p.plastic_rigidity, a = p.yield;
  EXPECT_DOUBLE_EQ(law.initialUpper(), a);
  EXPECT_DOUBLE_EQ(law.elasticRigidity(), k_e);
  const double x_u = law.initialUpper();
  EXPECT_NEAR(law.stress(a, x_u), k_e * a, 1e-12 * k_e * a);
  EXPECT_NEAR(law.stress(-a, x_u), -k_e * a, 1e-12 * k_e * a);
  for (double f : {-0.999, -0.5, 0.0, 0.25, 0.999}) {
    EXPECT_NEAR(law.stress(f * a, x_u), k_e * f * a, 1e-12 * k_e * a) << "x = " << f << " a";
  }
  // Beyond first yield: on the line through (a, k_e a) with slope k_p.
  for (double f : {1.001, 1.5, 3.0, 50.0}) {
    EXPECT_NEAR(law.stress(f * a, x_u), k_e * a + k_p * (f - 1.0) * a, 1e-12 * k_e * f * a)
        << "x = " << f << " a";
    EXPECT_NEAR(law.stress(-f * a, x_u), -k_e * a - k_p * (f - 1.0) * a, 1e-12 * k_e * f * a)
        << "x = -" << f << " a";
  }
  // Within the elastic range the yield point does not move.
  EXPECT_EQ(law.movedUpper(0.3 * a, x_u), x_u);
  EXPECT_EQ(law.movedUpper(-0.9 * a, x_u), x_u);
  // Virgin material has no plastic strain.
  EXPECT_NEAR(law.plasticStrain(x_u), 0.0, 1e-12 * a);
}

// Loading in steps past yield: the secant slope between committed points on
// the plastic branch is k_p, in tension and in compression.
TEST_P(TwoLineLawTable1, PlasticSlopeOnLoadingIsPlasticRigidity) {
  const HysteresisParams& p = GetParam().p;
  const double k_p = p.plastic_rigidity, a = p.yield;
  for (double sign : {1.0, -1.0}) {
    Driven d{TwoLineLaw(p)};
    double x_prev = 0.0, s_prev = 0.0;
    int plastic_pairs = 0;
    for (int i = 1; i <= 40; ++i) {
      const double x = sign * 4.0 * a * i / 40;
      const double s = d.go(x);
      if (std::abs(x_prev) >= a * (1.0 - 1e-12)) {  // both points on the plastic branch
        EXPECT_NEAR((s - s_prev) / (x - x_prev), k_p, 1e-9 * k_p) << "i = " << i;
        ++plastic_pairs;
      }
      x_prev = x;
      s_prev = s;
    }
    EXPECT_EQ(plastic_pairs, 30);
    // The committed upper yield point follows the strain in tension and stays
    // 2a above it in compression.
    EXPECT_NEAR(d.x_u, sign > 0 ? 4.0 * a : -4.0 * a + 2.0 * a, 1e-12 * a);
  }
}

// After loading to x_max: unloading follows slope k_e; the reverse yield is at
// x_max - 2a with stress s_max - 2 k_e a; beyond it the lower plastic line
// (slope k_p); continuing there drags the upper yield point along 2a above.
TEST_P(TwoLineLawTable1, UnloadingIsElasticAndReverseYieldIsTwoYieldsBelowMaximum) {
  const HysteresisParams& p = GetParam().p;
  const double k_e = p.elastic_rigidity, k_p = p.plastic_rigidity, a = p.yield;
  for (double x_max_in_a : {1.5, 4.0, 20.0}) {
    SCOPED_TRACE("x_max = " + std::to_string(x_max_in_a) + " a");
    const double x_max = x_max_in_a * a;
    Driven d{TwoLineLaw(p)};
    for (int i = 1; i <= 50; ++i) d.go(x_max * i / 50);
    const double s_max = k_e * a + k_p * (x_max - a);  // closed form on the upper line
    EXPECT_NEAR(d.law.stress(x_max, d.x_u), s_max, 1e-12 * k_e * x_max);
    const double x_rev = x_max - 2.0 * a;
    const double scale = k_e * x_max;
    // Unloading: slope k_e from (x_max, s_max) down to x_rev.
    for (double f : {0.0, 0.1, 0.5, 1.0, 1.7, 1.999, 2.0}) {
      const double x = x_max - f * a;
      EXPECT_NEAR(d.law.stress(x, d.x_u), s_max - k_e * f * a, 1e-12 * scale) << "f = " << f;
    }
    // Secant slopes inside the elastic range equal k_e.
    const double x1 = x_max - 0.3 * a, x2 = x_max - 1.6 * a;
    EXPECT_NEAR((d.law.stress(x1, d.x_u) - d.law.stress(x2, d.x_u)) / (x1 - x2), k_e, 1e-9 * k_e);
    // Reverse yield stress, and the lower plastic line beyond it.
    const double s_rev = s_max - 2.0 * k_e * a;
    EXPECT_NEAR(d.law.stress(x_rev, d.x_u), s_rev, 1e-12 * scale);
    for (double g : {1e-3, 0.5, 3.0}) {
      EXPECT_NEAR(d.law.stress(x_rev - g * a, d.x_u), s_rev - k_p * g * a, 1e-12 * scale)
          << "g = " << g;
    }
    // Just above the reverse yield the point is elastic (slope k_e), just
    // below it plastic (slope k_p): a kink exactly at x_max - 2a.
    const double eps = 1e-6 * a;
    EXPECT_NEAR((d.law.stress(x_rev + 2 * eps, d.x_u) - d.law.stress(x_rev + eps, d.x_u)) / eps,
                k_e, 1e-5 * k_e);
    EXPECT_NEAR((d.law.stress(x_rev - eps, d.x_u) - d.law.stress(x_rev - 2 * eps, d.x_u)) / eps,
                k_p, 1e-5 * k_e);
    // Committing a point below the reverse yield moves both yield points:
    // the lower one to that point, the upper one 2a above it.
    const double x_low = x_rev - 1.25 * a;
    for (int i = 1; i <= 50; ++i) d.go(x_max + (x_low - x_max) * i / 50);
    EXPECT_NEAR(d.x_u, x_low + 2.0 * a, 1e-12 * x_max);
    // Reloading is elastic up to the new upper yield point x_low + 2a.
    const double s_low = s_rev - k_p * 1.25 * a;
    EXPECT_NEAR(d.law.stress(x_low + 2.0 * a, d.x_u), s_low + 2.0 * k_e * a, 1e-12 * scale);
    EXPECT_NEAR(d.law.stress(x_low + 2.5 * a, d.x_u), s_low + 2.0 * k_e * a + k_p * 0.5 * a,
                1e-12 * scale);
  }
}

// Mirror symmetry: loading in compression first gives the negated response,
// with the reverse (tensile) yield at -x_max + 2a.
TEST_P(TwoLineLawTable1, CompressionFirstIsTheMirrorImage) {
  const HysteresisParams& p = GetParam().p;
  const double k_e = p.elastic_rigidity, a = p.yield;
  const std::vector<double> path = strainPath(kWaypoints, a, kPerLeg);
  Driven pos{TwoLineLaw(p)}, neg{TwoLineLaw(p)};
  for (double x : path) {
    const double sp = pos.go(x);
    const double sn = neg.go(-x);
    EXPECT_NEAR(sn, -sp, 1e-12 * k_e * std::max(std::abs(x), a)) << "x = " << x / a << " a";
    // Upper yield of the mirrored path = -(lower yield of the original).
    EXPECT_NEAR(neg.x_u, -(pos.x_u - 2.0 * a), 1e-12 * std::max(std::abs(x), a));
  }
}

// plasticStrain(x_u): the strain where the current elastic line crosses s = 0.
TEST_P(TwoLineLawTable1, PlasticStrainIsZeroStressPointOfElasticLine) {
  const HysteresisParams& p = GetParam().p;
  const double k_e = p.elastic_rigidity, k_p = p.plastic_rigidity, a = p.yield;
  for (double x_max_in_a : {1.0, 1.2, 2.0, 3.0}) {
    const double x_max = x_max_in_a * a;
    Driven d{TwoLineLaw(p)};
    for (int i = 1; i <= 20; ++i) d.go(x_max * i / 20);
    // Closed form: unload elastically from s_max = k_e a + k_p (x_max - a).
    const double s_max = k_e * a + k_p * (x_max - a);
    const double expected = x_max - s_max / k_e;
    const double xp = d.law.plasticStrain(d.x_u);
    EXPECT_NEAR(xp, expected, 1e-12 * x_max) << "x_max = " << x_max_in_a << " a";
    // With these x_max the zero crossing lies inside the elastic range, so the
    // law's own stress vanishes there.
    ASSERT_GE(xp, d.x_u - 2.0 * a);
    EXPECT_NEAR(d.law.stress(xp, d.x_u), 0.0, 1e-12 * k_e * x_max);
  }
  // Mirror: compression to -3a leaves the negated plastic strain.
  Driven d{TwoLineLaw(p)};
  for (int i = 1; i <= 20; ++i) d.go(-3.0 * a * i / 20);
  EXPECT_NEAR(d.law.plasticStrain(d.x_u), -(3.0 * a - (k_e * a + 2.0 * k_p * a) / k_e), 1e-12 * a);
}

// work(x0, x1, x_u) against numerical quadrature of stress(x, x_u), across
// neither, one and both yield points, in both directions.
TEST_P(TwoLineLawTable1, WorkEqualsQuadratureOfStress) {
  const HysteresisParams& p = GetParam().p;
  const double k_e = p.elastic_rigidity, k_p = p.plastic_rigidity, a = p.yield;
  const TwoLineLaw law(p);
  const int n = 200000;
  struct Interval {
    double x0, x1;  // in units of a
  };
  const std::vector<Interval> intervals{
      {-4.0, 5.0}, {5.0, -4.0},   // across both yield points
      {-0.9, 6.3}, {6.3, -0.9},   // across the upper one only (lower at 0.7)
      {0.2, 2.5},  {2.5, 0.2},    // across the lower one only
      {1.1, 2.6},  {2.6, 1.1},    // inside the elastic range
      {3.0, 7.5},  {-6.0, -1.0},  // on the upper / lower plastic line only
      {0.7, 2.7},  {2.7, 0.7},    // exactly from yield point to yield point
      {1.3, 1.3}};                // empty
  for (double x_u_in_a : {1.0, 2.7, -0.4}) {
    const double x_u = x_u_in_a * a;
    for (const Interval& iv : intervals) {
      // Shift the intervals with the yield points so each keeps its meaning.
      const double shift = x_u - 2.7 * a;
      const double x0 = iv.x0 * a + shift, x1 = iv.x1 * a + shift;
      const double w = law.work(x0, x1, x_u);
      const double q = trapezoid(law, x_u, x0, x1, n);
      const double h = std::abs(x1 - x0) / n;
      const double tol =
          2.0 * (k_e - k_p) * h * h / 8.0 +
          1e-12 * k_e * std::max({std::abs(x0), std::abs(x1), a}) * std::max(std::abs(x1 - x0), a);
      EXPECT_NEAR(w, q, tol) << "x_u = " << x_u_in_a << " a, [" << iv.x0 << ", " << iv.x1
                             << "] a (shifted)";
      // Reversing the direction negates the work.
      EXPECT_NEAR(law.work(x1, x0, x_u), -w, 1e-13 * std::abs(w) + 1e-300);
    }
  }
  // One closed-form value: the virgin elastic energy up to first yield.
  EXPECT_NEAR(law.work(0.0, a, a), 0.5 * k_e * a * a, 1e-12 * k_e * a * a);
  EXPECT_NEAR(law.elasticEnergy(k_e * a), 0.5 * k_e * a * a, 1e-12 * k_e * a * a);
}

// A closed strain cycle -X..X after first loading to X encloses the
// parallelogram between the two plastic lines (vertical gap 2C) and two
// elastic lines (horizontal width 2a): area 4 C (X - a), C = a (k_e - k_p).
TEST_P(TwoLineLawTable1, ClosedCycleDissipatesParallelogramArea) {
  const HysteresisParams& p = GetParam().p;
  const double k_e = p.elastic_rigidity, k_p = p.plastic_rigidity, a = p.yield;
  const double C = a * (k_e - k_p);
  for (double X_in_a : {1.5, 3.0, 10.0}) {
    const double X = X_in_a * a;
    Driven d{TwoLineLaw(p)};
    for (int i = 1; i <= 37; ++i) d.go(X * i / 37);
    const double w_start = d.w;
    const double s_start = d.law.stress(X, d.x_u);
    for (int i = 1; i <= 101; ++i) d.go(X - 2.0 * X * i / 101);   // to -X
    for (int i = 1; i <= 103; ++i) d.go(-X + 2.0 * X * i / 103);  // back to X
    EXPECT_NEAR(d.law.stress(X, d.x_u), s_start, 1e-12 * k_e * X);
    EXPECT_NEAR(d.w - w_start, 4.0 * C * (X - a), 1e-11 * k_e * X * X) << "X = " << X_in_a << " a";
  }
}

INSTANTIATE_TEST_SUITE_P(Table1, TwoLineLawTable1, ::testing::Values(kStretch, kBend, kTorsion),
                         lawName);

// ---------------------------------------------------------------------------
// Perfectly plastic limit k_p = 0: flat plastic lines at +-k_e a.
class TwoLineLawPerfectlyPlastic : public ::testing::TestWithParam<LawCase> {};

TEST_P(TwoLineLawPerfectlyPlastic, FlatYieldPlateausAndReturnMapping) {
  HysteresisParams p = GetParam().p;
  p.plastic_rigidity = 0.0;
  const double k_e = p.elastic_rigidity, a = p.yield;
  const TwoLineLaw law(p);
  // Against the reference (H = 0).
  const BranchCounts c = comparePath(p, strainPath(kWaypoints, a, kPerLeg));
  EXPECT_GT(c.elastic, 50);
  EXPECT_GT(c.upper, 50);
  EXPECT_GT(c.lower, 50);
  // Closed forms: plateau at k_e a, reverse yield at x_max - 2a with -k_e a,
  // plastic strain x_max - a.
  Driven d(law);
  for (int i = 1; i <= 40; ++i) {
    const double x = 5.0 * a * i / 40;
    const double s = d.go(x);
    EXPECT_NEAR(s, x <= a ? k_e * x : k_e * a, 1e-12 * k_e * 5.0 * a) << "x = " << x / a << " a";
  }
  EXPECT_NEAR(law.plasticStrain(d.x_u), 4.0 * a, 1e-12 * 5.0 * a);
  EXPECT_NEAR(law.stress(3.0 * a, d.x_u), -k_e * a, 1e-12 * k_e * 5.0 * a);
  EXPECT_NEAR(law.stress(1.0 * a, d.x_u), -k_e * a, 1e-12 * k_e * 5.0 * a);
  EXPECT_NEAR(law.stress(4.0 * a, d.x_u), 0.0, 1e-12 * k_e * 5.0 * a);
  // Work over a closed cycle -X..X: the rectangle 2 k_e a * 2 (X - a)... i.e.
  // 4 C (X - a) with C = k_e a.
  const double X = 5.0 * a;
  const double w0 = d.w;
  for (int i = 1; i <= 60; ++i) d.go(X - 2.0 * X * i / 60);
  for (int i = 1; i <= 60; ++i) d.go(-X + 2.0 * X * i / 60);
  EXPECT_NEAR(d.w - w0, 4.0 * k_e * a * (X - a), 1e-11 * k_e * X * X);
}

// The limit k_p = k_e: one straight line s = k_e x, no hysteresis, no
// permanent strain, no work over a closed cycle.
TEST_P(TwoLineLawPerfectlyPlastic, EqualRigiditiesGiveNoHysteresis) {
  HysteresisParams p = GetParam().p;
  p.plastic_rigidity = p.elastic_rigidity;
  const double k_e = p.elastic_rigidity, a = p.yield;
  const TwoLineLaw law(p);
  Driven d(law);
  const std::vector<double> path = strainPath(kWaypoints, a, kPerLeg);
  for (double x : path) {
    const double s = d.go(x);
    EXPECT_NEAR(s, k_e * x, 1e-12 * k_e * std::max(std::abs(x), a)) << "x = " << x / a << " a";
    EXPECT_NEAR(law.plasticStrain(d.x_u), 0.0, 1e-12 * std::max(std::abs(x), a));
  }
  // Total work equals the elastic energy at the end point.
  const double x_end = path.back();
  EXPECT_NEAR(d.w, 0.5 * k_e * x_end * x_end, 1e-11 * k_e * x_end * x_end);
  EXPECT_NEAR(d.w, law.elasticEnergy(k_e * x_end), 1e-11 * k_e * x_end * x_end);
}

INSTANTIATE_TEST_SUITE_P(Table1, TwoLineLawPerfectlyPlastic,
                         ::testing::Values(kStretch, kBend, kTorsion), lawName);

}  // namespace
