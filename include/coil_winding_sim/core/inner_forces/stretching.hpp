// Stretching springs between neighbouring mass points, eqs. (7)-(9): the
// law written once on the force sink (assembly/force_sink.hpp), in the
// formulation's own coordinates.
#pragma once

#include <vector>

#include "coil_winding_sim/core/assembly/force_effect.hpp"
#include "coil_winding_sim/core/base/hysteresis.hpp"

namespace cws {

class Stretching : public SinkEffect<Stretching>, public EffectHistory {
 public:
  // With plastic = false the law is linear (EA) and no yield state exists.
  Stretching(const WireConstants& c, const HysteresisParams& p, bool plastic);

  const char* name() const override { return "stretching"; }
  // Energy l w(eps) per segment, eps = (|d| - l) / l: the tension T pulls
  // both ends towards each other along the segment; its Jacobian blocks, the
  // tangent k / l along the segment and the tension's geometric stiffness
  // T / |d| across it (stretching.cpp; instantiated for the three sinks).
  template <class Sink>
  void law(Sink& s) const;
  // Implicit steps freeze the line of each segment's law (elastic, upper or
  // lower plastic) within a Newton solve; the lines carry over between steps.
  void beginStep(const NewtonView& s0) override;
  bool recheck(const NewtonView& s) override;
  void commit(const AcceptedStep& step) override;
  void grow(const WireKinematics& k) override;
  void shrink(const WireKinematics& k) override;
  void retireFront(int k) override;
  // Every segment of a virgin wire was stretched to its present strain along
  // the loading curve (a wire that starts under the supply tension).
  void preload(const WireKinematics& k);
  void appendHistory(std::vector<double>& out) const override;
  void restoreHistory(HistoryReader& in) override;
  EffectEnergy energy(const WireKinematics& k) const override;
  double elasticEnergy(const WireKinematics& k) const;  // [J]

  // Axial strain [-] and axial force [N] (tension positive) of segment j.
  double strain(const WireKinematics& k, int j) const;
  double axialForce(const WireKinematics& k, int j) const;
  // Axial force [N] of segment j at strain x [-] from its committed yield
  // state (a carried segment's, from its frozen length).
  double axialForceAtStrain(double x, int j) const { return stressOf(x, j); }
  // Work [J] that stretches a virgin segment to strain x.
  double virginWork(double x) const;
  // Permanent strain of segment j [-] (0 when elastic).
  double plasticStrain(int j) const;

 private:
  double stressOf(double x, int j) const;
  // Stress [N] and consistent tangent [N] at strain x of segment j: on its
  // frozen line, or (mapped) on the line x lies on.
  double stressTangent(double x, int j, bool mapped, double& tangent) const;
  // The implicit steps' lines at a step's start, and their recheck, in
  // either formulation.
  template <class State>
  void beginLines(const State& s0);
  template <class State>
  bool recheckLines(const State& s);
  // Commits segment j as loaded from virgin to its present strain.
  void loadVirgin(const WireKinematics& k, int j);

  TwoLineLaw law_;
  bool plastic_;
  // Per segment (capacity), allocated only when plastic: upper yield point,
  // strain at the last commit; work done on all segments up to it [J].
  std::vector<double> upper_, x_committed_;
  std::vector<signed char> line_;            // implicit steps' frozen line per segment
  std::vector<signed char> line_committed_;  // the lines of the last accepted step
  int from_ = 0, to_ = 0;                    // segments of the present implicit step
  double work_committed_ = 0.0;
};

}  // namespace cws
