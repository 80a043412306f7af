#include "coil_winding_sim/core/run/coil_report.hpp"

#include <algorithm>
#include <cmath>

#include "coil_winding_sim/core/external_forces/contact.hpp"
#include "coil_winding_sim/core/machine/traverse_profile.hpp"
#include "coil_winding_sim/core/run/wire_report.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

namespace {

constexpr double kTwoPi = 6.283185307179586;
// A point rests on wire it touches along a line less than 45 deg off the
// radial plane: |cos| to the axis below this.
constexpr double kRestingAxial = 0.7071;

// The layer of each wound point 0..last (core-frame positions, core axis
// z) from what it rests on.
std::vector<int> layersOf(const WireModel& m, const std::vector<Eigen::Vector3d>& p_core,
                          int last) {
  const Contact& contact = *m.contact();
  std::vector<int> layer(last + 1, 1);
  for (int i = 1; i <= last; ++i) {
    layer[i] = layer[i - 1];
    if (m.contactSurface(i, 0) >= 0) {
      layer[i] = 1;  // on the core
      continue;
    }
    int on = 0;
    for (int slot = 1; slot < contact.slots(); ++slot) {
      const int j = m.contactSurface(i, slot) - contact.wireSurface();
      if (j < 0 || j + 1 >= i) continue;
      // Resting on it: the line from the wire touched to the point is
      // nearer the radial plane than the axis (in a groove it is 30 deg off
      // the radial; a neighbour in the same layer lies along the axis).
      const Eigen::Vector3d a = p_core[j], e = p_core[j + 1] - a;
      const double u = std::clamp((p_core[i] - a).dot(e) / e.squaredNorm(), 0.0, 1.0);
      const Eigen::Vector3d from = p_core[i] - a - u * e;
      if (std::abs(from.z()) < kRestingAxial * from.norm()) {
        on = std::max(on, 1 + std::max(layer[j], layer[j + 1]));
      }
    }
    if (on > 0) layer[i] = on;
  }
  return layer;
}

}  // namespace

