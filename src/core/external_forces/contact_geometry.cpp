// What touches what (contact_geometry.hpp).
#include "coil_winding_sim/core/external_forces/contact_geometry.hpp"

#include <algorithm>
#include <cmath>

#include "coil_winding_sim/core/scene/core_geometry.hpp"

namespace cws {

ContactGeometry::ContactGeometry(const WireConstants& c, const Scene& s, const RotatingCore& core)
    : c_(c), core_(core) {
  for (const CylinderParams& cyl : s.core.cylinders) {
    centers_core_.emplace_back(cyl.center_core.x(), cyl.center_core.y(), 0.0);
    radii_.push_back(cyl.radius);
  }
  centers_world_.resize(radii_.size());
  for (const FaceParams& f : coreFaces(s.core)) {
    const Eigen::Vector2d d = f.to_core - f.from_core;
    face_from_core_.emplace_back(f.from_core.x(), f.from_core.y(), 0.0);
    face_dir_core_.emplace_back(d.x() / d.norm(), d.y() / d.norm(), 0.0);
    face_normal_core_.emplace_back(d.y() / d.norm(), -d.x() / d.norm(), 0.0);
    face_length_.push_back(d.norm());
  }
  face_from_world_.resize(face_length_.size());
  face_dir_world_.resize(face_length_.size());
  face_normal_world_.resize(face_length_.size());
  // The core's swept radius: its farthest surface from the axis. Nothing of
  // the core body reaches a point beyond it and a wire diameter (a margin
  // over the radius a point touches it within).
  double swept = 0.0;
  for (const CylinderParams& cyl : s.core.cylinders) {
    swept = std::max(swept, cyl.center_core.norm() + cyl.radius);
  }
  for (const FaceParams& face : coreFaces(s.core)) {
    swept = std::max({swept, face.from_core.norm(), face.to_core.norm()});
  }
  body_reach_ = swept + 2.0 * c.radius;
  if (s.physics.flanges) {
    // The winding runs from half a wire diameter behind the port's start,
    // in the traverse's first direction, over the winding width.
    const Eigen::Vector3d axis = s.core.axis_world.normalized();
    const double side = s.process.traverse_pitch < 0.0 ? -1.0 : 1.0;
    const double first =
        (s.supply.port_position_world - s.core.position_world).dot(axis) - side * c.radius;
    const double spacing =
        s.core.flange_spacing > 0.0 ? s.core.flange_spacing : s.process.winding_width;
    flange_at_ = {first, first + side * spacing};
    flange_side_ = {side, -side};
    flange_radius_ = swept + s.core.flange_height;
    flange_slot_ = slots_++;
  }
  wire_base_ = static_cast<int>(radii_.size() + face_length_.size() + flange_at_.size());
  wire_slot_ = slots_;
  if (s.physics.wire_contact) {
    slots_ += kWireSlots;
    // Points closer along the wire than three diameters never count as
    // touching: the wire cannot bend that far back on itself.
    skip_points_ =
        std::max(3, static_cast<int>(std::ceil(3.0 * 2.0 * c.radius / c.segment_length)));
    // (Carried wire stretches little: half as long again is room enough.)
    carried_index_.reserve(c_.capacity, 2.0 * c.radius, 1.5 * c.segment_length);
    segment_dir_core_.assign(c_.capacity, Eigen::Vector3d::Zero());
    segment_length2_.assign(c_.capacity, 1.0);
    // Points move far less than a quarter diameter in a step relative to the
    // core: a list serves the step's queries.
    near_skin_ = 0.5 * c.radius;
    near_.assign(c_.capacity, NearList());
    near_segments_.assign(static_cast<std::size_t>(c_.capacity) * kNearMax, -1);
  }
}

bool ContactGeometry::flangeDisc(int j, const Eigen::Vector3d& p_world, double& depth,
                                 Eigen::Vector3d& n_world, Eigen::Matrix3d* dnormal) const {
  const Eigen::Vector3d& a = core_.axisWorld();
  const Eigen::Vector3d r = p_world - core_.originWorld();
  const double off = r.dot(a) - flange_at_[j];  // [m] from the disc's plane
  const Eigen::Vector3d rho = r - r.dot(a) * a;
  const double rho_n = rho.norm();
  if (rho_n <= flange_radius_) {
    // The face the point lies on (in the plane: the winding's).
    n_world = (off == 0.0 ? flange_side_[j] : (off > 0.0 ? 1.0 : -1.0)) * a;
    depth = c_.radius - std::abs(off);
    if (dnormal) dnormal->setZero();
    return true;
  }
  if (rho_n > flange_radius_ + c_.radius) return false;
  // The rim: from the circle's nearest point, radius R at u = rho / |rho|;
  // the normal turns with u about the axis (t = a x u) and with d.
  const Eigen::Vector3d u = rho / rho_n;
  const Eigen::Vector3d d = (rho_n - flange_radius_) * u + off * a;
  const double dist = d.norm();
  if (dist == 0.0) return false;  // (the centre on the rim's circle: no normal)
  n_world = d / dist;
  depth = c_.radius - dist;
  if (dnormal) {
    const Eigen::Vector3d t = a.cross(u);
    *dnormal = (Eigen::Matrix3d::Identity() - n_world * n_world.transpose() -
                (flange_radius_ / rho_n) * t * t.transpose()) /
               dist;
  }
  return true;
}

ContactGeometry::FlangeSide ContactGeometry::flangeSide(const Eigen::Vector3d& p_world) const {
  FlangeSide out;
  if (flange_at_.empty()) return out;
  const Eigen::Vector3d& a = core_.axisWorld();
  const Eigen::Vector3d r = p_world - core_.originWorld();
  const double along = r.dot(a);
  out.outside_m = -std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j < flange_at_.size(); ++j) {
    const double outside = -flange_side_[j] * (along - flange_at_[j]);
    if (outside > out.outside_m) out = {outside, static_cast<int>(j), 0.0, 0.0};
  }
  out.from_axis_m = (r - along * a).norm();
  out.reach_m = flange_radius_;
  return out;
}

