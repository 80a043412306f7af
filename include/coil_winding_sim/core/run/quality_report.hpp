// The figures a coil is judged by beside its geometry (coil_report.hpp):
// how far the wire was stretched for good (plastic elongation thins the
// conductor and raises its resistance), how far it was bent against what
// its enamel is tested to stand, and how full the bobbin's winding window
// is (docs/MODEL.md, "A coil's quality figures").
#pragma once

#include <limits>
#include <vector>

namespace cws {

class WireModel;
struct Scene;
struct CoilReport;

struct QualityReport {
  // Largest permanent axial strain of the whole wire [-] (retired wire as
  // it was when it retired), the segment where it is (of the whole wire;
  // -1: none yielded), and the
  // conductor's cross-section lost to it at constant volume,
  // eps / (1 + eps) [-].
  double plastic_elongation = 0.0;
  int plastic_elongation_segment = -1;
  double cross_section_lost = 0.0;
  // Largest bending strain at the conductor's surface of the wound wire,
  // curvature x bare radius [-], and its point (-1: none).
  double bending_strain = 0.0;
  int bending_strain_point = -1;
  // The enamel's limits (enamelled wire, wire.insulation_grade 1-3; 0 for a
  // bare wire, which has none): the mandrel wrap's bending strain, and the
  // minimum elongation at break the surface strain (axial + bending) must
  // stay below [-]; the turns where the wound wire passed either.
  double bending_limit = 0.0, elongation_limit = 0.0;
  std::vector<int> turns_past_limits;
  // The crossover zone of each layer (index: layer - 1) [rad]: the angle
  // about the core axis over which a turn climbs from a tenth to nine
  // tenths of its axial step to the next groove, the median over the
  // layer's turns (NaN: none measured). A helix, laid as the traverse
  // moves, climbs over 0.8 of a turn; wire in an orthocyclic layer's
  // grooves climbs in a short zone.
  std::vector<double> crossover_per_layer_rad;
  // Conductor area of the wound turns over the bobbin's winding window
  // (flange spacing x flange height) [-]; NaN without flanges.
  double fill_factor = std::numeric_limits<double>::quiet_NaN();
  // The tension where a machine's load cell sits, after the nozzle (the
  // port's segment; Supply::trace): its highest and lowest over the run,
  // and the ripple (highest less lowest) of each whole core turn (the
  // turns planned, and more while there is room), with its largest and its
  // mean over every turn [N]. NaN and empty without a supply.
  double tension_peak_N = std::numeric_limits<double>::quiet_NaN();
  double tension_low_N = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> tension_ripple_per_turn_N;
  double tension_ripple_max_N = std::numeric_limits<double>::quiet_NaN();
  double tension_ripple_mean_N = std::numeric_limits<double>::quiet_NaN();
};

// The enamel's limits of a wire of nominal bare diameter d [m] (IEC 60317
// as IS 13730-0-1 and IS 13778-3 reproduce it): the bending strain of a
// wrap on a mandrel of one diameter, 1/2 (0.14 to 1.6 mm), and the minimum
// elongation at break by size [-]; 0 outside the sizes held.
double mandrelBendingLimit(double nominal_diameter);
double elongationAtBreakLimit(double nominal_diameter);

// How much of its enamel's limits point w of the whole wire has used at the
// last accepted step: the larger of its bending strain over the mandrel
// wrap's and its surface strain (axial + bending) over the elongation at
// break [-]; above 1 it passed one (0 for a bare wire).
double enamelRisk(const WireModel& m, const Scene& s, int w);

// The report of the model's wire at its last accepted step; `coil` gives
// the wound wire's turns (coil_report.hpp).
QualityReport reportQuality(const WireModel& m, const Scene& s, const CoilReport& coil);

}  // namespace cws
