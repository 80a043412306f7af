// Distances from the core's winding surface (the convex hull of its
// cylinders) against plane geometry worked out by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "coil_winding_sim/core/scene/core_geometry.hpp"

namespace {
// The paper's case: 5 mm cylinders at the corners of a 15 mm x 5 mm
// rectangle; the hull is a 20 mm x 10 mm rectangle with 2.5 mm corner radii.
cws::CoreParams paperCoreParams() {
  cws::CoreParams p;
  p.cylinders = {cws::CylinderParams{{7.5e-3, 2.5e-3}, 2.5e-3},
                 cws::CylinderParams{{-7.5e-3, 2.5e-3}, 2.5e-3},
                 cws::CylinderParams{{-7.5e-3, -2.5e-3}, 2.5e-3},
                 cws::CylinderParams{{7.5e-3, -2.5e-3}, 2.5e-3}};
  return p;
}
cws::CoreSection paperCore() { return cws::CoreSection(paperCoreParams()); }
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
  cws::CoreParams p;
  p.cylinders = {cws::CylinderParams{{1e-3, 2e-3}, 5e-3}};
  const cws::CoreSection drum(p);
  for (double a = 0.0; a < 6.28; a += 0.37) {
    const Eigen::Vector2d p =
        Eigen::Vector2d(1e-3, 2e-3) + 7e-3 * Eigen::Vector2d(std::cos(a), std::sin(a));
    EXPECT_NEAR(drum.signedDistance(p), 2e-3, 1e-9) << "angle " << a;
  }
}

TEST(CoreSection, HullFacesAreTheFlatSidesOfTheRoundedRectangle) {
  cws::CoreParams p = paperCoreParams();
  p.hull_faces = true;
  const std::vector<cws::FaceParams> faces = cws::coreFaces(p);
  ASSERT_EQ(faces.size(), 4u);
  // Each face lies on a side of the 20 mm x 10 mm rectangle, outside on its
  // right, and spans between the cylinders' tangent points.
  for (const cws::FaceParams& f : faces) {
    const Eigen::Vector2d t = (f.to_core - f.from_core).normalized();
    const Eigen::Vector2d out(t.y(), -t.x());
    const Eigen::Vector2d mid = 0.5 * (f.from_core + f.to_core);
    EXPECT_NEAR(paperCore().signedDistance(mid), 0.0, 1e-9);
    EXPECT_GT(mid.dot(out), 0.0) << "the outside must be on the right";
    const double len = (f.to_core - f.from_core).norm();
    EXPECT_TRUE(std::abs(len - 15e-3) < 1e-12 || std::abs(len - 5e-3) < 1e-12) << len;
  }
  // Unequal radii: the outer tangent of a 2 mm and a 1 mm disc 10 mm apart.
  cws::CoreParams q;
  q.hull_faces = true;
  q.cylinders = {cws::CylinderParams{{0.0, 0.0}, 2e-3}, cws::CylinderParams{{10e-3, 0.0}, 1e-3}};
  for (const cws::FaceParams& f : cws::coreFaces(q)) {
    const Eigen::Vector2d t = (f.to_core - f.from_core).normalized();
    const Eigen::Vector2d out(t.y(), -t.x());
    // Both circles touch the line from the inside: distance from centre = R.
    EXPECT_NEAR((q.cylinders[0].center_core - f.from_core).dot(out), -2e-3, 1e-12);
    EXPECT_NEAR((q.cylinders[1].center_core - f.from_core).dot(out), -1e-3, 1e-12);
  }
}
