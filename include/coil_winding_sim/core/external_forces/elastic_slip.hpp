// Friction as elastic slip (contact.friction_law: elastic_slip), decided by
// return mapping from the committed anchor, the law every integrator
// shares: the explicit steps evaluate it at every step, the Newton steps
// at every iteration (with its consistent tangent), and a commit moves the
// anchor (docs/MODEL.md, "Contact and friction").
//
// The trial force is the stick spring and its dashpot,
//   f_trial = -k_t g - c_t w,
// g the tangential offset of the point from its anchor [m] (the anchor is
// carried with the surface), w the sliding velocity [m/s]. It holds where
// it lies within the cone |f| <= L, L = mu N: mu_s N where the point stuck
// at the last commit, mu_d N where it slid or has just touched. Outside,
// the point slips and the force is returned onto the cone, f = L f_trial /
// |f_trial|; the commit then moves the anchor to where the spring alone
// gives that force. A point that stops sliding sticks without a speed
// threshold, and a stuck point never creeps: stick is a spring to a fixed
// anchor. (Within one step the limit is the committed one: a point that
// breaks loose slips at mu_s N for that step and at mu_d N from the next,
// which keeps the force continuous in the trial state.)
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace cws {

template <int D>
struct SlipReturn {
  using Vec = Eigen::Matrix<double, D, 1>;
  using Mat = Eigen::Matrix<double, D, D>;
  Vec force = Vec::Zero();  // [N]
  bool slipping = false;
  // Slip: the unit direction of the trial force, and L / |f_trial| [-].
  Vec dir = Vec::Zero();
  double ratio = 1.0;

  // The tangent: d force = scale() d f_trial + dir d L.
  Mat scale() const {
    if (!slipping) return Mat::Identity();
    return ratio * (Mat::Identity() - dir * dir.transpose());
  }
};

// The return map of a trial force [N] onto the cone of radius `limit` [N].
template <int D>
SlipReturn<D> returnToCone(const Eigen::Matrix<double, D, 1>& f_trial, double limit) {
  SlipReturn<D> r;
  const double size = f_trial.norm();
  if (size <= limit) {
    r.force = f_trial;
    return r;
  }
  r.slipping = true;
  r.dir = f_trial / size;
  r.ratio = limit / size;
  r.force = limit * r.dir;
  return r;
}

}  // namespace cws
