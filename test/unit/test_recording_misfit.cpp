// The misfit of a replay against a recording (recording_misfit.hpp) on
// closed forms: a helix measured with a known radial sensor offset, a
// tension of known offset at a different pace, and the distance to a
// polyline of known geometry.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "coil_winding_sim/core/run/recording_misfit.hpp"

namespace {

// A helix on radius r [m] with pitch [m/turn], points every `step` rad up to
// angle phi_end, as a profile cloud (stand-off over r0: r - r0).
cws::ProfileCloud helix(double t_s, double r, double phi_end, double step, double r0) {
  cws::ProfileCloud c;
  c.t_s = t_s;
  const double pitch = 0.5e-3;
  for (double phi = 0.0; phi <= phi_end + 1e-12; phi += step) {
    c.p_core.emplace_back(r * std::cos(phi), r * std::sin(phi), pitch * phi / (2 * M_PI));
    c.stand_off_m.push_back(r - r0);
  }
  return c;
}

// A spindle at constant speed w [rad/s] for 1 s at 100 Hz, tension T(angle).
cws::RecordedSeries run(double w, double tension_offset, double r) {
  cws::RecordedSeries s;
  for (int i = 0; i <= 100; ++i) {
    const double t = 0.01 * i, a = w * t;
    s.spindle_t_s.push_back(t);
    s.spindle_angle_rad.push_back(a);
    s.tension_t_s.push_back(t);
    s.tension_N.push_back(30.0 + std::sin(3.0 * a) + tension_offset);
  }
  for (int k = 1; k <= 4; ++k) s.profiles.push_back(helix(0.25 * k, r, w * 0.25 * k, 0.05, 5e-3));
  return s;
}

}  // namespace

TEST(RecordingMisfit, SignedDistanceToAPolyline) {
  // A segment along x at z = 0, radius measured in the x-y plane.
  const std::vector<Eigen::Vector3d> poly = {{1.0, 0.0, 0.0}, {1.0, 1.0, 0.0}};
  EXPECT_DOUBLE_EQ(cws::signedDistanceToPolyline({1.5, 0.5, 0.0}, poly), 0.5);
  EXPECT_DOUBLE_EQ(cws::signedDistanceToPolyline({0.5, 0.5, 0.0}, poly), -0.5);
  // Beyond an end: the distance to the end point.
  EXPECT_DOUBLE_EQ(cws::signedDistanceToPolyline({1.0, 2.0, 0.0}, poly), 1.0);
}

TEST(RecordingMisfit, HermiteIsExactForACubic) {
  std::vector<double> x, y;
  for (int i = 0; i < 20; ++i) {
    x.push_back(0.1 * i);
    y.push_back(2.0 * x.back() + 1.0);
  }
  const std::vector<double> q = cws::hermite({0.05, 0.77, 1.85}, x, y);
  EXPECT_NEAR(q[0], 1.1, 1e-12);
  EXPECT_NEAR(q[1], 2.54, 1e-12);
  EXPECT_NEAR(q[2], 4.7, 1e-12);
}

TEST(RecordingMisfit, TheSameRunHasNoMisfit) {
  const cws::RecordedSeries a = run(10.0, 0.0, 5.25e-3);
  const cws::Misfit m = cws::recordingMisfit(a, a, cws::MisfitWeights());
  // The offset is found to the golden section's 1e-7 mm.
  EXPECT_EQ(m.tensionRms(), 0.0);
  EXPECT_LT(m.profileRms(), 1e-7);
  EXPECT_LT(std::abs(m.profile_offset_mm), 1e-7);
  EXPECT_LT(m.bulgingRms(), 1e-7);
  EXPECT_EQ(m.profile_pairs, 4);
}

// A machine at another pace (the same curve by angle) with the tension 0.5
// N high and its profile sensor 0.03 mm out: by angle the tension error is
// the offset alone, and the offset removed leaves no profile or bulging
// error.
TEST(RecordingMisfit, AngleAlignmentAndTheSensorOffset) {
  const cws::RecordedSeries sim = run(10.0, 0.0, 5.25e-3);
  cws::RecordedSeries machine = run(10.0, 0.5, 5.25e-3 + 3e-5);
  for (cws::ProfileCloud& c : machine.profiles) {
    for (double& h : c.stand_off_m) h = 5.25e-3 - 5e-3 + 3e-5;
  }
  const cws::Misfit m = cws::recordingMisfit(machine, sim, cws::MisfitWeights());
  EXPECT_NEAR(m.tensionRms(), 0.5, 1e-9);
  for (double e : m.tension_N) EXPECT_NEAR(e, -0.5, 1e-9);
  EXPECT_NEAR(m.profile_offset_mm, 0.03, 1e-6);
  EXPECT_LT(m.profileRms(), 1e-5);
  EXPECT_LT(m.bulgingRms(), 1e-6);
  // Without the offset removed: the plain distances, 0.03 mm less the
  // chords' sag (0.05 rad steps on 5.25 mm: 1.6 um).
  cws::MisfitWeights plain;
  plain.remove_profile_offset = false;
  const cws::Misfit p = cws::recordingMisfit(machine, sim, plain);
  EXPECT_NEAR(p.profileRms(), 0.03, 0.002);
  EXPECT_NEAR(p.bulgingRms(), 0.03, 1e-6);
  // The weighted sum: 100 / N^2 x 101 samples x 0.25 N^2 + the rest.
  EXPECT_NEAR(m.value(cws::MisfitWeights()), 100.0 * m.tension_N.size() * 0.25, 1e-3);
}

TEST(RecordingMisfit, TooFewSamplesAreRefusedInTheComparisonsWords) {
  cws::RecordedSeries a = run(10.0, 0.0, 5.25e-3);
  a.tension_t_s.resize(5);
  a.tension_N.resize(5);
  try {
    cws::recordingMisfit(a, a, cws::MisfitWeights());
    FAIL() << "not refused";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "too few samples to align: machine/tension/measured has 5 (need 10)");
  }
}
