// Wound wire retired from the live arrays (WireModel::retireBuriedWire):
// carried wire buried under later turns, which nothing integrated can reach
// any more. It turns rigidly with the core, so its pose in the core frame
// is all its motion; its report figures are those it had when it retired.
// About 100 bytes a point, where a live point takes some 1.6 kB of state,
// Newton system and contact slots: a coil of 10,000 turns fits.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace cws {

// A point's figures in the reports (wire.csv, the markers).
struct PointFigures {
  double axial_force_N = 0.0;          // segment ending at the point (point 0: segment 0)
  double curvature_1pm = 0.0;          // |bending curvature| at the point's joint
  double plastic_curvature_1pm = 0.0;  // |permanent bending curvature| there
  double twist_rad_per_m = 0.0;        // twist rate there
  bool in_contact = false;             // touching the core or what it carries
  bool stick = false;                  // held by static friction
};

// A retired point: its figures when it retired, and where it lies.
struct RetiredPoint : PointFigures {
  Eigen::Vector3d p_core = Eigen::Vector3d::Zero();  // position, core frame [m]
  double stand_off_m = 0.0;                          // from the winding surface [m]
  // The contact's surface per slot at retirement (Contact::surface; -1:
  // none), for the layers the coil report finds.
  static constexpr int kSlots = 6;
  int surface[kSlots] = {-1, -1, -1, -1, -1, -1};
  // Permanent axial strain of the segment from this point to the next
  // (the stretching law's strain at zero force) [-].
  double segment_plastic_strain = 0.0;
};

class RetiredWire {
 public:
  // Room for `points` retired points without allocating (more grow the
  // store at a retirement, between steps).
  void reserve(int points) { points_.reserve(points); }
  int size() const { return static_cast<int>(points_.size()); }
  int capacity() const { return static_cast<int>(points_.capacity()); }
  const RetiredPoint& operator[](int i) const { return points_[i]; }
  void append(const RetiredPoint& p) { points_.push_back(p); }

  // The retired wire's recoverable energy and plastic work [J] (constant:
  // it no longer deforms).
  double elastic_J = 0.0, plastic_J = 0.0;
  // Its largest stand-off from the winding surface [m] and the point (-1:
  // none), for the bulging report.
  double max_stand_off_m = 0.0;
  int max_stand_off_point = -1;

  // Snapshot form: kValuesPerPoint numbers per point.
  static constexpr int kValuesPerPoint = 10 + RetiredPoint::kSlots;
  void exportPoints(std::vector<double>& out) const;
  // Throws std::runtime_error naming what is wrong (the store is unchanged).
  void importPoints(const std::vector<double>& in);
  void clear();

 private:
  std::vector<RetiredPoint> points_;
};

}  // namespace cws
