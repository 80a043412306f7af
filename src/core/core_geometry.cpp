#include "coil_winding_sim/core/core_geometry.hpp"

#include <cmath>
#include <limits>

namespace cws {

CoreSection::CoreSection(const std::vector<CylinderParams>& cylinders) {
  for (const CylinderParams& c : cylinders) {
    centers_.push_back(c.center_core);
    radii_.push_back(c.radius);
  }
}

// u . p - h(u) for the unit direction u at `angle`, where h is the support
// function of the union of discs: h(u) = max_j (u . c_j + R_j).
double CoreSection::supportGap(const Eigen::Vector2d& p, double angle) const {
  const Eigen::Vector2d u(std::cos(angle), std::sin(angle));
  double h = -std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j < centers_.size(); ++j) h = std::max(h, u.dot(centers_[j]) + radii_[j]);
  return u.dot(p) - h;
}

double CoreSection::signedDistance(const Eigen::Vector2d& p) const {
  // For a convex set K, max over unit u of (u . p - h_K(u)) is the distance
  // to K outside it and minus the distance to its boundary inside. Coarse
  // scan, then golden-section refinement around the best direction.
  constexpr int kSamples = 720;
  constexpr double kTwoPi = 6.283185307179586;
  double best = -std::numeric_limits<double>::infinity(), best_angle = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    const double a = kTwoPi * i / kSamples;
    const double g = supportGap(p, a);
    if (g > best) {
      best = g;
      best_angle = a;
    }
  }
  double lo = best_angle - kTwoPi / kSamples, hi = best_angle + kTwoPi / kSamples;
  const double phi = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = hi - phi * (hi - lo), x2 = lo + phi * (hi - lo);
  double f1 = supportGap(p, x1), f2 = supportGap(p, x2);
  for (int it = 0; it < 60; ++it) {
    if (f1 > f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - phi * (hi - lo);
      f1 = supportGap(p, x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + phi * (hi - lo);
      f2 = supportGap(p, x2);
    }
  }
  return std::max(best, std::max(f1, f2));
}

}  // namespace cws
