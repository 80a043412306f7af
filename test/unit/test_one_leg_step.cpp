// The scheme velocity of the core's material (one_leg_step.hpp) against
// the scheme applied to the positions the core itself gives a material point
// at the step's times: v = alpha (x(t1) - sum_j w_j x(t_j)) for backward
// Euler and variable-step BDF2, with the core speeding up (the turn is not
// uniform in time) and on a tilted axis off the origin.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "coil_winding_sim/core/assembly/one_leg_step.hpp"
#include "coil_winding_sim/core/machine/rotating_core.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace {

cws::CoreParams tiltedCore() {
  cws::CoreParams p;
  p.position_world = {0.01, -0.02, 0.005};
  p.axis_world = Eigen::Vector3d(0.3, -0.2, 1.0).normalized();
  p.start_at_speed = false;  // ramps from rest at max_angular_acceleration
  return p;
}

Eigen::Vector4d asVec(const Eigen::Quaterniond& q) { return {q.w(), q.x(), q.y(), q.z()}; }

// The step (t_past, w_past, alpha) of backward Euler or of BDF2 with the
// previous step h_prev [s].
cws::OneLegStep schemeStep(double t1, double h, double h_prev, bool bdf2) {
  cws::OneLegStep s;
  s.t1 = t1;
  s.t_past[0] = t1 - h;
  s.alpha = 1.0 / h;
  if (bdf2) {
    const double r = h / h_prev;
    s.past = 2;
    s.t_past[1] = t1 - h - h_prev;
    s.w_past[0] = (1.0 + r) * (1.0 + r) / (1.0 + 2.0 * r);
    s.w_past[1] = -r * r / (1.0 + 2.0 * r);
    s.alpha = (1.0 + 2.0 * r) / ((1.0 + r) * h);
  }
  return s;
}

void expectSchemeRates(bool bdf2) {
  const cws::CoreParams params = tiltedCore();
  const cws::RotatingCore core(params, 200.0);  // ramping for 10 ms
  const Eigen::Vector3d p_core(0.012, 0.003, 0.004);
  const Eigen::Quaterniond q_core =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  // Large steps, so that the chord and the tangent differ clearly.
  const double t1 = 6e-3, h = 1e-3, h_prev = 7e-4;
  const cws::OneLegStep step = schemeStep(t1, h, h_prev, bdf2);

  Eigen::Vector3d p_hat = Eigen::Vector3d::Zero();
  Eigen::Vector4d q_hat = Eigen::Vector4d::Zero();
  double theta_past[cws::OneLegStep::kMaxPast];
  for (int j = 0; j < step.past; ++j) {
    p_hat += step.w_past[j] * core.pointWorld(step.t_past[j], p_core);
    q_hat += step.w_past[j] * asVec(core.quaternionWorldCore(step.t_past[j]) * q_core);
    theta_past[j] = core.angle(step.t_past[j]);
  }
  const Eigen::Vector3d p1 = core.pointWorld(t1, p_core);
  const Eigen::Vector4d q1 = asVec(core.quaternionWorldCore(t1) * q_core);
  const Eigen::Vector3d v_expected = step.alpha * (p1 - p_hat);
  const Eigen::Vector4d qd_expected = step.alpha * (q1 - q_hat);

  const cws::CarriedRate rate = cws::CarriedRate::scheme(
      step, core.originWorld(), core.axisWorld(), core.angle(t1), core.omega(t1), theta_past);
  const Eigen::Vector3d v = rate.velocity(p1);
  const Eigen::Vector4d qd = rate.quaternionRate(q1, Eigen::Vector4d::Zero());
  const Eigen::Vector3d v_tangent = core.velocityWorld(t1, p1);
  std::printf("%s: scheme velocity error %.2e m/s; it differs from the tangent by %.2e m/s\n",
              bdf2 ? "bdf2" : "backward Euler", (v - v_expected).norm(),
              (v_expected - v_tangent).norm());
  EXPECT_LT((v - v_expected).norm(), 1e-12 * v_expected.norm());
  EXPECT_LT((qd - qd_expected).norm(), 1e-12 * qd_expected.norm());
  // The check has teeth: the tangent is far from the scheme's velocity.
  EXPECT_GT((v_expected - v_tangent).norm(), 1e-3 * v_expected.norm());
  EXPECT_LT((rate.exactVelocity(p1) - v_tangent).norm(), 1e-14);
}

}  // namespace

TEST(OneLegStep, BackwardEulerCarriedRateIsTheChordOfTheCoreMaterial) { expectSchemeRates(false); }

TEST(OneLegStep, Bdf2CarriedRateIsTheSchemeOfTheCoreMaterial) { expectSchemeRates(true); }

TEST(OneLegStep, TangentRateIsTheCoreVelocity) {
  const cws::RotatingCore core(tiltedCore(), 200.0);
  const double t = 4e-3;
  const cws::CarriedRate rate =
      cws::CarriedRate::tangent(core.originWorld(), core.axisWorld(), core.omega(t));
  const Eigen::Vector3d p(0.02, -0.01, 0.03);
  EXPECT_LT((rate.velocity(p) - core.velocityWorld(t, p)).norm(), 1e-14);
}

// The committed state's rate: exact at the start and after a restore, the
// accepted step's scheme rate at the time that step ended.
TEST(OneLegStep, CarriedMotionKeepsTheAcceptedStepsRate) {
  const cws::RotatingCore core(tiltedCore(), 200.0);
  cws::CarriedMotion motion(&core);
  const Eigen::Vector3d p = core.pointWorld(2e-3, Eigen::Vector3d(0.012, 0.0, 0.0));
  EXPECT_LT((motion.load(1e-3).velocity(p) - core.velocityWorld(1e-3, p)).norm(), 1e-14);
  const cws::OneLegStep step = schemeStep(2e-3, 1e-3, 0.0, false);
  const Eigen::Vector3d v_trial = motion.trial(step).velocity(p);
  motion.accept();
  EXPECT_LT((motion.load(2e-3).velocity(p) - v_trial).norm(), 1e-14);
  // A committed state the accepted step did not end at (a restored one).
  EXPECT_LT((motion.load(5e-3).velocity(p) - core.velocityWorld(5e-3, p)).norm(), 1e-14);
}
