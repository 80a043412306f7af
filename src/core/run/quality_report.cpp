#include "coil_winding_sim/core/run/quality_report.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "coil_winding_sim/core/external_forces/supply.hpp"
#include "coil_winding_sim/core/inner_forces/stretching.hpp"
#include "coil_winding_sim/core/model/wire_model.hpp"
#include "coil_winding_sim/core/run/coil_report.hpp"
#include "coil_winding_sim/core/run/wire_report.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

double mandrelBendingLimit(double nominal_diameter) {
  // Over 0.140 up to 1.600 mm: wound on a mandrel of one wire diameter, no
  // crack: the centre line at radius d, the surface strained (d / 2) / d.
  return nominal_diameter > 0.14e-3 && nominal_diameter <= 1.6e-3 ? 0.5 : 0.0;
}

double elongationAtBreakLimit(double nominal_diameter) {
  // Nominal diameter up to and including [mm], minimum elongation [%].
  static constexpr double kRows[][2] = {{0.200, 21}, {0.250, 22}, {0.315, 23}, {0.400, 24},
                                        {0.500, 25}, {0.630, 27}, {0.750, 28}, {0.850, 29},
                                        {1.060, 30}, {1.250, 31}, {1.600, 32}};
  for (const auto& row : kRows) {
    if (nominal_diameter <= 1e-3 * row[0] * (1.0 + 1e-9)) return 0.01 * row[1];
  }
  return 0.0;
}

namespace {
// Per layer, the median over its whole turns of the angle over which the
// turn's axial position climbs from 0.1 to 0.9 of its step (turns that
// step by less than half the pitch, the traverse's reversals, left out).
std::vector<double> crossoverPerLayer(const WireModel& m, const Scene& s, const CoilReport& coil) {
  constexpr double kTwoPi = 6.283185307179586;
  std::vector<std::vector<double>> angles(static_cast<std::size_t>(std::max(coil.layers, 0)));
  const double pitch = std::abs(s.process.traverse_pitch);
  // The last turn is the one being laid.
  for (std::size_t t = 0; t + 1 < coil.turns.size(); ++t) {
    const TurnReport& turn = coil.turns[t];
    if (turn.points < 8 || turn.layer < 1 || turn.layer > coil.layers) continue;
    const int first = turn.first_point, last = turn.first_point + turn.points - 1;
    const Eigen::Vector3d p0 = wirePointCore(m, first);
    const double step = wirePointCore(m, last).z() - p0.z();
    if (pitch == 0.0 || !(std::abs(step) >= 0.5 * pitch)) continue;
    // Where the climb passes a fraction, between the points either side.
    double angle = 0.0, previous = std::atan2(p0.y(), p0.x()), climbed_before = 0.0;
    double from = -1.0, to = -1.0;
    for (int w = first + 1; w <= last; ++w) {
      const Eigen::Vector3d p = wirePointCore(m, w);
      const double a = std::atan2(p.y(), p.x());
      const double turned = std::abs(std::remainder(a - previous, kTwoPi));
      previous = a;
      const double climbed = (p.z() - p0.z()) / step;
      auto passes = [&](double fraction, double& at) {
        if (at >= 0.0 || climbed < fraction) return;
        const double part = climbed > climbed_before
                                ? (fraction - climbed_before) / (climbed - climbed_before)
                                : 1.0;
        at = angle + std::clamp(part, 0.0, 1.0) * turned;
      };
      passes(0.1, from);
      passes(0.9, to);
      angle += turned;
      climbed_before = climbed;
    }
    if (from >= 0.0 && to >= from) angles[turn.layer - 1].push_back(to - from);
  }
  std::vector<double> median(angles.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t l = 0; l < angles.size(); ++l) {
    std::vector<double>& a = angles[l];
    if (a.empty()) continue;
    std::nth_element(a.begin(), a.begin() + a.size() / 2, a.end());
    median[l] = a[a.size() / 2];
  }
  return median;
}
}  // namespace

