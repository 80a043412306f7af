// The paper's two-line elastoplastic hysteresis, eqs. (7)-(15) and Fig. 5.
//
// Per unit length: generalized strain x (axial strain [-], curvature [1/m] or
// twist rate [rad/m]) and generalized stress s (axial force [N], bending or
// twisting moment [N m]); tension and counter-clockwise moments positive.
//
// Read with one sign convention, the paper's three laws are the same law:
//   upper plastic line  s = k_p x + C,          C = a (k_e - k_p)
//   lower plastic line  s = k_p x - C
//   elastic line        s = k_e (x - x_u) + k_p x_u + C   between the yield
//                       points x_l = x_u - 2a <= x <= x_u
// where a is the first yield (the paper's a, b, c) and x_u the current upper
// yield point (e_ye, alpha_ya, theta_ya). Beyond x_u the point rides the upper
// line and x_u moves to x; below x_l it rides the lower line and x_l moves to
// x (both yield points move together, 2a apart: linear kinematic hardening,
// Fig. 5). The only state is x_u.
#pragma once

namespace cws {

// One law's numbers (the scene's wire.stretch, wire.bend, wire.torsion).
struct HysteresisParams {
  double elastic_rigidity = 0.0;  // slope of the elastic line [N] or [N m^2]
  double plastic_rigidity = 0.0;  // slope of the plastic lines, <= elastic
  double yield = 0.0;             // first yield, strain [-], [1/m] or [rad/m]
};

class TwoLineLaw {
 public:
  TwoLineLaw() = default;
  explicit TwoLineLaw(const HysteresisParams& p)
      : k_e_(p.elastic_rigidity),
        k_p_(p.plastic_rigidity),
        a_(p.yield),
        c_(p.yield * (p.elastic_rigidity - p.plastic_rigidity)) {}

  // Upper yield point of virgin material.
  double initialUpper() const { return a_; }

  // Stress at strain x given the committed upper yield point x_u. Pure: it
  // does not move the yield points (trial evaluation inside a step).
  double stress(double x, double x_u) const {
    if (x > x_u) return k_p_ * x + c_;
    if (x < x_u - 2.0 * a_) return k_p_ * x - c_;
    return k_e_ * (x - x_u) + k_p_ * x_u + c_;
  }

  // The line x lies on given x_u: +1 upper plastic, -1 lower plastic, 0
  // elastic.
  static constexpr int kUpper = 1, kElastic = 0, kLower = -1;
  int branch(double x, double x_u) const {
    if (x > x_u) return kUpper;
    if (x < x_u - 2.0 * a_) return kLower;
    return kElastic;
  }
  // Whether a frozen line still holds at x: the line x lies on, or a
  // neighbouring one that x has crossed into by less than 1e-4 of the first
  // yield (the two lines then differ by less than 1e-4 C in stress), so that
  // a law resting at its yield point does not flip between lines.
  bool lineHolds(double x, double x_u, int line) const {
    const double tol = 1.0e-4 * a_;
    if (line == kUpper) return x >= x_u - tol;
    if (line == kLower) return x <= x_u - 2.0 * a_ + tol;
    return x <= x_u + tol && x >= x_u - 2.0 * a_ - tol;
  }
  // Stress on a given line, extended beyond its end (implicit steps freeze
  // each law's line within a Newton solve and recheck it after), and its
  // slope.
  double stressOnBranch(double x, double x_u, int line, double& tangent) const {
    if (line == kUpper) {
      tangent = k_p_;
      return k_p_ * x + c_;
    }
    if (line == kLower) {
      tangent = k_p_;
      return k_p_ * x - c_;
    }
    tangent = k_e_;
    return k_e_ * (x - x_u) + k_p_ * x_u + c_;
  }

  // Consistent tangent ds/dx at strain x from the committed x_u: the
  // slope of the line stress() is on (the return map of a step that starts
  // at x_u) [N] or [N m^2].
  double tangent(double x, double x_u) const {
    return (x > x_u || x < x_u - 2.0 * a_) ? k_p_ : k_e_;
  }

  // Upper yield point after the material has reached x (commit on an
  // accepted step).
  double movedUpper(double x, double x_u) const {
    if (x > x_u) return x;
    if (x < x_u - 2.0 * a_) return x + 2.0 * a_;
    return x_u;
  }

  // Plastic (permanent) strain: where the current elastic line meets s = 0.
  double plasticStrain(double x_u) const { return x_u - (k_p_ * x_u + c_) / k_e_; }

  // Recoverable elastic energy density at stress s [J/m].
  double elasticEnergy(double s) const { return 0.5 * s * s / k_e_; }

  // Work density done on the material from x0 to x1 with x_u fixed [J/m]:
  // the exact integral of the piecewise-linear stress(x, x_u).
  double work(double x0, double x1, double x_u) const {
    const double lo = x_u - 2.0 * a_;
    double w = 0.0;
    double from = x0;
    // Integrate piecewise, splitting at the two yield points.
    const double breaks[2] = {x1 > x0 ? lo : x_u, x1 > x0 ? x_u : lo};
    for (double b : breaks) {
      const bool between = (x1 > x0) ? (b > from && b < x1) : (b < from && b > x1);
      if (between) {
        w += 0.5 * (stress(from, x_u) + stress(b, x_u)) * (b - from);
        from = b;
      }
    }
    w += 0.5 * (stress(from, x_u) + stress(x1, x_u)) * (x1 - from);
    return w;
  }

  double elasticRigidity() const { return k_e_; }

 private:
  double k_e_ = 0.0;
  double k_p_ = 0.0;
  double a_ = 0.0;
  double c_ = 0.0;
};

}  // namespace cws
