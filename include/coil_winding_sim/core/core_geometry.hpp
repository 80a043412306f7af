// Plane geometry of the core's cross-section: the convex hull of its
// cylinders (the winding surface the wire lies on) and distances to it.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "coil_winding_sim/core/scene.hpp"

namespace cws {

class CoreSection {
 public:
  explicit CoreSection(const std::vector<CylinderParams>& cylinders);

  // Signed distance [m] of the core-frame point (x, y) from the convex hull
  // of the cylinders' discs: positive outside, negative inside. Exact up to
  // about 1e-9 of the point's distance from the cylinders (the support
  // function of the hull, maximized over directions).
  double signedDistance(const Eigen::Vector2d& p_core) const;

 private:
  double supportGap(const Eigen::Vector2d& p, double angle) const;
  std::vector<Eigen::Vector2d> centers_;
  std::vector<double> radii_;
};

}  // namespace cws