namespace {
// The bare conductor: its nominal diameter, or the wire's where none is
// given (paper_table_1, a bare wire) [m].
double bareDiameter(const Scene& s) {
  return s.wire.nominal_diameter > 0.0 ? s.wire.nominal_diameter : s.wire.diameter;
}
}  // namespace

double enamelRisk(const WireModel& m, const Scene& s, int w) {
  if (s.wire.insulation_grade <= 0) return 0.0;
  const WireConstants& c = m.constants();
  const double bare = bareDiameter(s);
  const double bending = wirePoint(m, w).curvature_1pm * 0.5 * bare;
  const int j = w - c.retired - 1;  // the live segment ending at the point
  const double axial = j >= 0 && j + 1 < c.n ? m.stretching().strain(m.committed(), j) : 0.0;
  const double mandrel = mandrelBendingLimit(bare), elongation = elongationAtBreakLimit(bare);
  double risk = 0.0;
  if (mandrel > 0.0) risk = bending / mandrel;
  if (elongation > 0.0) risk = std::max(risk, (std::max(axial, 0.0) + bending) / elongation);
  return risk;
}

QualityReport reportQuality(const WireModel& m, const Scene& s, const CoilReport& coil) {
  QualityReport q;
  const double bare = bareDiameter(s);
  const bool enamelled = s.wire.insulation_grade > 0;
  if (enamelled) {
    q.bending_limit = mandrelBendingLimit(bare);
    q.elongation_limit = elongationAtBreakLimit(bare);
  }
  // Permanent elongation over the whole wire (retired wire keeps its
  // figures from when it retired).
  const int retired = m.retiredPoints();
  for (int w = 0; w + 1 < m.wirePoints(); ++w) {
    const double eps = w < retired ? m.retiredWire()[w].segment_plastic_strain
                                   : m.stretching().plasticStrain(w - retired);
    if (eps > q.plastic_elongation) {
      q.plastic_elongation = eps;
      q.plastic_elongation_segment = w;  // of the whole wire
    }
  }
  q.cross_section_lost = q.plastic_elongation / (1.0 + q.plastic_elongation);
  // The load cell's trace.
  if (const Supply* supply = m.supply(); supply && supply->trace().seen) {
    const TensionTrace& tr = supply->trace();
    q.tension_peak_N = tr.peak;
    q.tension_low_N = tr.low;
    q.tension_ripple_per_turn_N = tr.ripple_per_turn;
    if (tr.ripple_turns > 0) {
      q.tension_ripple_max_N = tr.ripple_max;
      q.tension_ripple_mean_N = tr.ripple_sum / static_cast<double>(tr.ripple_turns);
    }
  }
  // Bending at the surface over the wound wire, against the limits turn by
  // turn (the axial strain of live segments added on the stretched side).
  const int wound = static_cast<int>(coil.point_turn.size());
  for (int w = 0; w < wound; ++w) {
    const double bending = wirePoint(m, w).curvature_1pm * 0.5 * bare;
    if (bending > q.bending_strain) {
      q.bending_strain = bending;
      q.bending_strain_point = w;
    }
    if (!enamelled) continue;
    const bool past = enamelRisk(m, s, w) > 1.0;
    const int turn = coil.point_turn[w];
    if (past && std::find(q.turns_past_limits.begin(), q.turns_past_limits.end(), turn) ==
                    q.turns_past_limits.end()) {
      q.turns_past_limits.push_back(turn);
    }
  }
  q.crossover_per_layer_rad = crossoverPerLayer(m, s, coil);
  // Conductor of the turns wound over the winding window.
  if (s.physics.flanges && coil.valid) {
    const double spacing =
        s.core.flange_spacing > 0.0 ? s.core.flange_spacing : s.process.winding_width;
    const double window = spacing * s.core.flange_height;
    if (window > 0.0) {
      q.fill_factor = coil.turns_wound * M_PI * bare * bare / 4.0 / window;
    }
  }
  return q;
}

}  // namespace cws
