// Contact geometry: which surfaces a mass point touches, how deep and
// along which normal. The core's cylinders and faces placed at the core's
// angle, its flanges, and the wound wire the core carries
// (physics.wire_contact): the carried segments as capsules of the wire's
// radius, found through a grid of the core frame (carried_wire_index.hpp),
// grouped into runs so that a point lying on a turn feels it once, and a
// point in the groove of two turns feels both. Each point has one slot per
// surface kind (the core body, a flange, the wire runs). The law of the
// force on a touch, and the state of stick and slip, are Contact's
// (contact.hpp). SI units: m.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <vector>

#include "coil_winding_sim/core/assembly/planar_assembly.hpp"
#include "coil_winding_sim/core/base/wire_types.hpp"
#include "coil_winding_sim/core/external_forces/carried_wire_index.hpp"
#include "coil_winding_sim/core/machine/rotating_core.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

class ContactGeometry {
 public:
  ContactGeometry(const WireConstants& c, const Scene& s, const RotatingCore& core);

  // With physics.wire_contact: the carried wire's poses in the core frame
  // (the model's, valid below c.first; kept by reference).
  void attachCarriedWire(const std::vector<Eigen::Vector3d>& p_core) { carried_p_core_ = &p_core; }

  // Slots per point: the core body, a flange, and the wire runs (a point
  // in a disordered coil can rest on four wires at once).
  static constexpr int kWireSlots = 4;
  static constexpr int kMaxSlots = 2 + kWireSlots;
  // Slots per point and their roles; surface ids: cylinders, faces,
  // flanges, then the carried segments from wireBase() (segment j of the
  // whole wire, retired points included: wireBase() + j).
  int slots() const { return slots_; }
  int flangeSlot() const { return flange_slot_; }  // -1: no flanges
  int wireSlot() const { return wire_slot_; }      // slots(): no wire contact
  int wireBase() const { return wire_base_; }
  // The points next to a point along the wire that never count as
  // touching it.
  int skipPoints() const { return skip_points_; }
  // Segments point i may touch: carried (both ends below c.first), and not
  // its neighbours along the wire. Largest such j (-1: none).
  int lastWireSegment(int i) const { return std::min(c_.first - 2, i - 1 - skip_points_); }
  // Is `a` the same surface as `b` for stick (a run of the carried wire
  // counts as one)?
  bool sameSurface(int a, int b) const {
    if (a == b) return true;
    return a >= wire_base_ && b >= wire_base_ && std::abs(a - b) <= kSameRun;
  }
  static constexpr int kSameRun = 2;

  // Places the cylinder axes and faces in the world at time t, once per
  // evaluation.
  void place(double t) const;
  // The core's pose as placed (core frame to world).
  const Eigen::Matrix3d& rotWorldCore() const { return rot_world_core_; }
  // Hashes the carried segments not yet hashed (all again after a release).
  void syncCarriedWire() const;
  // Deepest surface of the core body touching point p (as placed): its
  // index (cylinders, then faces; -1 if none), the penetration [m] and the
  // outward normal.
  int touch(const Eigen::Vector3d& p_world, double& h, Eigen::Vector3d& n_world) const;
  // Every surface touching point i at p (as placed), one per slot (surface
  // -1: none); the wire runs go to the slots whose surfaces in `ref` (the
  // point's committed or trial slots) they continue. False: none touches.
  struct Touch {
    int surface = -1;
    double h = 0.0;
    Eigen::Vector3d n_world = Eigen::Vector3d::Zero();
  };
  bool touchAll(int i, const Eigen::Vector3d& p_world, const int* ref, Touch* out) const;
  // Frozen surface of point i in the plane at the placed time: outward
  // normal, penetration [m] and d normal / dx [1/m]; false if the point is
  // at the surface's axis (no normal).
  bool planarSurface(const PlanarState& s, int surface, const Eigen::Vector2d& x,
                     Eigen::Vector2d& normal, double& depth, Eigen::Matrix2d& dnormal) const;
  // The same in 3-D for point i: outward normal, penetration [m], and d
  // normal / dp [1/m] where `dnormal` is given. A carried segment j stands
  // for the run j-1..j+1 (the nearest of the three).
  bool spatialSurface(int i, int surface, const Eigen::Vector3d& p_world,
                      Eigen::Vector3d& normal_world, double& depth, Eigen::Matrix3d* dnormal) const;
  // The carried wire is another (a restore) or numbered from a new front
  // (buried wire retired): hashed anew when next used; the first n points'
  // lists of nearby segments are dropped.
  void forgetCarriedWire(int n);
  // Where a point at p_world lies against the flanges: how far outside the
  // winding, beyond a flange's face [m] (at most 0 between them), which
  // flange (0: the first), and its distance from the core axis [m] against
  // the flanges' reach. Without flanges, flange -1. Wire wholly outside,
  // below the rim, has gone over a flange (docs/MODEL.md, "Flanges").
  struct FlangeSide {
    double outside_m = 0.0;
    int flange = -1;
    double from_axis_m = 0.0;
    double reach_m = 0.0;
  };
  FlangeSide flangeSide(const Eigen::Vector3d& p_world) const;

