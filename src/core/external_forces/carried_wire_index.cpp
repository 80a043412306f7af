#include "coil_winding_sim/core/external_forces/carried_wire_index.hpp"

#include <algorithm>
#include <cmath>

namespace cws {

void CarriedWireIndex::reserve(int segments, double reach, double longest) {
  cell_ = reach;
  // A segment's box, grown by the reach, spans at most ceil(u) + 3 cells
  // along an axis where the segment spans u cells: the most cells over the
  // ways a segment of at most `longest` can lie (ceil(u) = k needs
  // (k - 1)^2 of the squared length in cells).
  const double length = longest / reach;
  const int most = static_cast<int>(std::ceil(length));
  std::size_t per_segment = 1;
  for (int kx = 0; kx <= most; ++kx) {
    for (int ky = 0; ky <= most; ++ky) {
      for (int kz = 0; kz <= most; ++kz) {
        auto need = [](int k) { return k > 1 ? double(k - 1) * (k - 1) : 0.0; };
        if (need(kx) + need(ky) + need(kz) >= length * length) continue;
        per_segment = std::max<std::size_t>(per_segment, std::size_t(kx + 3) * (ky + 3) * (kz + 3));
      }
    }
  }
  const std::size_t nodes = static_cast<std::size_t>(std::max(segments, 1)) * per_segment;
  nodes_.reserve(nodes);
  // Buckets for the cells a segment of a coil fills (about 36 for a
  // segment as long as the reach: 4 x 3 x 3), at most twice that: short
  // chains, and no bucket array sized for the bound.
  const std::size_t typical = static_cast<std::size_t>(std::max(segments, 1)) * 32;
  int bits = 1;
  while ((std::size_t{1} << bits) < typical && bits < 40) ++bits;
  shift_ = 64 - bits;
  heads_.assign(std::size_t{1} << bits, -1);
  clear();
}

void CarriedWireIndex::clear() {
  // Only the buckets in use are reset.
  for (const Node& node : nodes_) heads_[bucketOf(node.key)] = -1;
  nodes_.clear();
  segments_ = 0;
  ++version_;
}

std::int64_t CarriedWireIndex::cellOf(double x) const {
  return static_cast<std::int64_t>(std::floor(x / cell_));
}

void CarriedWireIndex::add(int j, const Eigen::Vector3d& a_core, const Eigen::Vector3d& b_core) {
  const Eigen::Vector3d lo = a_core.cwiseMin(b_core).array() - cell_;
  const Eigen::Vector3d hi = a_core.cwiseMax(b_core).array() + cell_;
  for (std::int64_t ix = cellOf(lo.x()); ix <= cellOf(hi.x()); ++ix) {
    for (std::int64_t iy = cellOf(lo.y()); iy <= cellOf(hi.y()); ++iy) {
      for (std::int64_t iz = cellOf(lo.z()); iz <= cellOf(hi.z()); ++iz) {
        const std::int64_t key = keyOf(ix, iy, iz);
        int& head = heads_[bucketOf(key)];
        nodes_.push_back(Node{key, j, head});
        head = static_cast<int>(nodes_.size()) - 1;
      }
    }
  }
  segments_ = std::max(segments_, j + 1);
  ++version_;
}

}  // namespace cws