void ContactGeometry::forgetCarriedWire(int n) {
  if (!carried_p_core_) return;
  carried_index_.clear();
  indexed_segments_ = 0;
  carried_reach_ = 0.0;
  for (int i = 0; i < n; ++i) near_[i].count = -1;
}

void ContactGeometry::place(double t) const {
  // Every evaluation of a Newton solve places the surfaces at the step's
  // end: the same angle, the same placement.
  const double angle = core_.angle(t);
  if (angle == placed_angle_) return;
  placed_angle_ = angle;
  rot_world_core_ = core_.rotationWorldCore(t);
  const Eigen::Matrix3d& rot = rot_world_core_;
  for (std::size_t j = 0; j < radii_.size(); ++j) {
    centers_world_[j] = core_.originWorld() + rot * centers_core_[j];
  }
  if (face_length_.empty()) return;
  for (std::size_t j = 0; j < face_length_.size(); ++j) {
    face_from_world_[j] = core_.originWorld() + rot * face_from_core_[j];
    face_dir_world_[j] = rot * face_dir_core_[j];
    face_normal_world_[j] = rot * face_normal_core_[j];
  }
}

int ContactGeometry::touch(const Eigen::Vector3d& p_world, double& h,
                           Eigen::Vector3d& n_world) const {
  int best = -1;
  h = 0.0;
  const Eigen::Vector3d& a = core_.axisWorld();
  // A point beyond the body's reach from the axis (the free span) touches
  // none of its surfaces.
  {
    const Eigen::Vector3d r = p_world - core_.originWorld();
    if ((r - r.dot(a) * a).squaredNorm() > body_reach_ * body_reach_) return best;
  }
  for (std::size_t j = 0; j < radii_.size(); ++j) {
    const Eigen::Vector3d d = p_world - centers_world_[j];
    const Eigen::Vector3d d_perp = d - d.dot(a) * a;
    // A cylinder clearly out of reach is passed by its squared distance
    // (most are: the point lies at one corner of the core); the others
    // are judged on the root, as before.
    const double reach = radii_[j] + c_.radius - h + 1e-9 * (radii_[j] + c_.radius);
    const double dist2 = d_perp.squaredNorm();
    if (reach <= 0.0 || dist2 > reach * reach) continue;
    const double dist = std::sqrt(dist2);
    const double depth = radii_[j] + c_.radius - dist;
    if (depth > h && dist > 0.0) {
      h = depth;
      n_world = d_perp / dist;
      best = static_cast<int>(j);
    }
  }
  // Faces: the point is over the face strip and at most a wire diameter
  // below its outer side (deeper points belong to the other side).
  for (std::size_t j = 0; j < face_length_.size(); ++j) {
    const Eigen::Vector3d d = p_world - face_from_world_[j];
    const double along = d.dot(face_dir_world_[j]);
    if (along < 0.0 || along > face_length_[j]) continue;
    const double depth = c_.radius - d.dot(face_normal_world_[j]);
    if (depth > h && depth < 2.0 * c_.radius) {
      h = depth;
      n_world = face_normal_world_[j];
      best = static_cast<int>(radii_.size() + j);
    }
  }
  return best;
}

