// The calibration's numerics: evaluations run in batches through the sweep
// mechanism, the global search (dlib's global_function_search) over the
// fitted keys scaled to [0, 1], and the uncertainty and identifiability at
// the optimum.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "calibrate.hpp"

namespace cws_tools {

// Ctrl-C during a batch: the batch's running cases stopped and pending.
struct CalibrationStopped {};

class Evaluator {
 public:
  Evaluator(const CalibrationOptions& o, std::string exe, std::function<bool()> stop);
  // The keys' values [their units] at the scaled point u (0: lo, 1: hi).
  Eigen::VectorXd values(const Eigen::VectorXd& u) const;
  // One batch, each point's evaluation in order: N at once, or on Slurm.
  // Throws CalibrationStopped.
  std::vector<Evaluation> run(const std::vector<Eigen::VectorXd>& u);

  const CalibrationOptions& options() const { return o_; }
  double step() const { return o_.step; }
  int evaluations() const { return evaluations_; }
  int kept() const { return kept_; }
  bool haveBest() const { return best_.ok; }
  const Evaluation& best() const { return best_; }
  const Eigen::VectorXd& bestU() const { return best_u_; }
  // Every evaluation in order: scaled point and result.
  const std::vector<std::pair<Eigen::VectorXd, Evaluation>>& history() const { return history_; }
  std::string describe(const Eigen::VectorXd& u) const;  // "key=value, ..."

 private:
  const CalibrationOptions& o_;
  std::string exe_;
  std::function<bool()> stop_;
  int batch_ = 0, evaluations_ = 0, kept_ = 0;
  Evaluation best_;
  Eigen::VectorXd best_u_;
  std::vector<std::pair<Eigen::VectorXd, Evaluation>> history_;
  std::map<std::vector<double>, Evaluation> cache_;
  std::vector<std::string> keys_;  // the fitted keys, in o_.fit's order
  cws::Scene base_;                // the scene before the fit: the values of keys not fitted
};

struct FitOutcome {
  Eigen::VectorXd u;        // the best point, scaled
  std::string termination;  // how the search ended, one line
  bool stopped = false;     // Ctrl-C: the best so far
};
// The global search from the scaled start u0 and a Halton design over the
// box, then dlib's alternation of global exploration (its Lipschitz upper
// bound) and local refinement (a quadratic model about the best point), a
// batch of requests at a time, until o.max_evaluations.
FitOutcome fitGlobal(Evaluator& ev, const Eigen::VectorXd& u0);

// Each fitted key at the optimum: its 1-sigma uncertainty from the
// curvature (the Gauss-Newton Hessian J^T J of central differences) with
// each measurement's noise taken from its own residuals there, and whether
// the data pin it down.
struct ParameterVerdict {
  double sigma = 0.0;  // [the key's unit]; NaN when not identifiable
  bool identifiable = true;
  std::string note;  // why not, or with which key it is correlated
};
std::vector<ParameterVerdict> judgeParameters(Evaluator& ev, const Eigen::VectorXd& u);

}  // namespace cws_tools
