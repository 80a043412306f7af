// The Newton iterations both implicit formulations share (planar and 3-D):
// modified Newton (a factorization serves while the steps it gives shrink
// to less than half; otherwise, or after a halved step, it is made anew;
// the full steps taken with it update it, where the problem keeps secant
// steps: secant_steps.hpp), a
// backtracking line search on the residual's norm (halving up to
// five times), convergence when the step is below the
// tolerance or the residual's work over it below the energy tolerance, and flag
// rounds: after a converged solve the effects recheck their frozen flags
// (contact, stick, slip, hysteresis lines) and a change solves again with a
// new Jacobian, up to flag_rounds times (docs/MODEL.md, "Implicit
// integration"). A solve whose step has fallen below flag_check_tol
// rechecks its flags once before it goes on to the tolerance: a change
// starts the next round there, as the iterations from there to the
// tolerance would serve flags that no longer hold. From round
// return_mapping_round on, the solve decides the laws' lines itself (return
// mapping from the committed yield points at every evaluation): the rounds
// that remain settle contact and stick/slip only, where the frozen lines of
// the bending laws (their elastic band is narrow) could take turns with
// them without end. A factorization that costs many solves (many pairs of
// free segments, spatial_formulation.hpp) serves while its steps shrink by
// a fifth, and into the next flag round.
#pragma once

#include <cmath>
#include <limits>

#include "coil_winding_sim/core/implicit/newton_formulation.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

// What a factorization was made for: a later solve of the same system size
// and scheme coefficients may start from it (modified Newton).
struct FactorKey {
  double alpha = 0.0;  // [1/s]
  int first = -1, n = -1;
  bool operator==(const FactorKey& o) const {
    return alpha == o.alpha && first == o.first && n == o.n;
  }
};

struct NewtonSettings {
  double tol = 1e-9;  // [m]
  int max_iterations = 30;
  int flag_rounds = 4;
  int line_search_halvings = 5;
  double flag_check_tol = 0.0;      // [m]; 0: flags rechecked only at convergence
  int return_mapping_round = 1000;  // the first round that return-maps (beyond flag_rounds: none)
  // The scene's (solver.newton_tol, newton_max_iterations) and the Newton
  // steps' constants: eight flag
  // rounds, five halvings, flags rechecked early below 3e-7 m, the laws'
  // lines return-mapped from round 2 on (the scene keys solver.flag_rounds,
  // flag_check_tol and return_mapping_round until issue 61; docs/MODEL.md,
  // "Implicit integration of planar scenes").
  static NewtonSettings of(const SolverParams& s) {
    return {s.newton_tol, s.newton_max_iterations, 8, 5, 3.0e-7, 2};
  }
};

// How much an old factorization's steps must shrink from one iteration to
// the next where a factorization costs many solves (Problem::costlyFactor:
// the many pairs of free segments of wound wire released onto free wire,
// whose solve grows as their number cubed, pair_coupling_solve.hpp).
constexpr double kCostlyContraction = 0.8;

