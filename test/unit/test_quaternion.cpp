// The quaternion helpers the rotational springs use, against Eigen's own
// quaternion product: G(a) b is the vector part of conj(a) * b.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "coil_winding_sim/core/quaternion.hpp"

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
  }
}
