#include "coil_winding_sim/core/external_forces/end_load.hpp"

namespace cws {

void EndLoad::loadAt(double t, Eigen::Vector3d& force_world, Eigen::Vector3d& moment_world) const {
  // Before the first keyframe its values hold, as after the last.
  if (t <= schedule_.front().time) {
    force_world = schedule_.front().force_world;
    moment_world = schedule_.front().moment_world;
    return;
  }
  for (std::size_t i = 1; i < schedule_.size(); ++i) {
    const LoadKeyframe& a = schedule_[i - 1];
    const LoadKeyframe& b = schedule_[i];
    if (t <= b.time) {
      const double s = (t - a.time) / (b.time - a.time);
      force_world = (1.0 - s) * a.force_world + s * b.force_world;
      moment_world = (1.0 - s) * a.moment_world + s * b.moment_world;
      return;
    }
  }
  force_world = schedule_.back().force_world;
  moment_world = schedule_.back().moment_world;
}

}  // namespace cws
