// Turns, layers, gaps and overlaps of the wound coil at the last accepted
// step (docs/MODEL.md, "Turns, layers, gaps and overlaps").
//
// A point's turn counts its angle about the core axis from the fixed end
// (core frame). Its layer: 1 on the core; 1 + the layer of the wire it
// rests on, where it touches carried wire lying nearer the core; else the
// layer of the point before it (a span between supports). The traverse
// plans each turn's layer from the pass the port is on while it is laid
// (half a turn of slack for the wire's lag behind the port).
// - gap: a turn lies further than d (plus kGapTolerance d) along the axis
//   from the turn before it in its layer;
// - overlap: a quarter of a turn's points or more (at least kOverlapPoints)
//   lie in a layer above the traverse's plan (on a neighbour where it should
//   lie beside it, or crossing it); the next turn's climb beginning in the
//   crossover zone at a turn's end is less;
// - bulging per layer: the largest stand-off above the layer's ideal
//   surface, the core's outline grown by (layer - 1) sqrt(3)/2 d
//   (orthocyclic layers);
// - the coil's bulging (its headline figure, the defect): the largest of
//   those; the build-up of the layers (the largest stand-off from the core)
//   is its own figure (headlineBulging).
#pragma once

#include <limits>
#include <vector>

namespace cws {

class WireModel;
struct Scene;
struct BulgeReport;

struct TurnReport {
  int turn = 0;  // 1 from the fixed end
  int first_point = 0, points = 0;
  int layer = 1;                         // the layer most of its points lie in
  int planned_min = 1, planned_max = 1;  // the traverse's layers for it
  double axial_m = 0.0;      // mean position along the core axis from the port's start [m]
  double stand_off_m = 0.0;  // largest stand-off above its layer's ideal surface [m]
  double spacing_m = std::numeric_limits<double>::quiet_NaN();  // from the turn before in
                                                                // its layer, axially [m]
  double gap_m = 0.0;                                           // spacing beyond d (0: none) [m]
  bool overlap = false;
};

struct CoilReport {
  bool valid = false;  // false: no core contact, or nothing wound
  std::vector<TurnReport> turns;
  // Per point of the wound wire (index = point): its turn (1-based) and
  // layer; points beyond the wound wire are left out.
  std::vector<int> point_turn, point_layer;
  int layers = 0;  // the highest layer reached
  int gaps = 0, overlaps = 0;
  double largest_gap_m = 0.0;
  int first_gap_turn = 0, first_overlap_turn = 0;  // 0: none
  std::vector<double> bulging_per_layer_m;         // index: layer - 1 [m]
  // The largest of them and the point where it occurs (-1: none) [m].
  double bulging_m = 0.0;
  int bulging_index = -1;
  // The wound wire's angle about the core axis from the fixed end [turns];
  // wound_turns rounds it to a whole turn (process.turns wound give
  // process.turns; the list of turns ends with the one being laid).
  double turns_wound = 0.0;
  int wound_turns() const { return static_cast<int>(turns_wound + 0.5); }
};

// A gap is reported beyond (1 + kGapTolerance) d: the penalty law's
// spacing error is far below it (docs/MODEL.md).
constexpr double kGapTolerance = 0.05;
constexpr int kOverlapPoints = 3;
constexpr double kOverlapFraction = 0.25;

// The report of the model's wound wire; needs the scene's traverse and wire.
CoilReport reportCoil(const WireModel& m, const Scene& s);

// The bulging every report shows (summary.json, the node's messages, rviz,
// the error estimate), defined here once: in a scene that winds in layers
// (physics.wire_contact), the coil's bulging (the largest stand-off above a
// layer's ideal surface) at its point, with the build-up (the largest
// stand-off from the core) beside it; in other scenes the paper's bulging,
// the largest stand-off from the core, which is then the build-up too.
// `coil`: the scene's coil report if already made.
BulgeReport headlineBulging(const WireModel& m, const Scene& s, const CoilReport* coil = nullptr);

}  // namespace cws
