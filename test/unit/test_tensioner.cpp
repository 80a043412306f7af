// The tensioner and the nozzle (machine/tensioner.hpp) against closed
// forms: the dancer's transfer function from draw-in speed to tension, its
// return to the setpoint, the nozzle's capstan ratio; and in a wound coil,
// no ripple on a round core at constant speed.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "coil_winding_sim/core/external_forces/supply.hpp"
#include "coil_winding_sim/core/machine/tensioner.hpp"
#include "coil_winding_sim/core/run/run_checks.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kEA = 48900.0;  // the paper's wire [N]
constexpr double kSetpoint = 30.0;

cws::TensionerParams dancer() {
  cws::TensionerParams p;
  p.kind = "dancer";
  p.mass = 0.03;
  p.stiffness = 100.0;
  p.damping = 2.0;
  p.bandwidth = 30.0;
  p.span_length = 0.5;
  return p;
}

// Tension over draw-in speed, derived by hand from the arm's and the span's
// equations (docs/MODEL.md): with X = -2 T / (m s^2 + c s + k) and
// (s / k_w) T = (2 s + K_p + K_i / s) X + U,
//   H(s) = 1 / (s / k_w + 2 (2 s + K_p + K_i / s) / (m s^2 + c s + k)).
std::complex<double> closedForm(const cws::TensionerParams& p, double omega) {
  const std::complex<double> s(0.0, omega);
  const double kw = kEA / p.span_length, kp = 4.0 * p.bandwidth,
               ki = 2.0 * p.bandwidth * p.bandwidth;
  const std::complex<double> arm = p.mass * s * s + p.damping * s + p.stiffness;
  return 1.0 / (s / kw + 2.0 * (2.0 * s + kp + ki / s) / arm);
}
}  // namespace

TEST(Tensioner, ADancerAnswersASineAsItsTransferFunction) {
  // u = U0 + U1 sin(w t), fed as each step's mean (as the wire's draw-in
  // is); after the transients, T's component at w by least squares.
  const cws::TensionerParams p = dancer();
  const double u0 = 0.5, u1 = 0.01, h = 1.0e-5;
  for (double hz : {2.0, 10.0, 50.0, 200.0, 1000.0}) {
    SCOPED_TRACE(hz);
    const double w = 2.0 * kPi * hz;
    cws::Tensioner t(p, kEA, kSetpoint);
    const double settle = 3.0, periods = std::ceil(0.3 * hz);
    const double end = settle + periods / hz;
    double time = 0.0;
    // Sums for T ~ a + b sin + c cos (normal equations, solved below).
    double a_mat[3][3] = {}, rhs[3] = {};
    for (int k = 1; time < end; ++k) {
      const double t0 = time;
      time = k * h;
      const double mean_u = u0 + u1 * (std::cos(w * t0) - std::cos(w * time)) / (w * h);
      t.advance(time, mean_u);
      if (time <= settle) continue;
      const double f[3] = {1.0, std::sin(w * time), std::cos(w * time)};
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) a_mat[i][j] += f[i] * f[j];
        rhs[i] += f[i] * t.tension();
      }
    }
    // Solve the 3x3 system by Cramer's rule.
    auto det = [](double m[3][3]) {
      return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
             m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
             m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    };
    double coef[3];
    for (int c = 0; c < 3; ++c) {
      double m[3][3];
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) m[i][j] = j == c ? rhs[i] : a_mat[i][j];
      }
      coef[c] = det(m) / det(a_mat);
    }
    // T1 sin(w t + phi) = T1 cos(phi) sin + T1 sin(phi) cos.
    const std::complex<double> got(coef[1] / u1, coef[2] / u1);
    const std::complex<double> want = closedForm(p, w);
    EXPECT_NEAR(std::abs(got), std::abs(want), 0.02 * std::abs(want));
    EXPECT_NEAR(std::arg(got / want), 0.0, 0.02);
    EXPECT_NEAR(coef[0], kSetpoint, 0.02 * kSetpoint) << "the mean tension";
  }
}

TEST(Tensioner, AConstantDrawInReturnsToTheSetpointWithTheArmCentred) {
  // The loop's integral takes up any steady speed: T = T_set, x = 0.
  cws::Tensioner t(dancer(), kEA, kSetpoint);
  double time = 0.0;
  for (int k = 1; k <= 40000; ++k) {
    time = k * 1.0e-4;
    t.advance(time, std::min(1.0, time / 0.01));  // a 10 ms ramp to 1 m/s
  }
  EXPECT_NEAR(t.tension(), kSetpoint, 1e-6);
  EXPECT_NEAR(t.armPosition(), 0.0, 1e-9);
  EXPECT_NEAR(t.payOffSpeed(), 1.0, 1e-8);
}

TEST(Tensioner, ItsEnergyChangesByTheWorksBooked) {
  // The trapezoidal rule keeps the quadratic energy's change equal to the
  // works at the sub-steps' mean states.
  cws::Tensioner t(dancer(), kEA, kSetpoint);
  double time = 0.0;
  for (int k = 1; k <= 3000; ++k) {
    time = k * 1.0e-4;
    t.advance(time, 0.8 + 0.3 * std::sin(300.0 * time) + (k % 7 == 0 ? 0.05 : 0.0));
  }
  const double held = t.kinetic() + t.elastic() + t.damped();
  const double work = t.loadWork() + t.payOffWork() + t.drawnWork();
  EXPECT_NEAR(held, work, 1e-12 * std::abs(work));
  EXPECT_GT(t.damped(), 0.0);
}

