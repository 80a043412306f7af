#include "coil_winding_sim/core/external_forces/carried_wire_index.hpp"

#include <algorithm>
#include <cmath>

namespace cws {

void CarriedWireIndex::reserve(int segments, double reach, double longest) {
  cell_ = reach;
  // A segment's box grown by the reach spans at most ceil(longest / reach)
  // + 3 cells along each axis; buckets about twice the nodes.
  const std::size_t per_axis = static_cast<std::size_t>(std::ceil(longest / reach)) + 3;
  const std::size_t nodes =
      static_cast<std::size_t>(std::max(segments, 1)) * per_axis * per_axis * per_axis;
  nodes_.reserve(nodes);
  int bits = 1;
  while ((std::size_t{1} << bits) < 2 * nodes && bits < 40) ++bits;
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
