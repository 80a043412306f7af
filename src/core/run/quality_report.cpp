#include "coil_winding_sim/core/run/quality_report.hpp"

#include <algorithm>
#include <cmath>

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

QualityReport reportQuality(const WireModel& m, const Scene& s, const CoilReport& coil) {
  QualityReport q;
  const WireConstants& c = m.constants();
  // The bare conductor: its nominal diameter, or the wire's where none is
  // given (paper_table_1, a bare wire).
  const double bare = s.wire.nominal_diameter > 0.0 ? s.wire.nominal_diameter : s.wire.diameter;
  const bool enamelled = s.wire.insulation_grade > 0;
  if (enamelled) {
    q.bending_limit = mandrelBendingLimit(bare);
    q.elongation_limit = elongationAtBreakLimit(bare);
  }
  // Permanent elongation over the live segments (retired wire keeps its
  // figures, not its yield state).
  const Stretching& stretching = m.stretching();
  for (int j = 0; j + 1 < c.n; ++j) {
    const double eps = stretching.plasticStrain(j);
    if (eps > q.plastic_elongation) {
      q.plastic_elongation = eps;
      q.plastic_elongation_segment = j;
    }
  }
  q.cross_section_lost = q.plastic_elongation / (1.0 + q.plastic_elongation);
  // Bending at the surface over the wound wire, against the limits turn by
  // turn (the axial strain of live segments added on the stretched side).
  const int wound = static_cast<int>(coil.point_turn.size());
  const WireKinematics& k = m.committed();
  for (int w = 0; w < wound; ++w) {
    const double bending = wirePoint(m, w).curvature_1pm * 0.5 * bare;
    if (bending > q.bending_strain) {
      q.bending_strain = bending;
      q.bending_strain_point = w;
    }
    if (!enamelled) continue;
    const int j = w - c.retired - 1;  // the live segment ending at the point
    const double axial = j >= 0 && j + 1 < c.n ? stretching.strain(k, j) : 0.0;
    const bool past =
        (q.bending_limit > 0.0 && bending > q.bending_limit) ||
        (q.elongation_limit > 0.0 && std::max(axial, 0.0) + bending > q.elongation_limit);
    const int turn = coil.point_turn[w];
    if (past && std::find(q.turns_past_limits.begin(), q.turns_past_limits.end(), turn) ==
                    q.turns_past_limits.end()) {
      q.turns_past_limits.push_back(turn);
    }
  }
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