 private:
  // Flange j, a thin disc turning with the core, against a point at
  // p_world: the penetration [m], the outward normal and d normal / dp
  // [1/m] where `dnormal` is given. Within the disc's radius the point is
  // pushed off the face it lies on; beyond it, off the rim's circle along
  // the line from the circle's nearest point, so that the force turns
  // continuously over the edge. False: farther from the axis than a wire
  // radius beyond the rim, where the flange cannot touch.
  bool flangeDisc(int j, const Eigen::Vector3d& p_world, double& depth, Eigen::Vector3d& n_world,
                  Eigen::Matrix3d* dnormal) const;
  // The carried wire's runs touching point i (core-frame position), deepest
  // first, at most kMaxRuns; returns how many.
  static constexpr int kMaxRuns = 8;
  int touchWire(int i, const Eigen::Vector3d& p_core, Touch* runs) const;
  // Squared distance [m^2] of p_core from carried segment j (core frame),
  // the offset from the segment's nearest point (not normalized), and
  // whether that point is inside the segment (else at an end).
  // (Inline: every query takes a few.)
  double segmentOffset(int j, const Eigen::Vector3d& p_core, Eigen::Vector3d& offset_core,
                       bool& inside) const {
    const Eigen::Vector3d& from = (*carried_p_core_)[j];
    const Eigen::Vector3d& d = segment_dir_core_[j];
    const double s = (p_core - from).dot(d) / segment_length2_[j];
    inside = s > 0.0 && s < 1.0;
    offset_core = p_core - (from + std::clamp(s, 0.0, 1.0) * d);
    return offset_core.squaredNorm();
  }
  const WireConstants& c_;  // the model's: n grows with a supply
  const RotatingCore& core_;
  std::vector<Eigen::Vector3d> centers_core_;
  std::vector<double> radii_;
  mutable std::vector<Eigen::Vector3d> centers_world_;  // scratch, sized once
  mutable Eigen::Matrix3d rot_world_core_;              // core pose as placed
  // The core angle the surfaces were last placed at [rad] (placed again
  // only when it moves; NaN: never placed).
  mutable double placed_angle_ = std::numeric_limits<double>::quiet_NaN();
  // Faces: start, unit direction and outward normal in the core frame, length.
  std::vector<Eigen::Vector3d> face_from_core_, face_dir_core_, face_normal_core_;
  std::vector<double> face_length_;
  mutable std::vector<Eigen::Vector3d> face_from_world_, face_dir_world_, face_normal_world_;
  // Flanges: axial position from the core's origin [m] and the side the
  // winding lies on (+1: along the core axis). They turn in their own plane.
  std::vector<double> flange_at_;
  std::vector<double> flange_side_;
  double flange_radius_ = 0.0;  // their reach from the core axis [m]
  // How far from the core axis the core body and the carried wire reach a
  // point [m] (beyond both and the flanges, nothing touches).
  double body_reach_ = 0.0;
  mutable double carried_reach_ = 0.0;
  // Carried wire: its poses (the model's), the broad phase, how many
  // segments it holds, and the points next to a point along the wire that
  // never count as touching it.
  const std::vector<Eigen::Vector3d>* carried_p_core_ = nullptr;
  mutable CarriedWireIndex carried_index_;
  // Per carried segment j (set as it is hashed): p_j+1 - p_j in the core
  // frame and its squared length.
  mutable std::vector<Eigen::Vector3d> segment_dir_core_;
  mutable std::vector<double> segment_length2_;
  mutable int indexed_segments_ = 0;
  // Per point, the segments of the cell its last query read that lie within
  // the reach and near_skin_ of where it was (in the cell's order): a
  // Verlet list. A later query within the skin of that place, in the same
  // cell and with the same index, reads the list instead of the cell, and
  // meets the same segments in the same order, less ones it cannot touch.
  struct NearList {
    Eigen::Vector3d p_core = Eigen::Vector3d::Zero();
    std::int64_t cell = 0;
    unsigned version = 0;
    int count = -1;  // -1: none (or more than kNearMax)
  };
  static constexpr int kNearMax = 32;
  mutable std::vector<NearList> near_;
  mutable std::vector<int> near_segments_;  // kNearMax per point
  double near_skin_ = 0.0;                  // [m]
  // The list of point i valid at p_core, made anew where it is not;
  // nullptr: too many segments near, read the cell.
  const int* nearSegments(int i, const Eigen::Vector3d& p_core, int& count) const;
  int skip_points_ = 0;
  // Slots per point and their roles; surface ids: cylinders, faces,
  // flanges, then the carried segments from wire_base_.
  int slots_ = 1, flange_slot_ = -1, wire_slot_ = 1, wire_base_ = 0;
};

}  // namespace cws