bool ContactGeometry::touchAll(int i, const Eigen::Vector3d& p_world, const int* ref,
                               Touch* out) const {
  for (int s = 0; s < slots_; ++s) out[s].surface = -1;
  // A point farther from the core axis than any surface reaches (the free
  // span towards the port) touches none.
  {
    const Eigen::Vector3d& a = core_.axisWorld();
    const Eigen::Vector3d r = p_world - core_.originWorld();
    const double radial2 = (r - r.dot(a) * a).squaredNorm();
    const double reach = std::max(
        {body_reach_, flange_radius_ + (flange_at_.empty() ? 0.0 : c_.radius), carried_reach_});
    if (radial2 > reach * reach) return false;
  }
  out[0].surface = touch(p_world, out[0].h, out[0].n_world);
  bool any = out[0].surface >= 0;
  if (flange_slot_ < 0 && wire_slot_ == slots_) return any;
  const Eigen::Vector3d r = p_world - core_.originWorld();
  // Flanges: the deeper of the two discs (faces and rims).
  if (flange_slot_ >= 0) {
    Touch& t = out[flange_slot_];
    t.h = 0.0;
    for (std::size_t j = 0; j < flange_at_.size(); ++j) {
      double depth;
      Eigen::Vector3d n_world;
      if (flangeDisc(static_cast<int>(j), p_world, depth, n_world, nullptr) && depth > t.h) {
        t = Touch{static_cast<int>(radii_.size() + face_length_.size() + j), depth, n_world};
      }
    }
    any = any || t.surface >= 0;
  }
  if (wire_slot_ == slots_) return any;
  Touch runs[kMaxRuns];
  const int m = touchWire(i, rot_world_core_.transpose() * r, runs);
  if (m == 0) return any;
  // Each run keeps the slot whose surface it continues; new runs take the
  // free slots, deepest first. Where more runs touch than there are slots,
  // those held keep theirs: the deepest would otherwise take turns with
  // each other from one evaluation to the next (a point nested among wires
  // touches several at almost the same depth).
  bool used[kMaxRuns] = {};
  for (int s = wire_slot_; s < slots_; ++s) {
    if (ref[s] < wire_base_) continue;
    for (int g = 0; g < m; ++g) {
      if (!used[g] && sameSurface(runs[g].surface, ref[s])) {
        out[s] = runs[g];
        used[g] = true;
        break;
      }
    }
  }
  for (int g = 0; g < m; ++g) {
    if (used[g]) continue;
    for (int s = wire_slot_; s < slots_; ++s) {
      if (out[s].surface < 0) {
        out[s] = runs[g];
        break;
      }
    }
  }
  return true;
}

