// The implicit integrator: its banded LU against a dense LU, its coloured
// finite-difference Jacobian against a column-by-column one, a stiff problem
// with a closed-form solution, and the cantilever's closed form.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <random>

#include "coil_winding_sim/core/linear_algebra/banded_lu.hpp"
#include "coil_winding_sim/core/model/wire_model.hpp"
#include "coil_winding_sim/core/time_steppers/rosenbrock2.hpp"
#include "wire_test_support.hpp"

namespace {

// Random banded matrix with a weak diagonal, so that pivoting is needed.
void checkBandedSolve(int n, int kl, int ku) {
  std::mt19937 rng(7 + n + kl * 31 + ku);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(n, n);
  cws::BandedLu lu(n + 5, kl, ku);
  lu.setZero(n);
  for (int j = 0; j < n; ++j) {
    for (int i = std::max(0, j - ku); i <= std::min(n - 1, j + kl); ++i) {
      const double a = (i == j) ? 1e-3 * u(rng) : u(rng);
      dense(i, j) = a;
      lu.at(i, j) = a;
    }
  }
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) b[i] = u(rng);
  const Eigen::VectorXd x_dense = dense.partialPivLu().solve(b);
  ASSERT_TRUE(lu.factor());
  Eigen::VectorXd x = b;
  lu.solve(x);
  const double residual = (dense * x - b).norm() / b.norm();
  const double diff = (x - x_dense).norm() / x_dense.norm();
  std::printf("banded LU n=%d kl=%d ku=%d: residual %.1e, vs dense LU %.1e\n", n, kl, ku, residual,
              diff);
  EXPECT_LT(residual, 1e-10);
  EXPECT_LT(diff, 1e-8);
}

// Prothero-Robinson: y_j' = lambda_j (y_j - g(t)) + g'(t), exact y_j = g(t)
// for y_j(0) = g(0) at any stiffness lambda_j < 0. Chain of 1-component
// blocks, no coupling.
class ProtheroRobinson : public cws::OdeSystem {
 public:
  explicit ProtheroRobinson(const Eigen::VectorXd& lambda) : lambda_(lambda) {
    atol_.setConstant(lambda.size(), 1e-8);
    rweight_.setOnes(lambda.size());
  }
  static double g(double t) { return std::sin(10.0 * t) + 0.5 * t; }
  static double gdot(double t) { return 10.0 * std::cos(10.0 * t) + 0.5; }
  int size() const override { return static_cast<int>(lambda_.size()); }
  int capacity() const override { return size(); }
  void derivative(double t, ConstRef y, Ref dydt) override {
    for (int j = 0; j < size(); ++j) dydt[j] = lambda_[j] * (y[j] - g(t)) + gdot(t);
  }
  const Eigen::VectorXd& absoluteTolerance() const override { return atol_; }
  const Eigen::VectorXd& relativeToleranceWeight() const override { return rweight_; }
  cws::ChainStructure chainStructure() const override { return {0, 1, 0}; }
  void acceptStep(double, Eigen::VectorXd&) override {}

 private:
  Eigen::VectorXd lambda_, atol_, rweight_;
};

// Integrates Prothero-Robinson over [0, 1] s from the exact start; returns
// the largest error at the end and the accepted (and rejected) steps.
double solveProtheroRobinson(const Eigen::VectorXd& lambda, double rtol, double initial_step,
                             long& steps, long& rejected) {
  ProtheroRobinson sys(lambda);
  cws::SolverParams p;
  p.rtol = rtol;
  p.max_step = 0.1;
  p.initial_step = initial_step;
  cws::Rosenbrock2 ros(p, sys);
  Eigen::VectorXd y = Eigen::VectorXd::Constant(lambda.size(), ProtheroRobinson::g(0.0));
  double t = 0.0;
  while (t < 1.0) ros.step(sys, t, y, 1.0);
  steps = ros.counts().accepted;
  rejected = ros.counts().rejected;
  return (y.array() - ProtheroRobinson::g(1.0)).abs().maxCoeff();
}

}  // namespace

TEST(BandedLu, MatchesADenseLu) {
  checkBandedSolve(40, 3, 3);
  checkBandedSolve(90, 41, 41);  // the wire's band (14-component blocks, radius 2)
  checkBandedSolve(50, 2, 7);
  checkBandedSolve(1, 0, 0);
}

TEST(BandedLu, ReportsASingularMatrix) {
  cws::BandedLu lu(4, 1, 1);
  lu.setZero(4);
  for (int i = 0; i < 4; ++i) lu.at(i, i) = 1.0;
  lu.at(2, 2) = 0.0;
  lu.at(3, 2) = 0.0;
  EXPECT_FALSE(lu.factor());
}

