#include "coil_winding_sim/core/inner_forces/rotational_spring.hpp"

#include <algorithm>
#include <cmath>

#include "coil_winding_sim/core/base/quaternion.hpp"

namespace cws {

RotationalSpring::RotationalSpring(const char* name, const WireConstants& c,
                                   const HysteresisParams& p, bool plastic, int first, int count)
    : SinkEffect(c), name_(name), law_(p), plastic_(plastic), first_(first), count_(count) {
  if (plastic_) {
    upper_.assign(static_cast<std::size_t>(c_.capacity - 1) * count_, law_.initialUpper());
    x_committed_.assign(static_cast<std::size_t>(c_.capacity - 1) * count_, 0.0);
    line_.assign(static_cast<std::size_t>(c_.capacity - 1) * count_, TwoLineLaw::kElastic);
    line_committed_ = line_;
  }
}

double RotationalSpring::jointLength(int j) const {
  // (Joint 0 of the whole wire, at the fixed end, stands for half a segment.)
  return j + c_.retired == 0 ? 0.5 * c_.segment_length : c_.segment_length;
}

Eigen::Vector3d RotationalSpring::darboux(const WireKinematics& k, int j) const {
  return (2.0 / jointLength(j)) * quat::gTimes(k.q.col(j), k.q.col(j + 1));
}

double RotationalSpring::stressOf(double x, int idx) const {
  return plastic_ ? law_.stress(x, upper_[idx]) : law_.elasticRigidity() * x;
}

double RotationalSpring::stressTangent(double x, int idx, bool mapped, double& tangent) const {
  if (!plastic_) {
    tangent = law_.elasticRigidity();
    return tangent * x;
  }
  if (mapped) {
    tangent = law_.tangent(x, upper_[idx]);
    return law_.stress(x, upper_[idx]);
  }
  return law_.stressOnBranch(x, upper_[idx], line_[idx], tangent);
}

void RotationalSpring::beginLines(int first, int n) {
  if (!plastic_) return;
  from_ = (first - 1) * count_;
  to_ = (n - 1) * count_;
  // Every solve of a step (a retried one too) starts from the lines of the
  // last accepted step (a snapshot carries them); see Stretching::beginLines.
  std::copy(line_committed_.begin() + from_, line_committed_.begin() + to_, line_.begin() + from_);
}

template <class Argument>
int RotationalSpring::recheckLines(int first, int n, bool mapped, Argument argument) {
  if (!plastic_) return -1;
  int changed = -1;
  for (int j = first - 1; j + 1 < n; ++j) {
    for (int c = 0; c < count_; ++c) {
      double x;
      if (!argument(j, c, x)) continue;
      const int idx = j * count_ + c;
      // Return-mapped: the line the solve used, recorded for the commit.
      if (mapped) {
        line_[idx] = static_cast<signed char>(law_.branch(x, upper_[idx]));
        continue;
      }
      if (!law_.lineHolds(x, upper_[idx], line_[idx])) {
        line_[idx] = static_cast<signed char>(law_.branch(x, upper_[idx]));
        changed = j;
      }
    }
  }
  return changed;
}

Eigen::Vector3d RotationalSpring::darboux(const SpatialState& s, int j) const {
  return (2.0 / jointLength(j)) * quat::gTimes(s.q.col(j), s.q.col(j + 1));
}

void RotationalSpring::beginStep(const NewtonView& s0) {
  s0.visit([&](const auto& s) { beginLines(s.first, s.n); });
}

bool RotationalSpring::recheck(const NewtonView& s) {
  return s.planar() ? recheckPlanar(*s.planar()) : recheckSpatial(*s.spatial());
}

bool RotationalSpring::recheckPlanar(const PlanarState& s) {
  // The joints in order: segment j serves joints j and j+1 (as in
  // the planar sink).
  int joint = s.first - 2;
  double kappa = 0.0;
  planar::SegmentGeometry ga, gb;
  gb.setPrescribed(s.boundary_tangent);
  return recheckLines(s.first, s.n, s.return_mapping, [&](int j, int c, double& x) {
           const double w = s.n_material[first_ + c];
           if (w == 0.0) return false;
           if (j != joint) {
             ga = gb;
             if (j != joint + 1) ga.set(s.segment(j - 1), false);
             gb.set(s.segment(j), false);
             double sin_half, cos_half;
             kappa = planar::jointCurvature(ga, gb, jointLength(j), sin_half, cos_half);
             joint = j;
           }
           x = kappa * w;
           return true;
         }) >= 0;
}

bool RotationalSpring::recheckSpatial(const SpatialState& s) {
  // One Darboux vector per joint for all of its components.
  int joint = -1;
  Eigen::Vector3d omega;
  const int changed = recheckLines(s.first, s.n, s.return_mapping, [&](int j, int c, double& x) {
    if (j != joint) {
      joint = j;
      omega = darboux(s, j);
    }
    x = omega[first_ + c];
    return true;
  });
  // (The highest joint changed, j to j + 1.)
  if (changed >= 0) s.flagChangedAt(changed + 1);
  return changed >= 0;
}

double RotationalSpring::moment(const WireKinematics& k, int j, int m) const {
  return stressOf(darboux(k, j)[first_ + m], j * count_ + m);
}

double RotationalSpring::plasticValue(int j, int m) const {
  return plastic_ ? law_.plasticStrain(upper_[j * count_ + m]) : 0.0;
}

template <class Sink>
void RotationalSpring::law(Sink& s) const {
  if (in_shared_pass_) return;
  // The components this formulation moves (the plane: those along its
  // normal; none for torsion), each with its spring, found once.
  struct Moved {
    const RotationalSpring* spring;
    int component, law;
  };
  Moved moved[3];
  int count = 0;
  for (const RotationalSpring* r : {this, static_cast<const RotationalSpring*>(partner_)}) {
    if (!r) continue;
    for (int i = 0; i < r->count_; ++i) {
      if (s.jointComponent(r->first_ + i)) moved[count++] = {r, r->first_ + i, i};
    }
  }
  if (count == 0) return;
  const bool mapped = s.returnMapping();
  for (int j = s.first() - 1; j + 1 < s.n(); ++j) {
    const double lambda = jointLength(j);
    const Eigen::Vector3d omega = s.darboux(j, lambda);
    // Each component's moment and tangent from its own law (forces alone,
    // with the lines decided here: the moment alone).
    const bool tangent = !mapped || s.jacobian(j);
    Eigen::Vector3d m = Eigen::Vector3d::Zero(), dm = Eigen::Vector3d::Zero();
    for (int k = 0; k < count; ++k) {
      const RotationalSpring& r = *moved[k].spring;
      const int c = moved[k].component, idx = j * r.count_ + moved[k].law;
      if (tangent) {
        m[c] = r.stressTangent(omega[c], idx, mapped, dm[c]);
      } else {
        m[c] = r.stressOf(omega[c], idx);
      }
    }
    s.addJointMoment(j, lambda, m, dm);
  }
}
template void RotationalSpring::law(ExplicitSink&) const;
template void RotationalSpring::law(PlanarSink&) const;
template void RotationalSpring::law(SpatialSink&) const;

void RotationalSpring::commit(const AcceptedStep& step) {
  if (!plastic_) return;
  // A Newton step's lines are the step's.
  if (step.newton)
    std::copy(line_.begin() + from_, line_.begin() + to_, line_committed_.begin() + from_);
  const WireKinematics& k = step.k;
  // Carried joints do not deform: nothing to commit.
  for (int j = c_.first - 1; j + 1 < c_.n; ++j) {
    const Eigen::Vector3d omega = darboux(k, j);
    for (int i = 0; i < count_; ++i) {
      const int idx = j * count_ + i;
      const double x = omega[first_ + i];
      work_committed_ += jointLength(j) * law_.work(x_committed_[idx], x, upper_[idx]);
      upper_[idx] = law_.movedUpper(x, upper_[idx]);
      x_committed_[idx] = x;
    }
  }
}

void RotationalSpring::shrink(const WireKinematics& k) {
  if (!plastic_) return;
  const int j = c_.n - 2;
  for (int i = 0; i < count_; ++i) {
    const int idx = j * count_ + i;
    work_committed_ -= jointLength(j) * law_.elasticEnergy(moment(k, j, i));
    upper_[idx] = law_.initialUpper();
    line_[idx] = line_committed_[idx] = TwoLineLaw::kElastic;
    x_committed_[idx] = 0.0;
  }
}

void RotationalSpring::retireFront(int k) {
  if (!plastic_) return;
  const std::size_t drop = static_cast<std::size_t>(k) * count_;
  const std::size_t used = static_cast<std::size_t>(c_.n - 1) * count_;
  dropFront(upper_, drop, used, law_.initialUpper());
  dropFront(x_committed_, drop, used, 0.0);
  dropFront(line_, drop, used, static_cast<signed char>(TwoLineLaw::kElastic));
  dropFront(line_committed_, drop, used, static_cast<signed char>(TwoLineLaw::kElastic));
}

double RotationalSpring::elasticEnergy(const WireKinematics& k) const {
  double e = 0.0;
  for (int j = 0; j + 1 < c_.n; ++j) {
    for (int i = 0; i < count_; ++i) e += jointLength(j) * law_.elasticEnergy(moment(k, j, i));
  }
  return e;
}

EffectEnergy RotationalSpring::energy(const WireKinematics& k) const {
  const double e = elasticEnergy(k);
  return {e, plastic_ ? work_committed_ - e : 0.0};
}

void RotationalSpring::appendHistory(std::vector<double>& out) const {
  if (!plastic_) return;
  const std::size_t used = static_cast<std::size_t>(c_.n - 1) * count_;
  out.insert(out.end(), upper_.begin(), upper_.begin() + used);
  out.insert(out.end(), x_committed_.begin(), x_committed_.begin() + used);
  out.push_back(work_committed_);
  // The implicit steps' lines: a continued run starts from the same ones.
  out.insert(out.end(), line_committed_.begin(), line_committed_.begin() + used);
}

void RotationalSpring::restoreHistory(HistoryReader& in) {
  if (!plastic_) return;
  const std::size_t used = static_cast<std::size_t>(c_.n - 1) * count_;
  for (std::size_t i = 0; i < used; ++i) upper_[i] = in.next();
  for (std::size_t i = 0; i < used; ++i) x_committed_[i] = in.next();
  work_committed_ = in.next();
  std::fill(line_committed_.begin(), line_committed_.end(), TwoLineLaw::kElastic);
  const std::string what = std::string(name_) + " hysteresis line";
  for (std::size_t i = 0; i < used; ++i) {
    line_committed_[i] = static_cast<signed char>(
        in.nextInteger(TwoLineLaw::kLower, TwoLineLaw::kUpper, what.c_str()));
  }
  line_ = line_committed_;
}

}  // namespace cws