void ContactGeometry::syncCarriedWire() const {
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

const int* ContactGeometry::nearSegments(int i, const Eigen::Vector3d& p_core, int& count) const {
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

int ContactGeometry::touchWire(int i, const Eigen::Vector3d& p_core, Touch* runs) const {
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
  // (Surface ids number the segments of the whole wire: they stay as
  // buried wire retires, WireModel::retireBuriedWire.)
  const int base = wire_base_ + c_.retired;
  for (int a = 0; a < hits; ++a) {
    if (m > 0 && hit[a] - hit[a - 1] <= kSameRun) {
      if (depth[a] > all[m - 1].h) all[m - 1] = Run{base + hit[a], depth[a], normal[a]};
      continue;
    }
    all[m++] = Run{base + hit[a], depth[a], normal[a]};
  }
  // The deepest runs, in the world frame.
  std::sort(all, all + m, [](const Run& x, const Run& y) { return x.h > y.h; });
  m = std::min(m, kMaxRuns);
  for (int g = 0; g < m; ++g) runs[g] = Touch{all[g].surface, all[g].h, rot_world_core_ * all[g].n};
  return m;
}

bool ContactGeometry::planarSurface(const PlanarState& s, int surface, const Eigen::Vector2d& x,
                                    Eigen::Vector2d& normal, double& depth,
                                    Eigen::Matrix2d& dnormal) const {
  const int cylinders = static_cast<int>(radii_.size());
  if (surface < cylinders) {
    // Distance from the cylinder's axis (the plane normal).
    const Eigen::Vector2d r = x - s.plane.toPlane(centers_world_[surface]);
    const double dist = r.norm();
    if (dist == 0.0) return false;
    normal = r / dist;
    depth = radii_[surface] + c_.radius - dist;
    dnormal = (Eigen::Matrix2d::Identity() - normal * normal.transpose()) / dist;
    return true;
  }
  const int f = surface - cylinders;
  normal = s.plane.vectorToPlane(face_normal_world_[f]);
  depth = c_.radius - (x - s.plane.toPlane(face_from_world_[f])).dot(normal);
  dnormal.setZero();
  return true;
}

bool ContactGeometry::spatialSurface(int i, int surface, const Eigen::Vector3d& p_world,
                                     Eigen::Vector3d& normal_world, double& depth,
                                     Eigen::Matrix3d* dnormal) const {
  const int cylinders = static_cast<int>(radii_.size());
  if (surface < cylinders) {
    // Distance from the cylinder's axis (the core axis through its centre).
    const Eigen::Vector3d& a = core_.axisWorld();
    const Eigen::Vector3d d = p_world - centers_world_[surface];
    const Eigen::Vector3d d_perp = d - d.dot(a) * a;
    const double dist = d_perp.norm();
    if (dist == 0.0) return false;
    normal_world = d_perp / dist;
    depth = radii_[surface] + c_.radius - dist;
    if (dnormal) {
      *dnormal = (Eigen::Matrix3d::Identity() - a * a.transpose() -
                  normal_world * normal_world.transpose()) /
                 dist;
    }
    return true;
  }
  if (surface >= wire_base_) {
    // The nearest of the carried segments j-1..j+1 (as capsules): inside
    // one, the distance from its line; past its ends, from the end point.
    // (A segment of retired wire, j < 0, is out of reach: no segment below.)
    const int j = surface - wire_base_ - c_.retired;
    const int last = lastWireSegment(i);
    const Eigen::Vector3d p_core = rot_world_core_.transpose() * (p_world - core_.originWorld());
    // (Compared by their squared distances: one root, for the nearest.)
    double best2 = -1.0;
    int nearest = -1;
    bool nearest_inside = false;
    Eigen::Vector3d n_core = Eigen::Vector3d::Zero(), t_core = Eigen::Vector3d::Zero();
    for (int m = std::max(1, j - 1); m <= std::min(j + 1, last); ++m) {
      Eigen::Vector3d offset;
      bool inside;
      const double dist2 = segmentOffset(m, p_core, offset, inside);
      if (best2 >= 0.0 && dist2 >= best2) continue;
      best2 = dist2;
      nearest = m;
      nearest_inside = inside;
      n_core = offset;
    }
    const double best = nearest >= 0 ? std::sqrt(best2) : -1.0;
    if (best <= 0.0) return false;
    n_core /= best;
    normal_world = rot_world_core_ * n_core;
    depth = 2.0 * c_.radius - best;
    if (dnormal) {
      if (nearest_inside) t_core = segment_dir_core_[nearest].normalized();
      const Eigen::Vector3d t_world = rot_world_core_ * t_core;
      *dnormal = (Eigen::Matrix3d::Identity() - t_world * t_world.transpose() -
                  normal_world * normal_world.transpose()) /
                 best;
    }
    return true;
  }
  if (dnormal) dnormal->setZero();
  const int f = surface - cylinders;
  if (f >= static_cast<int>(face_length_.size())) {
    // A flange as touchAll finds it, face and rim: a flange that pushed as
    // its whole plane moved a point beyond its reach, where touchAll found
    // no flange, and the flag changed at every recheck.
    return flangeDisc(f - static_cast<int>(face_length_.size()), p_world, depth, normal_world,
                      dnormal);
  }
  normal_world = face_normal_world_[f];
  depth = c_.radius - (p_world - face_from_world_[f]).dot(normal_world);
  return true;
}

}  // namespace cws
