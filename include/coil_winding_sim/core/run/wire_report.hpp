// What the whole wire is at the last accepted step, read from its model:
// its points from the fixed end (the retired ones, then the live ones, at
// whole-wire index w; WireModel::wirePoints), each point's place in the
// core frame and stand-off from the winding surface, the last point
// touching the core, and the bulging. Reports only: nothing here changes a
// model. (The live points' figures and stand-offs stay the model's, as a
// retirement records them; so does the energy, which the model books
// across a point's arrival and a retirement.)
#pragma once

#include <Eigen/Core>

#include "coil_winding_sim/core/model/wire_model.hpp"

namespace cws {

// Bulging (wire lifting off the core): the stand-off of the wound wire's
// centreline from the core's winding surface, the convex hull of the
// cylinders widened by the wire radius, measured in the core's cross-section.
// The wound part runs from the fixed end to the last point touching the core.
struct BulgeReport {
  bool valid = false;         // false: no core or nothing wound
  double height_m = 0.0;      // largest stand-off (0 when the wire lies on the core)
  double build_up_m = 0.0;    // largest stand-off from the core (headlineBulging) [m]
  int index = -1;             // the point where it occurs
  double arc_length_m = 0.0;  // its natural arc length from the fixed end
  Eigen::Vector3d p_core = Eigen::Vector3d::Zero();  // its position, core frame [m]
  int wound_points = 0;                              // points of the wound part
};

// Whole-wire point w: where it is [m], world frame, and its figures.
PointReport wirePoint(const WireModel& m, int w);
// Point w's position in the core frame [m] (needs a core).
Eigen::Vector3d wirePointCore(const WireModel& m, int w);
// Point w's stand-off from the winding surface [m] (needs a core).
double standOff(const WireModel& m, int w);
// The last point touching the core (whole-wire index); -1: none, or a
// scene without contact.
int lastInContact(const WireModel& m);
// The bulging of the wound wire (the stand-off alone; reports use
// headlineBulging, coil_report.hpp). Invalid without contact or a core.
BulgeReport bulging(const WireModel& m);

}  // namespace cws
