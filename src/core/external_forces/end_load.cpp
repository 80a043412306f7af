#include "coil_winding_sim/core/external_forces/end_load.hpp"

#include "coil_winding_sim/core/assembly/planar_assembly.hpp"
#include "coil_winding_sim/core/assembly/spatial_assembly.hpp"
#include "coil_winding_sim/core/base/quaternion.hpp"

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

void EndLoad::addForces(double t, const WireKinematics& k, WireForces& f) const {
  Eigen::Vector3d force_world, moment_world;
  loadAt(t, force_world, moment_world);
  const int tip = c_.n - 1;
  f.f_world.col(tip) += force_world;
  f.f_work_world.col(tip) += force_world;
  // A world moment m acts on q as 2 E(q)^T m; its power is m . omega_world.
  const Eigen::Vector4d fq = 2.0 * quat::E(k.q.col(tip)).transpose() * moment_world;
  f.f_q.col(tip) += fq;
  f.fq_work.col(tip) += fq;
}

void EndLoad::addPlanarForces(const PlanarState& s, PlanarAssembly& a) const {
  Eigen::Vector3d force_world, moment_world;
  loadAt(s.t, force_world, moment_world);
  const int tip = s.n - 1;
  const Eigen::Vector2d f = s.plane.vectorToPlane(force_world);
  a.addForce(tip, f);
  a.f_work.col(tip) += f;
  // The moment about n turns the tip's frame, that is its segment: forces
  // m dphi/dx on its two points.
  const double m = moment_world.dot(s.plane.n_world);
  if (m == 0.0) return;
  const Eigen::Vector2d d = s.segment(tip - 1);
  const Eigen::Vector2d g = m * planar::angleGradient(d);
  a.addForce(tip, g);
  a.addForce(tip - 1, -g);
  a.f_work.col(tip) += g;
  if (tip - 1 >= s.first) a.f_work.col(tip - 1) -= g;
  const Eigen::Matrix2d h = m * planar::angleHessian(d);
  a.addStiffness(tip, tip, h);
  a.addStiffness(tip, tip - 1, -h);
  a.addStiffness(tip - 1, tip, -h);
  a.addStiffness(tip - 1, tip - 1, h);
}

void EndLoad::addSpatialForces(const SpatialState& s, SpatialAssembly& a) const {
  Eigen::Vector3d force_world, moment_world;
  loadAt(s.t, force_world, moment_world);
  const int tip = s.n - 1;
  a.addForce(tip, force_world);
  a.f_work.col(tip) += force_world;
  if (moment_world.isZero()) return;
  // The moment as 2 E(q)^T m on the tip's quaternion (linear in q).
  const Eigen::Vector4d fq = 2.0 * quat::E(s.q.col(tip)).transpose() * moment_world;
  a.addQForce(tip, fq);
  a.fq_work.col(tip) += fq;
  Eigen::Matrix4d dq;
  for (int k = 0; k < 4; ++k) {
    dq.col(k) = 2.0 * quat::E(quat::Vec4::Unit(k)).transpose() * moment_world;
  }
  a.addStiffnessQQ(tip, tip, dq);
}

}  // namespace cws
