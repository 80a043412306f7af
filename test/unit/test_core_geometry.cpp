// Distances from the core's winding surface (the convex hull of its
// cylinders) against plane geometry worked out by hand, and core.shape's
// bobbin as drawn made into that surface.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
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

// core.shape: a bobbin as drawn, against the closed-form signed distance of
// a rounded rectangle: with q = |p| - (w/2 - r, h/2 - r) componentwise,
// |max(q, 0)| + min(max(q_x, q_y), 0) - r.
namespace {
double roundedRectangleDistance(const Eigen::Vector2d& p, double w, double h, double r) {
  const Eigen::Vector2d q = p.cwiseAbs() - Eigen::Vector2d(0.5 * w - r, 0.5 * h - r);
  return q.cwiseMax(0.0).norm() + std::min(std::max(q.x(), q.y()), 0.0) - r;
}

cws::Scene shapedScene(const std::string& shape) {
  return cws::sceneFromYamlText("core: {shape: {kind: rounded_rectangle, " + shape + "}}");
}
}  // namespace

TEST(CoreShape, ARoundedRectangleIsItsCornerCylindersAndFlatSides) {
  const double w = 12e-3, h = 8e-3, r = 1e-3;
  const cws::Scene s = shapedScene("width: 0.012, height: 0.008, corner_radius: 0.001");
  ASSERT_EQ(s.core.cylinders.size(), 4u);
  EXPECT_TRUE(s.core.hull_faces);
  EXPECT_TRUE(s.core.faces.empty());
  const cws::CoreSection section(s.core);
  // Points all around, outside and inside, against the closed form.
  for (double a = 0.05; a < 6.28; a += 0.21) {
    for (double rho : {1e-3, 4.5e-3, 6.5e-3, 9e-3}) {
      const Eigen::Vector2d p = rho * Eigen::Vector2d(std::cos(a), std::sin(a));
      EXPECT_NEAR(section.signedDistance(p), roundedRectangleDistance(p, w, h, r), 1e-9)
          << "at (" << p.x() << ", " << p.y() << ")";
    }
  }
}

TEST(CoreShape, ThePapersOutlineGivesItsCylindersInTheirOrder) {
  // default.yaml's four cylinders, with the flat sides between them.
  const cws::Scene s = shapedScene("width: 0.020, height: 0.010, corner_radius: 0.0025");
  const std::vector<Eigen::Vector2d> paper{
      {7.5e-3, 2.5e-3}, {-7.5e-3, 2.5e-3}, {-7.5e-3, -2.5e-3}, {7.5e-3, -2.5e-3}};
  ASSERT_EQ(s.core.cylinders.size(), paper.size());
  for (std::size_t i = 0; i < paper.size(); ++i) {
    EXPECT_EQ(s.core.cylinders[i].center_core, paper[i]) << "cylinder " << i;
    EXPECT_EQ(s.core.cylinders[i].radius, 2.5e-3);
  }
  EXPECT_TRUE(s.core.hull_faces);
  // config/scenes/paper_core.yaml: the same cylinders, as the paper lists
  // them, without the sides.
  const cws::Scene listed =
      cws::loadScene(std::string(CWS_SOURCE_DIR) + "/config/scenes/paper_core.yaml", {});
  ASSERT_EQ(listed.core.cylinders.size(), paper.size());
  for (std::size_t i = 0; i < paper.size(); ++i) {
    EXPECT_EQ(listed.core.cylinders[i].center_core, s.core.cylinders[i].center_core);
    EXPECT_EQ(listed.core.cylinders[i].radius, s.core.cylinders[i].radius);
  }
  EXPECT_FALSE(listed.core.hull_faces);
}

TEST(CoreShape, SidesOfTwiceTheCornerRadiusMakeASlotOrARoundCore) {
  // Both sides: a round core of radius r.
  const cws::Scene round = shapedScene("width: 0.008, height: 0.008, corner_radius: 0.004");
  ASSERT_EQ(round.core.cylinders.size(), 1u);
  EXPECT_FALSE(round.core.hull_faces);
  const cws::CoreSection disc(round.core);
  for (double a = 0.0; a < 6.28; a += 0.5) {
    EXPECT_NEAR(disc.signedDistance(7e-3 * Eigen::Vector2d(std::cos(a), std::sin(a))), 3e-3, 1e-9);
  }
  // One side: a slot, two cylinders and two flat sides.
  const cws::Scene slot = shapedScene("width: 0.004, height: 0.010, corner_radius: 0.002");
  ASSERT_EQ(slot.core.cylinders.size(), 2u);
  EXPECT_TRUE(slot.core.hull_faces);
  EXPECT_EQ(cws::coreFaces(slot.core).size(), 2u);
  const cws::CoreSection section(slot.core);
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(5e-3, 0.0), Eigen::Vector2d(1e-3, 8e-3),
                                   Eigen::Vector2d(-3e-3, -1e-3), Eigen::Vector2d(0.0, 0.0)}) {
    EXPECT_NEAR(section.signedDistance(p), roundedRectangleDistance(p, 4e-3, 10e-3, 2e-3), 1e-9);
  }
}

TEST(CoreShape, AShapeThatCannotBeMadeIsRefusedByItsKey) {
  auto refusedKey = [](const std::string& shape) {
    try {
      shapedScene(shape);
    } catch (const cws::SceneError& e) {
      return e.key();
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(refusedKey("width: 0.012, height: 0.008, corner_radius: 0.005"),
            "core.shape.corner_radius");
  EXPECT_EQ(refusedKey("width: 0.0, height: 0.008, corner_radius: 0.001"), "core.shape.width");
  EXPECT_EQ(refusedKey("width: 0.012, height: 0.008, corner_radius: 0.0"),
            "core.shape.corner_radius");
  EXPECT_EQ(refusedKey("width: 0.012, height: -0.008, corner_radius: 0.001"), "core.shape.height");
  // Corners sharper than a segment is long: named by the shape's key.
  try {
    cws::sceneFromYamlText(
        "physics: {contact: true}\n"
        "core: {shape: {kind: rounded_rectangle, width: 0.012, height: 0.008, "
        "corner_radius: 0.0005}}");
    ADD_FAILURE() << "1 mm segments over 0.5 mm corners were accepted";
  } catch (const cws::SceneError& e) {
    EXPECT_EQ(e.key(), "wire.segment_length");
    EXPECT_NE(e.why().find("core.shape.corner_radius"), std::string::npos) << e.why();
  }
}
