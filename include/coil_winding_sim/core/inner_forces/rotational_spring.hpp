// Rotational springs at the joints between neighbouring frames: the shared
// mechanism of bending (eqs. 10-12) and torsion (eqs. 13-15).
//
// The curvature-twist (Darboux) vector of joint j in the material frame of
// frame j is
//   Omega_j = (2 / lambda_j) Im(conj(q_j) q_{j+1}) = (2 / lambda_j) G(q_j) q_{j+1}
// (lambda_j = l; lambda_0 = l / 2 at the clamp, whose joint spans half a
// segment: the clamp fixes the tangent at the point, the first segment is the
// chord half a segment further), whose components 0 and 1 are the two bending curvatures (about xi
// and eta) [1/m] and component 2 the twist rate (about zeta) [rad/m]; |Omega| lambda equals 2
// sin(angle / 2), the paper's spring angle to second order. With it a constant moment puts the
// points exactly on the arc of radius EI / M. Each component has its own two-line law. The moment
// vector m reaches the quaternions as generalized forces -l m . dOmega/dq, and through the
// rotational constraint (5) the segments and their mass points (the paper's "moment divided by the
// length of the straight spring"). The law is written once on the force
// sink (assembly/force_sink.hpp, its joint calls).
#pragma once

#include <vector>

#include "coil_winding_sim/core/assembly/force_effect.hpp"
#include "coil_winding_sim/core/base/hysteresis.hpp"

namespace cws {

class RotationalSpring : public SinkEffect<RotationalSpring>, public EffectHistory {
 public:
  // Components [first, first + count) of Omega follow `p`.
  RotationalSpring(const char* name, const WireConstants& c, const HysteresisParams& p,
                   bool plastic, int first, int count);

  const char* name() const override { return name_; }
  // Each joint's moment m(Omega) from the laws of its components, with
  // their tangents (rotational_spring.cpp; instantiated for the three
  // sinks).
  template <class Sink>
  void law(Sink& s) const;
  // Implicit steps freeze the line of each law (elastic, upper or lower
  // plastic) within a Newton solve; the lines carry over between steps.
  void beginStep(const NewtonView& s0) override;
  bool recheck(const NewtonView& s) override;
  void commit(const AcceptedStep& step) override;
  void shrink(const WireKinematics& k) override;
  void retireFront(int k) override;
  void appendHistory(std::vector<double>& out) const override;
  void restoreHistory(HistoryReader& in) override;
  EffectEnergy energy(const WireKinematics& k) const override;
  double elasticEnergy(const WireKinematics& k) const;  // [J]

  // Darboux vector of joint j (0 <= j <= n-2) in frame j [1/m].
  Eigen::Vector3d darboux(const WireKinematics& k, int j) const;
  // Moment of component m (0-based within this spring) at joint j [N m].
  double moment(const WireKinematics& k, int j, int m) const;
  // Permanent curvature/twist of component m at joint j [1/m] (0 if elastic).
  double plasticValue(int j, int m) const;
  int first() const { return first_; }
  int count() const { return count_; }
  // `partner`, the other components of the same joints (torsion beside
  // bending), is evaluated in this spring's pass, which then forms the
  // Darboux vector and the joints' moments once for both; the partner's
  // own pass adds nothing.
  void sharePass(RotationalSpring& partner) {
    partner_ = &partner;
    partner.in_shared_pass_ = true;
  }

 private:
  double stressOf(double x, int idx) const;
  // Stress [N m] and consistent tangent [N m^2] of law idx at x: on its
  // frozen line, or (mapped) on the line x lies on.
  double stressTangent(double x, int idx, bool mapped, double& tangent) const;
  // Length of wire that joint j stands for [m].
  double jointLength(int j) const;
  // Darboux vector of joint j at a 3-D trial state [1/m].
  Eigen::Vector3d darboux(const SpatialState& s, int j) const;
  // The implicit steps' lines at a step's start (the committed ones), and
  // their recheck given each law's argument: argument(j, c, x) sets x,
  // false to skip the law; mapped: the lines are only recorded, as the
  // solve return-mapped them.
  void beginLines(int first, int n);
  template <class Argument>
  int recheckLines(int first, int n, bool mapped,
                   Argument argument);  // the highest joint changed, or -1
  // The lines' recheck at the laws' arguments: in the plane, kappa
  // n_material[c] (none for a component with no part about n); in 3-D, the
  // Darboux vector's components.
  bool recheckPlanar(const PlanarState& s);
  bool recheckSpatial(const SpatialState& s);

  const char* name_;
  TwoLineLaw law_;
  bool plastic_;
  int first_, count_;
  // Per joint and component, allocated only when plastic.
  std::vector<double> upper_, x_committed_;
  std::vector<signed char> line_;            // implicit steps' frozen line per law
  std::vector<signed char> line_committed_;  // the lines of the last accepted step
  int from_ = 0, to_ = 0;                    // laws of the present implicit step
  double work_committed_ = 0.0;
  RotationalSpring* partner_ = nullptr;  // evaluated in this pass
  bool in_shared_pass_ = false;          // evaluated in another spring's pass
};

}  // namespace cws
