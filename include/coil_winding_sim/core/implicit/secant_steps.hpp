// Secant (good Broyden) updates of a kept factorization, in the
// error-oriented form of Deuflhard's QNERR (Newton Methods for Nonlinear
// Problems, 2004, section 2.1.4). After full steps dx_0..dx_k taken with
// the factorization of J_0, the step from x_k+1 = x_k + dx_k is
//   v = -J_0^-1 F(x_k+1);  v += dx_i <dx_i-1, v> / |dx_i-1|^2  (i = 1..k);
//   a = <dx_k, v> / |dx_k|^2;  dx_k+1 = v / (1 - a),
// the Newton step of J_0 updated by one rank-one secant condition per step
// taken (J_i+1 dx_i = F(x_i+1) - F(x_i)). A modified Newton solve then
// converges superlinearly instead of linearly, with one solve of J_0 per
// iteration. <a, b> is weighted per unknown (a weight of 0 leaves an
// unknown, e.g. a multiplier, out of the norm).
#pragma once

#include <Eigen/Core>
#include <algorithm>

namespace cws {

class SecantSteps {
 public:
  static constexpr int kMax = 8;  // steps kept; then the factorization is made anew

  // Storage for systems of up to `unknowns` unknowns (once, before a run).
  void reserve(int unknowns) {
    steps_.setZero(unknowns, kMax);
    norm2_.setZero();
  }
  void clear() { count_ = 0; }

  // Turns v = -J_0^-1 F(x) at the iterate the last kept step reached into
  // the updated step. False where the update breaks down (a >= 1/2: the
  // steps do not contract): v is then no step, and J_0 wants refreshing.
  bool correct(Eigen::Ref<Eigen::VectorXd> v, const Eigen::Ref<const Eigen::VectorXd>& w) const {
    if (count_ == 0) return true;
    const int n = static_cast<int>(v.size());
    for (int i = 1; i < count_; ++i) {
      const double c = dot(steps_.col(i - 1).head(n), v, w) / norm2_[i - 1];
      v += c * steps_.col(i).head(n);
    }
    const double a = dot(steps_.col(count_ - 1).head(n), v, w) / norm2_[count_ - 1];
    if (!(a < 0.5)) return false;
    v /= 1.0 - a;
    return true;
  }

  // A full step taken with the present factorization (and its corrections).
  // False: its weighted norm is zero, or no room is left (nothing kept).
  bool push(const Eigen::Ref<const Eigen::VectorXd>& dx,
            const Eigen::Ref<const Eigen::VectorXd>& w) {
    if (count_ == kMax) return false;
    const int n = static_cast<int>(dx.size());
    const double n2 = dot(dx, dx, w);
    if (!(n2 > 0.0)) return false;
    // A longer system than the storage holds (reserve: the integrated span
    // SpatialAssembly reserves) grows it, keeping the steps kept.
    if (n > steps_.rows()) {
      Eigen::MatrixXd grown =
          Eigen::MatrixXd::Zero(std::max<Eigen::Index>(n, 2 * steps_.rows()), kMax);
      grown.topRows(steps_.rows()) = steps_;
      steps_.swap(grown);
    }
    steps_.col(count_).head(n) = dx;
    norm2_[count_++] = n2;
    return true;
  }

 private:
  template <class A, class B>
  static double dot(const A& a, const B& b, const Eigen::Ref<const Eigen::VectorXd>& w) {
    return (a.array() * b.array() * w.head(a.size()).array()).sum();
  }

  Eigen::MatrixXd steps_;
  Eigen::Matrix<double, kMax, 1> norm2_;
  int count_ = 0;
};

}  // namespace cws
