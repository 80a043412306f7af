// The quaternion helpers the rotational springs use, against Eigen's own
// quaternion product: G(a) b is the vector part of conj(a) * b.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "coil_winding_sim/core/base/quaternion.hpp"

namespace {

Eigen::Vector3d vectorPartOfConjProduct(const cws::quat::Vec4& a, const cws::quat::Vec4& b) {
  const Eigen::Quaterniond qa(a[0], a[1], a[2], a[3]), qb(b[0], b[1], b[2], b[3]);
  return (qa.conjugate() * qb).vec();
}

}  // namespace

TEST(Quaternion, GTimesIsTheVectorPartOfTheConjugateProduct) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 100; ++k) {
    // Not unit: the forces are defined off the unit sphere too.
    const cws::quat::Vec4 a(u(rng), u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng), u(rng));
    const Eigen::Vector3d expected = vectorPartOfConjProduct(a, b);
    EXPECT_LT((cws::quat::gTimes(a, b) - expected).norm(), 1e-15);
    EXPECT_LT((cws::quat::G(a) * b - expected).norm(), 1e-15);
    // G(a)^T v: v . (G(a) b) = (G(a)^T v) . b for every b.
    const Eigen::Vector3d v(u(rng), u(rng), u(rng));
    EXPECT_NEAR(cws::quat::gTransposeApply(a, v).dot(b), v.dot(expected), 1e-14);
  }
}

// d . xi(q) and d . eta(q) differentiated in q: the frame constraints'
// generalized forces, against central differences of the axes from Eigen's
// rotation matrix (xi, eta are its first two columns, quadratic in q, so the
// differences are exact to round-off).
TEST(Quaternion, AxisGradientsMatchDifferencesOfTheRotationMatrix) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto axes = [](const cws::quat::Vec4& q) {
    // The quadratic form off the unit sphere: |q|^2 times the rotation of q / |q|.
    const Eigen::Quaterniond unit = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized();
    return Eigen::Matrix3d(q.squaredNorm() * unit.toRotationMatrix());
  };
  for (int k = 0; k < 50; ++k) {
    const cws::quat::Vec4 q(u(rng), u(rng), u(rng), u(rng));
    const Eigen::Vector3d d(u(rng), u(rng), u(rng));
    Eigen::Vector4d xi_fd, eta_fd;
    const double h = 1e-4;
    for (int c = 0; c < 4; ++c) {
      const cws::quat::Vec4 e = h * cws::quat::Vec4::Unit(c);
      const Eigen::Matrix3d rp = axes(q + e), rm = axes(q - e);
      xi_fd[c] = d.dot(rp.col(0) - rm.col(0)) / (2.0 * h);
      eta_fd[c] = d.dot(rp.col(1) - rm.col(1)) / (2.0 * h);
    }
    EXPECT_LT((cws::quat::xiJacobianTransposeTimes(q, d) - xi_fd).norm(), 1e-9);
    EXPECT_LT((cws::quat::etaJacobianTransposeTimes(q, d) - eta_fd).norm(), 1e-9);
    EXPECT_LT((cws::quat::xiJacobianTransposeTimes(q, d) - cws::quat::xiJacobian(q).transpose() * d)
                  .norm(),
              1e-14);
    EXPECT_LT(
        (cws::quat::etaJacobianTransposeTimes(q, d) - cws::quat::etaJacobian(q).transpose() * d)
            .norm(),
        1e-14);
  }
}