TEST(Rosenbrock2, StiffProblemAtStepsFarAboveOneOverLambda) {
  // Stiffness from 1 to 1e8 1/s; the explicit limit would be ~2e-8 s.
  Eigen::VectorXd lambda(5);
  lambda << -1.0, -1e2, -1e4, -1e6, -1e8;
  long steps = 0, rejected = 0;
  const double err = solveProtheroRobinson(lambda, 1e-6, 1e-4, steps, rejected);
  std::printf(
      "rosenbrock2 Prothero-Robinson (lambda to -1e8): error %.2e in %ld steps "
      "(%ld rejected), mean step %.2e s\n",
      err, steps, rejected, 1.0 / steps);
  EXPECT_LT(err, 1e-5);
  // Steps sized by the smooth solution, not by 1 / |lambda| = 1e-8 s (an
  // explicit method would need ~5e7 steps).
  EXPECT_GT(1.0 / steps, 1e-5);
}

TEST(Rosenbrock2, SecondOrderOnANonStiffProblem) {
  // Global error against the number of steps the controller chose, at two
  // tolerances: error ~ steps^-2. (On stiff components Rosenbrock methods
  // show the known order reduction towards 1, which is why this checks a
  // non-stiff problem.)
  Eigen::VectorXd lambda(2);
  lambda << -0.5, -2.0;
  double err[2];
  long steps[2];
  const double rtol[2] = {1e-5, 1e-7};
  for (int k = 0; k < 2; ++k) {
    long rejected = 0;
    err[k] = solveProtheroRobinson(lambda, rtol[k], 1e-5, steps[k], rejected);
  }
  const double order = std::log(err[0] / err[1]) / std::log(double(steps[1]) / steps[0]);
  std::printf("rosenbrock2 order: errors %.2e / %.2e in %ld / %ld steps: observed order %.2f\n",
              err[0], err[1], steps[0], steps[1], order);
  EXPECT_GT(order, 1.6);
  EXPECT_LT(order, 2.6);
}

TEST(Rosenbrock2, ColouredJacobianMatchesColumnByColumn) {
  // A bent, moving 3-D wire (all 14 components of every block active).
  cws::Scene s = cws_test::cantilever(0.02, 8);
  cws::WireModel model(s);
  Eigen::VectorXd y = model.initialState();
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 1.0);
  const int n = model.size();
  for (int i = 2; i < n; ++i) {
    const int c = (i - 2) % 14;
    y[i] += (c < 3 ? 2e-4 : c < 7 ? 2e-2 : c < 10 ? 0.1 : 10.0) * noise(rng);
  }
  cws::Rosenbrock2 ros(s.solver, model);
  ros.buildJacobian(model, 0.0, y);
  // Column by column, central differences.
  Eigen::MatrixXd dense(n, n);
  Eigen::VectorXd fp(n), fm(n), yp = y;
  for (int j = 0; j < n; ++j) {
    const double d = 1e-7 * std::max(std::abs(y[j]), 1e-3);
    yp[j] = y[j] + d;
    model.derivative(0.0, yp, fp);
    yp[j] = y[j] - d;
    model.derivative(0.0, yp, fm);
    yp[j] = y[j];
    dense.col(j) = (fp - fm) / (2.0 * d);
  }
  dense.topRows(2).setZero();  // the lead rows are explicit
  Eigen::MatrixXd banded(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) banded(i, j) = ros.jacobian(i, j);
  }
  // Inside the band both agree; what the band drops (coupling through the
  // constraint solve beyond one neighbour) is small against what it keeps.
  Eigen::MatrixXd in_band = Eigen::MatrixXd::Zero(n, n), outside = dense;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (std::abs(i - j) <= 41) {  // radius 2: 3 x 14 - 1
        in_band(i, j) = dense(i, j);
        outside(i, j) = 0.0;
      }
    }
  }
  const double in_band_diff = (banded - in_band).norm() / in_band.norm();
  const double dropped = outside.norm() / dense.norm();
  std::printf("coloured Jacobian vs column-by-column: %.1e inside the band; dropped part %.1e\n",
              in_band_diff, dropped);
  EXPECT_LT(in_band_diff, 5e-2);
  EXPECT_LT(dropped, 5e-2);
}

TEST(Rosenbrock2, CantileverTipForce) {
  const double force = 9.18e-3, length = 0.1;
  cws::Scene s = cws_test::rampedStatic(cws_test::cantilever(length, 10), {0.0, force, 0.0},
                                        {0, 0, 0}, 0.02, 0.08);
  cws::Simulation reference(s);  // RKF45
  reference.run();
  s.solver.integrator = "rosenbrock2";
  s.solver.atol = 1e-9;
  s.solver.rtol = 1e-4;
  cws::Simulation sim(s);
  sim.run();
  const double expected = force * std::pow(length, 3) / (3.0 * s.wire.bend.elastic_rigidity);
  const double error = cws_test::tipPosition(sim).y() / expected - 1.0;
  const double vs_rkf45 =
      (cws_test::tipPosition(sim).y() - cws_test::tipPosition(reference).y()) / expected;
  std::printf(
      "rosenbrock2: cantilever n=11 rel. error %.3e against PL^3/3EI, %.1e against rkf45; "
      "%.2f s wall, %ld steps (rkf45 %.2f s, %ld steps)\n",
      error, vs_rkf45, sim.wallTime(), sim.stepper().counts().accepted, reference.wallTime(),
      reference.stepper().counts().accepted);
  EXPECT_LT(std::abs(error), 5e-3);
  EXPECT_LT(std::abs(vs_rkf45), 1e-3);
}
