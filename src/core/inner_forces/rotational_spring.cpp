#include "coil_winding_sim/core/inner_forces/rotational_spring.hpp"

#include "coil_winding_sim/core/quaternion.hpp"

namespace cws {

RotationalSpring::RotationalSpring(const char* name, const WireConstants& c,
                                   const HysteresisParams& p, bool plastic, int first, int count)
    : name_(name), c_(c), law_(p), plastic_(plastic), first_(first), count_(count) {
  if (plastic_) {
    upper_.assign(static_cast<std::size_t>(c_.capacity - 1) * count_, law_.initialUpper());
    x_committed_.assign(static_cast<std::size_t>(c_.capacity - 1) * count_, 0.0);
  }
}

double RotationalSpring::jointLength(int j) const {
  return j == 0 ? 0.5 * c_.segment_length : c_.segment_length;
}

Eigen::Vector3d RotationalSpring::darboux(const WireKinematics& k, int j) const {
  return (2.0 / jointLength(j)) * (quat::G(k.q.col(j)) * k.q.col(j + 1));
}

double RotationalSpring::stressOf(double x, int idx) const {
  return plastic_ ? law_.stress(x, upper_[idx]) : law_.elasticRigidity() * x;
}

double RotationalSpring::moment(const WireKinematics& k, int j, int m) const {
  return stressOf(darboux(k, j)[first_ + m], j * count_ + m);
}

double RotationalSpring::plasticValue(int j, int m) const {
  return plastic_ ? law_.plasticStrain(upper_[j * count_ + m]) : 0.0;
}

void RotationalSpring::addForces(double, const WireKinematics& k, WireForces& f) const {
  for (int j = c_.first - 1; j + 1 < c_.n; ++j) {
    const quat::Vec4 qa = k.q.col(j);
    const quat::Vec4 qb = k.q.col(j + 1);
    const Eigen::Vector3d omega = (2.0 / jointLength(j)) * (quat::G(qa) * qb);
    Eigen::Vector3d m = Eigen::Vector3d::Zero();
    for (int i = 0; i < count_; ++i) m[first_ + i] = stressOf(omega[first_ + i], j * count_ + i);
    // -lambda m . dOmega/dq with dOmega/dq_b = (2/lambda) G(q_a) and
    // dOmega/dq_a = -(2/lambda) G(q_b): the joint length lambda cancels.
    f.f_q.col(j) += 2.0 * quat::G(qb).transpose() * m;
    f.f_q.col(j + 1) -= 2.0 * quat::G(qa).transpose() * m;
  }
}

void RotationalSpring::commit(double, const WireKinematics& k) {
  if (!plastic_) return;
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
    x_committed_[idx] = 0.0;
  }
}

double RotationalSpring::elasticEnergy(const WireKinematics& k) const {
  double e = 0.0;
  for (int j = 0; j + 1 < c_.n; ++j) {
    for (int i = 0; i < count_; ++i) e += jointLength(j) * law_.elasticEnergy(moment(k, j, i));
  }
  return e;
}

double RotationalSpring::plasticWork(const WireKinematics& k) const {
  return plastic_ ? work_committed_ - elasticEnergy(k) : 0.0;
}

void RotationalSpring::appendHistory(std::vector<double>& out) const {
  if (!plastic_) return;
  const std::size_t used = static_cast<std::size_t>(c_.n - 1) * count_;
  out.insert(out.end(), upper_.begin(), upper_.begin() + used);
  out.insert(out.end(), x_committed_.begin(), x_committed_.begin() + used);
  out.push_back(work_committed_);
}

void RotationalSpring::restoreHistory(HistoryReader& in) {
  if (!plastic_) return;
  const std::size_t used = static_cast<std::size_t>(c_.n - 1) * count_;
  for (std::size_t i = 0; i < used; ++i) upper_[i] = in.next();
  for (std::size_t i = 0; i < used; ++i) x_committed_[i] = in.next();
  work_committed_ = in.next();
}

}  // namespace cws