TEST(Tensioner, TheNozzlesCapstanRatioIsExpMuTheta) {
  const double mu = 0.2, theta = 1.5, vs = 1e-3;
  EXPECT_DOUBLE_EQ(cws::capstanRatio(mu, theta, 0.5, vs), std::exp(mu * theta));
  EXPECT_DOUBLE_EQ(cws::capstanRatio(mu, theta, -0.5, vs), std::exp(-mu * theta));
  EXPECT_DOUBLE_EQ(cws::capstanRatio(mu, theta, 0.0, vs), 1.0);
  EXPECT_DOUBLE_EQ(cws::capstanRatio(mu, theta, 0.5e-3, vs), std::exp(0.5 * mu * theta));
}

TEST(Tensioner, TheLoadCellsTraceKeepsWhatItsListHasRoomFor) {
  // Tension 10 + turn * sin(4 pi turns): each whole turn's ripple is twice
  // its turn number. A list with room for two: the first two turns listed,
  // the largest and the mean over all four.
  cws::TensionTrace trace;
  trace.ripple_per_turn.reserve(2);
  for (int k = 0; k <= 4000; ++k) {
    const double turns = k / 800.0;  // to 5 turns
    const double n = std::floor(turns) + 1.0;
    trace.note(turns, 10.0 + n * std::sin(4.0 * kPi * turns));
  }
  ASSERT_EQ(trace.ripple_per_turn.size(), 2u);
  EXPECT_NEAR(trace.ripple_per_turn[0], 2.0, 1e-4);
  EXPECT_NEAR(trace.ripple_per_turn[1], 4.0, 1e-4);
  EXPECT_EQ(trace.ripple_turns, 5);
  EXPECT_NEAR(trace.ripple_max, 10.0, 1e-4);
  EXPECT_NEAR(trace.ripple_sum / trace.ripple_turns, 6.0, 1e-4);
  EXPECT_NEAR(trace.peak, 15.0, 1e-4);
  EXPECT_NEAR(trace.low, 10.0 - 5.0, 1e-3);
}

#ifdef CWS_SOURCE_DIR
namespace {
cws::Scene paperCase(const std::vector<std::string>& more) {
  std::vector<std::string> keys = {"process.turns=5"};
  keys.insert(keys.end(), more.begin(), more.end());
  return cws::loadScene(std::string(CWS_SOURCE_DIR) + "/config/scenes/default.yaml", keys);
}
// The paper's case on a round core of 7.5 mm radius, clamped on it.
const std::vector<std::string> kRoundCore = {
    "core.shape.kind=rounded_rectangle", "core.shape.width=0.015", "core.shape.height=0.015",
    "core.shape.corner_radius=0.0075", "start.position=[0, -8.0e-3, 0]"};
}  // namespace

TEST(Tensioner, ARoundCoreAtConstantSpeedHasNoRipple) {
  // A round core draws wire in at a constant speed, w (R + r): once the
  // start has passed, the load cell sees no ripple. The paper's rectangular
  // core draws in faster at its corners: a ripple each turn.
  std::vector<std::string> round = kRoundCore;
  round.push_back("supply.tensioner.kind=dancer");
  cws::Simulation sim(paperCase(round));
  sim.run();
  const std::vector<double>& ripple = sim.model().supply()->trace().ripple_per_turn;
  ASSERT_GE(ripple.size(), 4u);
  EXPECT_GT(ripple.front(), 1.0) << "the start's transient";
  EXPECT_LT(ripple.back(), 0.1) << "0.3 % of the tension";
  const double draw_in = 2.0 * kPi * 10.0 * (7.5e-3 + 0.5e-3);
  EXPECT_NEAR(sim.model().supply()->tensioner()->payOffSpeed(), draw_in, 0.01 * draw_in);
  // The balance holds the dancer: its imbalance is the ideal tensioner's
  // (bdf2's own, 2.7 % on this core) within 0.2 % of the work.
  cws::Simulation ideal(paperCase(kRoundCore));
  ideal.run();
  EXPECT_NEAR(cws::measureRun(sim).energy_signed_rel, cws::measureRun(ideal).energy_signed_rel,
              2e-3);

  cws::Simulation rect(paperCase({"supply.tensioner.kind=dancer"}));
  rect.run();
  EXPECT_GT(rect.model().supply()->trace().ripple_per_turn.back(), 10.0 * ripple.back());
}

TEST(Tensioner, TheNozzleRaisesThePortsTensionByTheCapstanRatio) {
  // The ideal tensioner at the setpoint, a nozzle of mu 0.2 over 1.5 rad:
  // while wire is drawn in, the port pulls with T_set exp(mu theta), and
  // the wire's last segment carries it.
  cws::Simulation sim(
      paperCase({"process.turns=1", "supply.nozzle_friction=0.2", "supply.nozzle_wrap_angle=1.5"}));
  sim.run();
  const double want = kSetpoint * std::exp(0.3);
  EXPECT_DOUBLE_EQ(sim.model().supply()->tension(), want);
  EXPECT_DOUBLE_EQ(sim.model().supply()->tensionSetpoint(), kSetpoint);
  EXPECT_NEAR(sim.model().portAxialForce(), want, 0.01 * want);
}

TEST(Tensioner, AMachineWithoutASupplyIsRefusedByItsKey) {
  const std::string path = std::string(CWS_SOURCE_DIR) + "/config/scenes/default.yaml";
  for (const std::string& key :
       {std::string("supply.tensioner.kind=dancer"), std::string("supply.nozzle_friction=0.2")}) {
    try {
      cws::loadScene(path, {"physics.supply=false", key, "supply.nozzle_wrap_angle=1"});
      ADD_FAILURE() << key << " was accepted";
    } catch (const cws::SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(key.substr(0, key.find('='))), std::string::npos)
          << e.what();
    }
  }
}
#endif
