// Broad phase of contact against the wound wire the core carries: the
// carried segments are rigid in the core frame, so they are hashed once,
// into a uniform grid of that frame, when the core takes them on; a query
// then reads one cell. Cost per query: the segments near that cell, not
// the whole coil.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace cws {

class CarriedWireIndex {
 public:
  // Storage for `segments` segments up to `longest` [m] long (more would
  // allocate); `reach` is the largest distance [m] a query point may have
  // from a segment it touches (the cell size).
  void reserve(int segments, double reach, double longest);
  // Forgets every segment.
  void clear();
  // Segment j from a_core to b_core [m], core frame: hashed into every cell
  // its box, grown by the reach, overlaps.
  void add(int j, const Eigen::Vector3d& a_core, const Eigen::Vector3d& b_core);
  // Calls visit(j) for each segment j that may lie within the reach of
  // p_core (each once): those hashed into p_core's cell.
  template <class Visit>
  void forEachNear(const Eigen::Vector3d& p_core, Visit&& visit) const {
    if (nodes_.empty()) return;
    const std::int64_t key = cellKey(p_core);
    for (int k = heads_[bucketOf(key)]; k >= 0; k = nodes_[k].next) {
      if (nodes_[k].key == key) visit(nodes_[k].segment);
    }
  }
  int segments() const { return segments_; }
  // The cell p_core lies in: two queries in the same cell visit the same
  // segments in the same order while version() stays.
  std::int64_t cellKey(const Eigen::Vector3d& p_core) const {
    return keyOf(cellOf(p_core.x()), cellOf(p_core.y()), cellOf(p_core.z()));
  }
  // Counts every change of the hashed segments (an add, a clear).
  unsigned version() const { return version_; }

 private:
  struct Node {
    std::int64_t key;
    int segment, next;
  };
  std::int64_t cellOf(double x) const;
  static std::int64_t keyOf(std::int64_t ix, std::int64_t iy, std::int64_t iz) {
    constexpr std::int64_t kSpan = 1 << 20;  // cells per axis either side
    return ((ix + kSpan) << 42) | ((iy + kSpan) << 21) | (iz + kSpan);
  }
  std::size_t bucketOf(std::int64_t key) const {
    return static_cast<std::size_t>((static_cast<std::uint64_t>(key) * 0x9E3779B97F4A7C15ull) >>
                                    shift_);
  }

  double cell_ = 1.0;  // cell size [m]
  int shift_ = 63;     // 64 - log2(buckets)
  int segments_ = 0;
  unsigned version_ = 0;
  std::vector<int> heads_;
  std::vector<Node> nodes_;
};

}  // namespace cws
