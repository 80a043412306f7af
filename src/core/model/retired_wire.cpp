#include "coil_winding_sim/core/model/retired_wire.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace cws {

void RetiredWire::exportPoints(std::vector<double>& out) const {
  out.reserve(out.size() + kValuesPerPoint * points_.size());
  for (const RetiredPoint& p : points_) {
    out.insert(out.end(), p.p_core.data(), p.p_core.data() + 3);
    out.push_back(p.stand_off_m);
    out.push_back(p.axial_force_N);
    out.push_back(p.curvature_1pm);
    out.push_back(p.plastic_curvature_1pm);
    out.push_back(p.twist_rad_per_m);
    out.push_back((p.in_contact ? 1.0 : 0.0) + (p.stick ? 2.0 : 0.0));
    out.insert(out.end(), p.surface, p.surface + RetiredPoint::kSlots);
    out.push_back(p.segment_plastic_strain);
  }
}

void RetiredWire::importPoints(const std::vector<double>& in) {
  if (in.size() % kValuesPerPoint != 0) {
    throw std::runtime_error("snapshot has " + std::to_string(in.size()) +
                             " retired-wire values, not " + std::to_string(kValuesPerPoint) +
                             " per point");
  }
  std::vector<RetiredPoint> points(in.size() / kValuesPerPoint);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double* v = in.data() + kValuesPerPoint * i;
    for (int d = 0; d < kValuesPerPoint; ++d) {
      if (!std::isfinite(v[d])) throw std::runtime_error("snapshot retired wire is not finite");
    }
    const int flags = static_cast<int>(v[8]);
    if (v[8] != flags || flags < 0 || flags > 3) {
      throw std::runtime_error("snapshot retired wire has contact flags " + std::to_string(v[8]) +
                               " (0 to 3)");
    }
    RetiredPoint& p = points[i];
    p.p_core = Eigen::Vector3d(v[0], v[1], v[2]);
    p.stand_off_m = v[3];
    p.axial_force_N = v[4];
    p.curvature_1pm = v[5];
    p.plastic_curvature_1pm = v[6];
    p.twist_rad_per_m = v[7];
    p.in_contact = (flags & 1) != 0;
    p.stick = (flags & 2) != 0;
    for (int s = 0; s < RetiredPoint::kSlots; ++s) {
      const double id = v[9 + s];
      if (id != std::floor(id) || id < -1.0 || id > 1e9) {
        throw std::runtime_error("snapshot retired wire has contact surface " + std::to_string(id) +
                                 " (an id, or -1)");
      }
      p.surface[s] = static_cast<int>(id);
    }
    p.segment_plastic_strain = v[9 + RetiredPoint::kSlots];
  }
  // (Into the store's own records: what it reserved stays reserved.)
  points_.assign(points.begin(), points.end());
  // The largest stand-off, as the retirements found it (the first of equals).
  max_stand_off_m = 0.0;
  max_stand_off_point = -1;
  for (int i = 0; i < size(); ++i) {
    if (points_[i].stand_off_m > max_stand_off_m || max_stand_off_point < 0) {
      max_stand_off_m = std::max(0.0, points_[i].stand_off_m);
      max_stand_off_point = i;
    }
  }
}

void RetiredWire::clear() {
  points_.clear();
  elastic_J = plastic_J = 0.0;
  max_stand_off_m = 0.0;
  max_stand_off_point = -1;
}

}  // namespace cws
