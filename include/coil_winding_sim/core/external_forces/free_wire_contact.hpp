// Contact between two free segments of the wire (physics.wire_contact): an
// integrated point against a segment earlier along the wire whose ends are
// integrated too, before the core carries either. (The boundary segment,
// from the last carried point to the first integrated one, is left to the
// carried wire's contact, which has that point's sphere at its end: with
// both, a point beside the junction would feel two springs.)
// Contact.hpp's wire contact covers the segments the core carries; this
// covers the rest, so that a landing turn cannot pass through a turn the
// core does not carry yet (docs/MODEL.md, "Wire against wound wire").
//
// - The same capsule geometry: h = 2 r - the point's distance from the
//   segment, node against segment, the later point against the earlier
//   segment only (as against carried wire), neighbours along the wire
//   within Contact::skipPoints() never counting. A point feels the nearest
//   segment of each run of touching segments, of the kRuns runs nearest.
// - The same normal law (Contact::normalLaw: k h with its dashpot against
//   the relative normal speed); the reaction acts on the segment's two ends
//   in the ratio of the nearest point's position along it.
// - Kinetic friction mu_d N against the relative sliding velocity. Two
//   free segments do not stick: a stick spring needs an anchor that moves
//   with one of them, and once the core carries one, the carried-wire
//   contact (with stick) takes the pair over. An implicit step divides by
//   at least contact.stick_speed (viscous below it, so that Newton does not
//   chase the kink at rest); the explicit methods take the direction as it
//   is (a bounded force: a viscous law that stiff would hold their step).
// - Candidates come from a neighbour list with a skin (as molecular
//   dynamics keeps its Verlet lists): the pairs within 2 d, built anew at a
//   commit once a point has moved r / 2 since the last build, or the
//   integrated span changed.
// - In a Newton step the pair couples two distant blocks. Its Jacobian goes
//   to the assembly as a coupling outside the band
//   (SpatialAssembly::addPairCoupling), solved through the Woodbury
//   identity over the band's factorization (pair_coupling_solve.hpp), so the
//   system stays block-tridiagonal. Which pairs touch is a flag, frozen
//   within a solve and rechecked after it, as the core's contacts are.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "coil_winding_sim/core/external_forces/contact.hpp"

namespace cws {

class FreeWireContact : public ForceEffect, public EffectHistory {
 public:
  // contact: the core's contact, whose laws and parameters this shares.
  FreeWireContact(const WireConstants& c, const Contact& contact);

  const char* name() const override { return "free_wire_contact"; }
  // The law, written once on the sink (law below); wire contact is refused
  // in the plane: nothing to add there.
  void addForces(ExplicitSink& s) const override { law(s); }
  void addForces(PlanarSink& /*s*/) const override {}
  void addForces(SpatialSink& s) const override { law(s); }
  void beginStep(const NewtonView& s0) override {
    if (s0.spatial()) beginSpatial(*s0.spatial());
  }
  bool recheck(const NewtonView& s) override {
    return s.spatial() ? recheckSpatial(*s.spatial()) : false;
  }
  void commit(const AcceptedStep& step) override;
  void shrink(const WireKinematics& k) override;
  void retireFront(int k) override;
  // No history (no stick): the neighbour list is built anew after a restore.
  void restoreHistory(HistoryReader& in) override;
  EffectEnergy energy(const WireKinematics&) const override { return {elastic_committed_, 0.0}; }
  double elasticEnergy() const { return elastic_committed_; }  // [J]

  static constexpr int kRuns = 2;           // pairs a point keeps: its nearest runs
  static constexpr int kCandidateRuns = 8;  // runs within reach compared for them
  // The pair deepest in contact at the last commit (depth 0: none).
  struct Deepest {
    double depth_m = 0.0;
    int point = -1, segment = -1;
  };
  const Deepest& deepest() const { return deepest_; }
  // Pairs in the neighbour list, and those touching, at the last commit.
  int candidates() const { return static_cast<int>(pairs_.size()); }
  int touching() const;
  // Tests: the force on point a of a pair (a, b) at state s, as the
  // implicit step adds it, and its derivative in p_a (with v_a following as
  // alpha p_a); false if the pair does not touch there.
  bool pairForceAt(const SpatialState& s, int a, int b, Eigen::Vector3d& f_a,
                   Eigen::Matrix3d& df_a) const;

 private:
  // Each touching pair's force on its point, the reaction on the segment's
  // ends, and the pair's coupling: touching as the positions say in
  // explicit steps, as the frozen flag says in Newton steps.
  template <class Sink>
  void law(Sink& s) const;
  void beginSpatial(const SpatialState& s0);
  bool recheckSpatial(const SpatialState& s);
  struct Pair {
    int a, b;           // point a against segment b (points b, b + 1)
    char active;        // touching at the last commit
    char trial_active;  // an implicit step's frozen flag
  };
  // Point a against the nearest of segments b-1..b+1 that it may touch
  // (first <= m <= a-1-skip): segment m, the nearest point's position t
  // along it, delta = p_a - that point, and the segment's unit direction
  // where that point lies inside it (zero at an end). False: none (a or b
  // no longer free, or a degenerate distance).
  struct Geometry {
    int m;
    double t;
    Eigen::Vector3d delta, tangent;
  };
  // (p(i): point i's position [m], world frame.)
  template <class Positions>
  bool geometry(const Positions& p, int first, int a, int b, Geometry& g) const;
  bool geometry(const Eigen::Matrix3Xd& p, int first, int a, int b, Geometry& g) const;
  // The force on point a at the pair's geometry and relative velocity
  // r_v = v_a - (1 - t) v_m - t v_m+1; with jacobian, df = dF / d p_a
  // where the velocities follow the positions as v = alpha (x - x_hat).
  // Friction is divided by at least floor_speed [m/s] (0: the Coulomb
  // direction, zero at rest).
  struct PairForce {
    Eigen::Vector3d f, f_dissipative;
    Eigen::Matrix3d df;
    double h;
  };
  PairForce pairForce(const Geometry& g, const Eigen::Vector3d& r_v, double alpha, bool jacobian,
                      double floor_speed) const;
  // The neighbour list at positions p of points first-1..n-1.
  void build(const Eigen::Matrix3Xd& p, int first, int n);
  bool needsBuild(const Eigen::Matrix3Xd& p, int first, int n) const;
  // The list (built anew if needed), which pairs touch, their energy and
  // the deepest, at positions p of the committed state.
  void refresh(const Eigen::Matrix3Xd& p, int first, int n);

  const WireConstants& c_;
  const Contact& contact_;
  double touch_distance_;  // 2 r [m]
  double reach_;           // 2 r plus the skin [m]
  double rebuild_move_;    // a point's move that rebuilds the list [m]
  int skip_;
  std::vector<Pair> pairs_;  // reserved to the capacity once
  Eigen::Matrix3Xd p_built_;
  int built_first_ = -1, built_n_ = -1;
  double elastic_committed_ = 0.0;
  Deepest deepest_;
};

}  // namespace cws
