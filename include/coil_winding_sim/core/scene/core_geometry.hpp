// Plane geometry of the core's cross-section: the convex hull of its
// cylinders (the winding surface the wire lies on) and distances to it.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

// core.shape made into the core's cylinders and faces, the one place that
// does it: a rounded_rectangle becomes its corner cylinders, counter-
// clockwise from (+x, +y) as the paper's core lists them, with
// core.hull_faces for the flat sides (core.cylinders, core.faces and
// core.hull_faces given beside it are replaced); a side of twice the corner
// radius shares its corners' cylinder (two cylinders make a slot, one a
// round core). kind cylinders: nothing changes. Throws SceneError naming the
// core.shape key that cannot make a section.
void applyCoreShape(CoreParams& core);

// The flat faces of the core: those listed in core.faces plus, with
// core.hull_faces, the sides of the convex hull between neighbouring
// cylinders (the outer common tangents), counter-clockwise.
std::vector<FaceParams> coreFaces(const CoreParams& core);

class CoreSection {
 public:
  // The winding surface: the convex hull of the cylinders and the faces.
  explicit CoreSection(const CoreParams& core);

  // Signed distance [m] of the core-frame point (x, y) from the convex hull
  // of the cylinders' discs and the faces: positive outside, negative inside. Exact up to
  // about 1e-9 of the point's distance from the cylinders (the support
  // function of the hull, maximized over directions).
  double signedDistance(const Eigen::Vector2d& p_core) const;

 private:
  double supportGap(const Eigen::Vector2d& p, double angle) const;
  std::vector<Eigen::Vector2d> centers_;
  std::vector<double> radii_;
};

}  // namespace cws
