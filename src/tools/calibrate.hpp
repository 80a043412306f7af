// Calibration of scene keys to a machine's recording (wire_sim calibrate):
// a global search (dlib) for the least misfit of recording_misfit.hpp,
// every evaluation a replay of the machine bag run as a case of a sweep
// (locally N at once, or on Slurm), so that a batch of evaluations runs in
// parallel and a second run of the same command takes the evaluations it
// already has.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "coil_winding_sim/core/run/recording_misfit.hpp"
#include "key_order.hpp"
#include "sweep_plan.hpp"
#include "sweep_slurm.hpp"

namespace cws_tools {

// A fitted key with its bounds and starting value (in the key's unit).
struct FitParameter {
  std::string key;
  double lo = 0.0, hi = 0.0, start = 0.0;
};

struct CalibrationOptions {
  std::string machine_bag;       // absolute
  std::string machine_bag_hash;  // its bytes hashed (an evaluation is kept for the same bag)
  std::string scene;             // absolute, or "" for the built-in defaults
  std::vector<std::string> overrides;
  std::vector<FitParameter> fit;
  cws::MisfitWeights weights;
  double spindle_rate_hz = 100.0;  // the replay's sampling, as replay_machine.launch's
  double profile_rate_hz = 5.0;
  double profile_turns = 2.0;
  std::string out = "out/calibration";
  int jobs = 2;
  bool slurm = false;
  SlurmOptions slurm_options;
  // Evaluations in all (the search's budget); -1: 80 per fitted key.
  int max_evaluations = -1;
  // Evaluations per batch on Slurm (locally: --jobs).
  int batch = 8;
  // Points of the start design (Halton) over the box, evaluated at once;
  // -1: 8 per fitted key.
  int design_points = -1;
  // Finite-difference step for the Jacobian and the curvature, a fraction
  // of each range: wide enough to see the misfit's trend through the small
  // jumps of a replay's discrete events (contact and stick decisions).
  double step = 0.05;
};

// One evaluation's result, read from its case folder.
struct Evaluation {
  bool ok = false;
  std::string error;
  double misfit = 0.0, tension_rms_N = 0.0, profile_rms_mm = 0.0, bulging_rms_mm = 0.0,
         profile_offset_mm = 0.0;
  int tension_samples = 0, profile_points = 0, profile_pairs = 0;
  Eigen::VectorXd residuals;  // weighted: their sum of squares is the misfit
};

// The fitted keys' names, in o.fit's order.
std::vector<std::string> fitKeys(const CalibrationOptions& o);

// The plan of one batch of evaluations: one case per point (values in the
// keys' units), the options the case runner needs in plan.options.
SweepPlan calibrationPlan(const CalibrationOptions& o, const std::vector<Eigen::VectorXd>& points);
Evaluation readEvaluation(const SweepPlan& plan, const std::string& dir, std::size_t i);

// wire_sim calibrate ...: the exit code (0 done, 1 a failure, 2 bad input,
// 128 + signal when stopped, having written the best so far).
int calibrateMain(const std::vector<std::string>& args, const std::string& default_scene,
                  const std::string& exe, const std::function<bool()>& stop);

}  // namespace cws_tools
