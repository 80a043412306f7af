// Distances from the core's winding surface (the convex hull of its
// cylinders) against plane geometry worked out by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "coil_winding_sim/core/core_geometry.hpp"

namespace {
// The paper's case: 5 mm cylinders at the corners of a 15 mm x 5 mm
// rectangle; the hull is a 20 mm x 10 mm rectangle with 2.5 mm corner radii.
cws::CoreSection paperCore() {
  return cws::CoreSection({cws::CylinderParams{{7.5e-3, 2.5e-3}, 2.5e-3},
                           cws::CylinderParams{{-7.5e-3, 2.5e-3}, 2.5e-3},
                           cws::CylinderParams{{-7.5e-3, -2.5e-3}, 2.5e-3},
                           cws::CylinderParams{{7.5e-3, -2.5e-3}, 2.5e-3}});
}
}  // namespace

TEST(CoreSection, DistancesFromTheRoundedRectangle) {
  const cws::CoreSection core = paperCore();
  const double tol = 1e-9;  // [m]
  // Off a flat face: the distance to the face line.
  EXPECT_NEAR(core.signedDistance({0.0, -6.3e-3}), 1.3e-3, tol);
  EXPECT_NEAR(core.signedDistance({3.0e-3, 5.0e-3}), 0.0, tol);
  EXPECT_NEAR(core.signedDistance({-12.0e-3, 0.0}), 2.0e-3, tol);
  // Beyond a corner: the distance to that cylinder.
  const Eigen::Vector2d c(7.5e-3, -2.5e-3);
  const Eigen::Vector2d p = c + 4.0e-3 * Eigen::Vector2d(1.0, -1.0).normalized();
  EXPECT_NEAR(core.signedDistance(p), 1.5e-3, tol);
  // Inside: minus the distance to the nearest face.
  EXPECT_NEAR(core.signedDistance({0.0, 0.0}), -5.0e-3, tol);
  EXPECT_NEAR(core.signedDistance({9.0e-3, 0.0}), -1.0e-3, tol);
}

TEST(CoreSection, SingleCylinderIsACircle) {
  const cws::CoreSection drum({cws::CylinderParams{{1e-3, 2e-3}, 5e-3}});
  for (double a = 0.0; a < 6.28; a += 0.37) {
    const Eigen::Vector2d p =
        Eigen::Vector2d(1e-3, 2e-3) + 7e-3 * Eigen::Vector2d(std::cos(a), std::sin(a));
    EXPECT_NEAR(drum.signedDistance(p), 2e-3, 1e-9) << "angle " << a;
  }
}