CoilReport reportCoil(const WireModel& m, const Scene& s) {
  CoilReport r;
  if (!m.contact() || !m.core() || s.core.cylinders.empty()) return r;
  const int last = lastInContact(m);
  if (last < 1) return r;
  r.valid = true;
  const double d = s.wire.diameter, rise = 0.5 * std::sqrt(3.0) * d;
  const Eigen::Vector3d axis = s.core.axis_world.normalized();
  const double axial0 = (s.supply.port_position_world - s.core.position_world).dot(axis);

  // Each point's stand-off, axial position and turn.
  std::vector<double> stand_off(last + 1), axial(last + 1);
  std::vector<Eigen::Vector3d> p_core(last + 1);
  r.point_turn.assign(last + 1, 1);
  double unwrapped = 0.0, previous = 0.0;
  for (int i = 0; i <= last; ++i) {
    const Eigen::Vector3d p = p_core[i] = wirePointCore(m, i);
    stand_off[i] = standOff(m, i);
    axial[i] = p.z() - axial0;
    const double a = std::atan2(p.y(), p.x());
    if (i > 0) unwrapped += std::remainder(a - previous, kTwoPi);
    previous = a;
    r.point_turn[i] = 1 + static_cast<int>(std::floor(std::abs(unwrapped) / kTwoPi));
  }
  r.turns_wound = std::abs(unwrapped) / kTwoPi;
  r.point_layer = layersOf(m, p_core, last);

  // Turns: their points, layer (the most common), plan, position, stand-off.
  const TraverseProfile plan =
      TraverseProfile::of(s.process.traverse_pitch, s.process.winding_width, d, s.traverseLayers())
          .stalled(s.process.traverse_stall_turn, s.process.traverse_stall_turns);
  for (int i = 0; i <= last;) {
    TurnReport turn;
    turn.turn = r.point_turn[i];
    turn.first_point = i;
    int counts[8] = {};
    double sum = 0.0;
    while (i <= last && r.point_turn[i] == turn.turn) {
      ++counts[std::min(r.point_layer[i], 8) - 1];
      sum += axial[i];
      ++i;
    }
    turn.points = i - turn.first_point;
    turn.layer = 1 + static_cast<int>(std::max_element(counts, counts + 8) - counts);
    turn.axial_m = sum / turn.points;
    const double start = kTwoPi * (turn.turn - 1);
    turn.planned_min = 1 + plan.at(std::max(0.0, start - 0.5 * kTwoPi)).layer;
    turn.planned_max = 1 + plan.at(start + (1.0 - 1e-9) * kTwoPi).layer;
    int above = 0, turn_index = -1;  // (the point of the turn's stand-off)
    for (int j = turn.first_point; j < i; ++j) {
      const int layer = r.point_layer[j];
      above += layer > turn.planned_max;
      // (Points of another layer than their turn's cross over between
      // layers: they bulge no layer.)
      if (layer != turn.layer) continue;
      const double height = std::max(0.0, stand_off[j] - (layer - 1) * rise);
      if (height > turn.stand_off_m || turn_index < 0) turn_index = j;
      turn.stand_off_m = std::max(turn.stand_off_m, height);
    }
    if (static_cast<int>(r.bulging_per_layer_m.size()) < turn.layer) {
      r.bulging_per_layer_m.resize(turn.layer, 0.0);
    }
    // (A turn on which the traverse changes layer crosses over: it bulges
    // no layer.)
    double& bulge = r.bulging_per_layer_m[turn.layer - 1];
    if (turn.planned_min == turn.planned_max) bulge = std::max(bulge, turn.stand_off_m);
    if (turn.planned_min == turn.planned_max && turn_index >= 0 &&
        (r.bulging_index < 0 || turn.stand_off_m > r.bulging_m)) {
      r.bulging_m = turn.stand_off_m;
      r.bulging_index = turn_index;
    }
    // (A crossover zone, where the next turn starts to climb, spans less
    // than a quarter of a turn.)
    turn.overlap = above >= std::max<double>(kOverlapPoints, kOverlapFraction * turn.points);
    r.turns.push_back(turn);
  }

  // Gaps: from the turn before in the same layer (the last turn is still
  // being laid: its spacing is not yet final and counts for nothing).
  for (std::size_t a = 1; a < r.turns.size(); ++a) {
    TurnReport& turn = r.turns[a];
    r.layers = std::max(r.layers, turn.layer);
    for (std::size_t b = a; b-- > 0;) {
      if (r.turns[b].layer != turn.layer) continue;
      if (b + 1 == a) turn.spacing_m = std::abs(turn.axial_m - r.turns[b].axial_m);
      break;
    }
    if (a + 1 < r.turns.size() && turn.spacing_m > (1.0 + kGapTolerance) * d) {
      turn.gap_m = turn.spacing_m - d;
      ++r.gaps;
      r.largest_gap_m = std::max(r.largest_gap_m, turn.gap_m);
      if (r.first_gap_turn == 0) r.first_gap_turn = turn.turn;
    }
  }
  r.layers = std::max(r.layers, r.turns.front().layer);
  for (const TurnReport& turn : r.turns) {
    if (!turn.overlap) continue;
    ++r.overlaps;
    if (r.first_overlap_turn == 0) r.first_overlap_turn = turn.turn;
  }
  return r;
}

BulgeReport headlineBulging(const WireModel& m, const Scene& s, const CoilReport* coil) {
  BulgeReport b = bulging(m);
  if (!b.valid || !s.physics.wire_contact) return b;
  CoilReport own;
  if (!coil) {
    own = reportCoil(m, s);
    coil = &own;
  }
  if (!coil->valid) return b;
  // The build-up stays; the bulging is the coil's, at its point (none yet
  // while every turn wound crosses between layers).
  if (coil->bulging_index < 0) {
    b.height_m = 0.0;
    return b;
  }
  b.height_m = coil->bulging_m;
  b.index = coil->bulging_index;
  b.arc_length_m = b.index * m.constants().segment_length;
  b.p_core = wirePointCore(m, b.index);
  return b;
}

}  // namespace cws
