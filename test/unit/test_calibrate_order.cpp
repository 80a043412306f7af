// A calibration searches within the keys' order (kinetic friction at most
// static friction): a point that breaks it is moved onto it, the fitted key
// of the pair taking the other's value (key_order.hpp).
#include <gtest/gtest.h>

#include "key_order.hpp"

TEST(CalibrationOrder, KineticFrictionStaysAtOrBelowStatic) {
  cws::Scene base;  // mu_s 0.23, mu_k 0.17
  const std::vector<std::string> both{"contact.static_friction", "contact.kinetic_friction"};
  // In order: unchanged; broken: kinetic takes static's value.
  EXPECT_EQ(cws_tools::keepKeyOrder(both, base, Eigen::Vector2d(0.3, 0.2)),
            Eigen::VectorXd(Eigen::Vector2d(0.3, 0.2)));
  EXPECT_EQ(cws_tools::keepKeyOrder(both, base, Eigen::Vector2d(0.2, 0.3)),
            Eigen::VectorXd(Eigen::Vector2d(0.2, 0.2)));
  // One of the pair fitted: the scene's other value bounds it.
  const std::vector<std::string> kinetic{"contact.kinetic_friction"};
  EXPECT_EQ(cws_tools::keepKeyOrder(kinetic, base, Eigen::VectorXd::Constant(1, 0.3))[0], 0.23);
  EXPECT_EQ(cws_tools::keepKeyOrder(kinetic, base, Eigen::VectorXd::Constant(1, 0.1))[0], 0.1);
  const std::vector<std::string> stat{"contact.static_friction"};
  EXPECT_EQ(cws_tools::keepKeyOrder(stat, base, Eigen::VectorXd::Constant(1, 0.1))[0], 0.17);
  // Keys of no pair: untouched.
  const std::vector<std::string> other{"wire.bend.yield_curvature"};
  EXPECT_EQ(cws_tools::keepKeyOrder(other, base, Eigen::VectorXd::Constant(1, 5.0))[0], 5.0);
}
