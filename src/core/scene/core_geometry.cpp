#include "coil_winding_sim/core/scene/core_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "scene_detail.hpp"

namespace cws {

using detail::fmt;

void applyCoreShape(CoreParams& core) {
  const CoreShapeParams& shape = core.shape;
  if (shape.kind != "rounded_rectangle") return;
  const double w = shape.width, h = shape.height, r = shape.corner_radius;
  if (!(w > 0.0))
    throw SceneError("core.shape.width", "a rounded_rectangle needs a width above 0 m");
  if (!(h > 0.0)) {
    throw SceneError("core.shape.height", "a rounded_rectangle needs a height above 0 m");
  }
  if (!(r > 0.0)) {
    throw SceneError("core.shape.corner_radius",
                     "a rounded_rectangle needs corners of a radius above 0 m (wire bent over a "
                     "sharp edge has no contact normal there)");
  }
  if (!(2.0 * r <= std::min(w, h))) {
    throw SceneError("core.shape.corner_radius",
                     fmt(r) + " m is more than half the shorter side (" + fmt(std::min(w, h)) +
                         " m); at most " + fmt(0.5 * std::min(w, h)) + " m");
  }
  // The corner cylinders' centres; a side of 2 r (to rounding) has one.
  double x = 0.5 * w - r, y = 0.5 * h - r;
  if (x < 1e-9 * r) x = 0.0;
  if (y < 1e-9 * r) y = 0.0;
  std::vector<Eigen::Vector2d> centers;
  for (const Eigen::Vector2d& c : {Eigen::Vector2d(x, y), Eigen::Vector2d(-x, y),
                                   Eigen::Vector2d(-x, -y), Eigen::Vector2d(x, -y)}) {
    if (std::find(centers.begin(), centers.end(), c) == centers.end()) centers.push_back(c);
  }
  core.cylinders.clear();
  for (const Eigen::Vector2d& c : centers) core.cylinders.push_back(CylinderParams{c, r});
  core.faces.clear();
  core.hull_faces = core.cylinders.size() >= 2;
}

std::vector<FaceParams> coreFaces(const CoreParams& core) {
  std::vector<FaceParams> faces = core.faces;
  const std::vector<CylinderParams>& cyl = core.cylinders;
  if (!core.hull_faces || cyl.size() < 2) return faces;
  // Convex hull of the centres (monotone chain), counter-clockwise.
  std::vector<int> idx(cyl.size());
  for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = static_cast<int>(i);
  std::sort(idx.begin(), idx.end(), [&](int a, int b) {
    const Eigen::Vector2d &p = cyl[a].center_core, &q = cyl[b].center_core;
    return p.x() < q.x() || (p.x() == q.x() && p.y() < q.y());
  });
  auto cross = [&](int o, int a, int b) {
    const Eigen::Vector2d u = cyl[a].center_core - cyl[o].center_core;
    const Eigen::Vector2d v = cyl[b].center_core - cyl[o].center_core;
    return u.x() * v.y() - u.y() * v.x();
  };
  std::vector<int> hull;
  for (int pass = 0; pass < 2; ++pass) {
    const std::size_t base = hull.size();
    for (int i : idx) {
      while (hull.size() >= base + 2 && cross(hull[hull.size() - 2], hull.back(), i) <= 0.0) {
        hull.pop_back();
      }
      hull.push_back(i);
    }
    hull.pop_back();
    std::reverse(idx.begin(), idx.end());
  }
  // Outer common tangent of consecutive hull cylinders: the outward normal n
  // (right of the edge) with n . c1 + R1 = n . c2 + R2.
  for (std::size_t k = 0; k < hull.size() && hull.size() >= 2; ++k) {
    const CylinderParams& a = cyl[hull[k]];
    const CylinderParams& b = cyl[hull[(k + 1) % hull.size()]];
    const Eigen::Vector2d d = b.center_core - a.center_core;
    const double len = d.norm();
    const Eigen::Vector2d t = d / len, right(t.y(), -t.x());
    const double alpha = (a.radius - b.radius) / len;
    const Eigen::Vector2d n = alpha * t + std::sqrt(std::max(0.0, 1.0 - alpha * alpha)) * right;
    faces.push_back(FaceParams{a.center_core + a.radius * n, b.center_core + b.radius * n});
  }
  return faces;
}

CoreSection::CoreSection(const CoreParams& core) {
  for (const CylinderParams& c : core.cylinders) {
    centers_.push_back(c.center_core);
    radii_.push_back(c.radius);
  }
  // Face ends count as discs of radius zero.
  for (const FaceParams& f : core.faces) {
    for (const Eigen::Vector2d& p : {f.from_core, f.to_core}) {
      centers_.push_back(p);
      radii_.push_back(0.0);
    }
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
