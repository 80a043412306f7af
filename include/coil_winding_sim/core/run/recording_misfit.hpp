// How far a replay is from the machine's recording, as residuals a
// least-squares fit can take (wire_sim calibrate): the tension error by
// spindle angle, each measured profile point's distance to the simulated
// wire, and the bulging height difference, paired as compare_bags.py pairs
// them with --align angle (the same rules, written again here in C++ and
// checked against it by test_calibrate). Times are seconds from the
// machine bag's start, lengths metres in, millimetres in the profile and
// bulging residuals.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace cws {

// One profile cloud: points [m] in the core frame and, when the cloud has
// the field, their stand-off [m] from the winding surface.
struct ProfileCloud {
  double t_s = 0.0;
  std::vector<Eigen::Vector3d> p_core;
  std::vector<double> stand_off_m;  // empty without the field
};

// What a cell measures, from the machine or from the simulation.
struct RecordedSeries {
  std::vector<double> spindle_t_s, spindle_angle_rad;  // spindle/state
  std::vector<double> tension_t_s, tension_N;          // tension/measured
  std::vector<ProfileCloud> profiles;                  // profile
};

// The misfit's weights, per sample: misfit = tension N_T RMS_T^2 +
// profile N_p RMS_p^2 + bulging N_b RMS_b^2 (N: the samples compared), a
// chi-square when each weight is 1 / sigma^2 of its measurement's noise.
// The defaults take 0.1 N for the load cell, 5 um for the profile sensor
// and 10 um for the bulging (the largest stand-off of a noisy profile).
struct MisfitWeights {
  double tension = 100.0;  // [1/N^2]
  double profile = 4.0e4;  // [1/mm^2]
  double bulging = 1.0e4;  // [1/mm^2]
  // Remove the profile's mean radial offset (a line sensor's zero) before
  // the profile and bulging terms.
  bool remove_profile_offset = true;
};

struct Misfit {
  // Residuals: tension [N] (sim - machine at the machine's samples in the
  // common angle range, to 1 micro-radian beyond the sim's end), profile [mm]
  // (each measured point's distance to the simulated wire, as
  // compare_bags.py measures it, after the points are moved radially by the
  // offset), bulging [mm] (per profile pair: the largest stand-off, sim -
  // machine less the offset).
  std::vector<double> tension_N, profile_mm, bulging_mm;
  double profile_offset_mm = 0.0;  // the radial offset removed, outward positive [mm]
  int profile_pairs = 0;
  std::vector<std::string> notes;  // what was not compared, and why

  double rms(const std::vector<double>& r) const;
  double tensionRms() const { return rms(tension_N); }
  double profileRms() const { return rms(profile_mm); }
  double bulgingRms() const { return rms(bulging_mm); }
  // The weighted sum of squares [-].
  double value(const MisfitWeights& w) const;
  // The residuals times the square roots of their weights (their sum of
  // squares is value(w)), in the order tension, profile, bulging.
  Eigen::VectorXd weighted(const MisfitWeights& w) const;
};

// The misfit of `sim` against `machine`. Throws std::invalid_argument, in
// compare_bags.py's words, when they cannot be aligned (fewer than 10
// samples, no overlap in time or angle).
Misfit recordingMisfit(const RecordedSeries& machine, const RecordedSeries& sim,
                       const MisfitWeights& weights);

// Numerics shared with compare_bags.py's series_math.py, for tests.
// Cubic Hermite interpolation of y(x) at xq (x strictly increasing), slopes
// by central differences, constant beyond the ends' cubic pieces.
std::vector<double> hermite(const std::vector<double>& xq, const std::vector<double>& x,
                            const std::vector<double>& y);
// The distance [m] of p to the polyline through `poly`, signed positive
// when p lies further from the core axis (z) than its nearest point on it.
double signedDistanceToPolyline(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& poly);

}  // namespace cws