// Problem: the formulation's trial state and Newton system, with
//   double residual(bool jacobian, int top)
//                                   assembles; the residual's norm. top >= 0 (a
//                                   flag round's): the Jacobian may be assembled
//                                   only up to point `top`
//   bool factor()                   factors the Jacobian just assembled (where
//                                   it was assembled up to a point, only there)
//   int changedTop()                the highest point the last recheck changed
//   double direction()              the Newton direction; its size [m]
//   void keepStart()                remembers the present iterate
//   void moveAlong(double s)        iterate = kept + s direction (rates too)
//   void forgetSteps()              the steps taken no longer update the
//                                   factorization (a new one, new flags)
//   bool keepStep()                 the full step just taken updates the
//                                   factorization for the next directions
//                                   (secant_steps.hpp); false: no room left
//   bool recheckFlags()             true: a flag changed
//   bool costlyFactor()             the present factorization cost many
//                                   solves: it serves longer
//   void returnMapping(bool on)     the laws' lines return-mapped (on) or
//                                   frozen (off)
// have_factor: the system's matrix holds a usable factorization (in, out).
template <class Problem>
NewtonStats newtonSolve(Problem& p, const NewtonSettings& c, bool& have_factor) {
  NewtonStats st;
  int top = -1;  // the next factorization: all of it, or from a flag round's highest point down
  p.returnMapping(c.return_mapping_round <= 0);
  st.return_mapped = c.return_mapping_round <= 0;
  for (int round = 0; round <= c.flag_rounds; ++round) {
    // (The Jacobian at the switch is that of the last recheck's lines: the
    // partial factorization that round asked for still serves.)
    if (round > 0 && round == c.return_mapping_round) {
      p.returnMapping(true);
      st.return_mapped = true;
    }
    bool converged = false;
    bool checked_early = false, changed_early = false;
    // A round that will factor assembles the Jacobian with its first
    // residual (`assembled`: the matrix holds the present iterate's).
    bool assembled = !have_factor;
    p.forgetSteps();
    double norm = p.residual(assembled, top);
    double previous = std::numeric_limits<double>::infinity();
    bool fresh = false;
    for (int it = 0; it < c.max_iterations; ++it) {
      ++st.iterations;
      if (!have_factor) {
        if (!assembled) p.residual(true, top);
        assembled = false;
        if (!p.factor()) return st;
        top = -1;
        p.forgetSteps();
        have_factor = fresh = true;
        ++st.factorizations;
      }
      const double step = p.direction();
      // An old factorization that does not contract: refactor here. One
      // that costs many solves (costlyFactor) serves while the steps shrink
      // by a fifth.
      const double contraction = p.costlyFactor() ? kCostlyContraction : 0.5;
      if (!fresh && !(step < contraction * previous)) {
        have_factor = false;
        continue;
      }
      if (!std::isfinite(step)) return st;
      p.keepStart();
      // A step below the tolerance ends the solve, and is taken. The
      // residual is not evaluated again there: the step's bookkeeping keeps
      // the forces of the last evaluation, less than the tolerance away
      // (a changed flag starts a new round with an evaluation of its own).
      if (step < c.tol) {
        p.moveAlong(1.0);
        converged = true;
        break;
      }
      // Line search: halve the step while the residual does not fall.
      double s = 1.0, trial = 0.0;
      int ls = 0;
      for (;; ++ls) {
        p.moveAlong(s);
        trial = p.residual(false);
        if (trial < norm || ls >= c.line_search_halvings || s * step < c.tol) break;
        s *= 0.5;
        ++st.line_searches;
      }
      norm = trial;
      if (s * step < c.tol) {
        converged = true;
        break;
      }
      // A halved step: the Jacobian is refreshed for the next iteration. A
      // full one updates it (secant steps), while there is room for one.
      if (ls > 0 || !p.keepStep()) have_factor = false;
      previous = s * step;
      fresh = false;
      if (!checked_early && previous < c.flag_check_tol) {
        checked_early = true;
        if (p.recheckFlags()) {
          changed_early = true;
          break;
        }
      }
    }
    if (!converged && !changed_early) return st;
    if (!changed_early && !p.recheckFlags()) {
      st.converged = true;
      return st;
    }
    if (round < c.flag_rounds) ++st.flag_rounds;
    // Changed flags change the system (a stick spring, a contact, a
    // hysteresis line's slope): the next round starts from a new Jacobian,
    // as the old one's steps would mostly be cut by the line search. Only
    // the blocks up to the highest changed point are factored again (they
    // lie near the core, where the elimination ends). A costly
    // factorization is kept into the round, until its steps stop shrinking.
    if (p.costlyFactor()) continue;
    have_factor = false;
    top = p.changedTop();
  }
  // Flags still changing after the last round: the step is retried smaller.
  return st;
}

}  // namespace cws
