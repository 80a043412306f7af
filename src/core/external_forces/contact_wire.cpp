// Contact against the wound wire the core carries (physics.wire_contact):
// the carried segments as capsules of the wire's radius, found through a
// grid of the core frame (carried_wire_index.hpp), and grouped into runs so
// that a point lying on a turn feels it once, and a point in the groove of
// two turns feels both.
#include <algorithm>
#include <cmath>

#include "coil_winding_sim/core/external_forces/contact.hpp"

namespace cws {

void Contact::syncCarriedWire() const {
  if (!carried_p_core_) return;
  // Carried segments j join carried points j and j + 1 < c.first (from
  // point 1: point 0 is the clamp); they are rigid in the core frame while
  // carried. A release (c.first fell) moves some of them again: all are
  // hashed anew.
  const int carried = std::max(1, c_.first - 1);
  if (carried < indexed_segments_) {
    carried_index_.clear();
    indexed_segments_ = 0;
    carried_reach_ = 0.0;
  }
  const std::vector<Eigen::Vector3d>& p = *carried_p_core_;
  for (int j = std::max(1, indexed_segments_); j < carried; ++j) {
    carried_index_.add(j, p[j], p[j + 1]);
    // The segment's direction and squared length, read by every query.
    segment_dir_core_[j] = p[j + 1] - p[j];
    segment_length2_[j] = segment_dir_core_[j].squaredNorm();
    // (The core axis is z in the core frame.)
    for (const Eigen::Vector3d* e : {&p[j], &p[j + 1]}) {
      carried_reach_ = std::max(carried_reach_, e->head<2>().norm() + 2.0 * c_.radius);
    }
  }
  indexed_segments_ = carried;
}

const int* Contact::nearSegments(int i, const Eigen::Vector3d& p_core, int& count) const {
  NearList& list = near_[i];
  const std::int64_t cell = carried_index_.cellKey(p_core);
  if (list.count >= 0 && list.version == carried_index_.version() && list.cell == cell &&
      (p_core - list.p_core).squaredNorm() <= near_skin_ * near_skin_) {
    count = list.count;
    return &near_segments_[static_cast<std::size_t>(i) * kNearMax];
  }
  // Made anew: the cell's segments that may come within the reach while the
  // point stays within the skin.
  int* out = &near_segments_[static_cast<std::size_t>(i) * kNearMax];
  const double keep = 2.0 * c_.radius + near_skin_;
  const double keep2 = keep * keep * (1.0 + 1e-9);
  list = NearList{p_core, cell, carried_index_.version(), 0};
  carried_index_.forEachNear(p_core, [&](int j) {
    if (list.count < 0) return;
    Eigen::Vector3d offset;
    bool inside;
    if (segmentOffset(j, p_core, offset, inside) > keep2) return;
    if (list.count == kNearMax) {
      list.count = -1;
      return;
    }
    out[list.count++] = j;
  });
  count = list.count;
  return list.count >= 0 ? out : nullptr;
}

int Contact::touchWire(int i, const Eigen::Vector3d& p_core, Touch* runs) const {
  const int last = lastWireSegment(i);
  if (last < 0 || !carried_p_core_) return 0;
  // The touching segments, by index (a point touches few).
  constexpr int kMaxHits = 24;
  int hit[kMaxHits];
  double depth[kMaxHits];
  Eigen::Vector3d normal[kMaxHits];
  int hits = 0;
  const double reach = 2.0 * c_.radius;
  // (Most segments of the cell lie beyond the reach: their squared
  // distance rejects them before a root is taken.)
  const double beyond2 = reach * reach * (1.0 + 1e-9);
  auto visit = [&](int j) {
    if (j > last || hits == kMaxHits) return;
    Eigen::Vector3d n;
    bool inside;
    const double dist2 = segmentOffset(j, p_core, n, inside);
    if (dist2 > beyond2) return;
    const double dist = std::sqrt(dist2);
    if (dist > 0.0) n /= dist;
    if (dist >= reach || dist == 0.0) return;
    hit[hits] = j;
    depth[hits] = reach - dist;
    normal[hits] = n;
    ++hits;
  };
  int near = 0;
  const int* list = nearSegments(i, p_core, near);
  if (list) {
    for (int k = 0; k < near; ++k) visit(list[k]);
  } else {
    carried_index_.forEachNear(p_core, visit);
  }
  if (hits == 0) return 0;
  // Sort by index (insertion: few), then split into runs of segments at
  // most kSameRun apart; each run's deepest segment stands for it.
  for (int a = 1; a < hits; ++a) {
    for (int b = a; b > 0 && hit[b - 1] > hit[b]; --b) {
      std::swap(hit[b - 1], hit[b]);
      std::swap(depth[b - 1], depth[b]);
      std::swap(normal[b - 1], normal[b]);
    }
  }
  // (Scratch left uninitialized: Touch's defaults would be written for all
  // kMaxHits on every query.)
  struct Run {
    int surface;
    double h;
    Eigen::Vector3d n;
  };
  Run all[kMaxHits];
  int m = 0;
  for (int a = 0; a < hits; ++a) {
    if (m > 0 && hit[a] - hit[a - 1] <= kSameRun) {
      if (depth[a] > all[m - 1].h) all[m - 1] = Run{wire_base_ + hit[a], depth[a], normal[a]};
      continue;
    }
    all[m++] = Run{wire_base_ + hit[a], depth[a], normal[a]};
  }
  // The deepest runs, in the world frame.
  std::sort(all, all + m, [](const Run& x, const Run& y) { return x.h > y.h; });
  m = std::min(m, kMaxRuns);
  for (int g = 0; g < m; ++g) runs[g] = Touch{all[g].surface, all[g].h, rot_world_core_ * all[g].n};
  return m;
}

}  // namespace cws
