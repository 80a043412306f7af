#include "coil_winding_sim/core/inner_forces/stretching.hpp"

#include <algorithm>

namespace cws {

Stretching::Stretching(const WireConstants& c, const HysteresisParams& p, bool plastic)
    : SinkEffect(c), law_(p), plastic_(plastic) {
  if (plastic_) {
    upper_.assign(c_.capacity - 1, law_.initialUpper());
    x_committed_.assign(c_.capacity - 1, 0.0);
    line_.assign(c_.capacity - 1, TwoLineLaw::kElastic);
    line_committed_ = line_;
  }
}

double Stretching::strain(const WireKinematics& k, int j) const {
  return ((k.p_world.col(j + 1) - k.p_world.col(j)).norm() - c_.segment_length) / c_.segment_length;
}

double Stretching::stressOf(double x, int j) const {
  return plastic_ ? law_.stress(x, upper_[j]) : law_.elasticRigidity() * x;
}

double Stretching::stressTangent(double x, int j, bool mapped, double& tangent) const {
  if (!plastic_) {
    tangent = law_.elasticRigidity();
    return tangent * x;
  }
  if (mapped) {
    tangent = law_.tangent(x, upper_[j]);
    return law_.stress(x, upper_[j]);
  }
  return law_.stressOnBranch(x, upper_[j], line_[j], tangent);
}

template <class State>
void Stretching::beginLines(const State& s0) {
  if (!plastic_) return;
  from_ = s0.first - 1;
  to_ = s0.n - 1;
  // Every solve of a step (a retried one too) starts from the lines of the
  // last accepted step (a snapshot carries them); a line the commit left
  // not holding is switched by the recheck after the first solve
  // (docs/MODEL.md, "What is frozen within one Newton solve").
  std::copy(line_committed_.begin() + from_, line_committed_.begin() + to_, line_.begin() + from_);
}

template <class State>
bool Stretching::recheckLines(const State& s) {
  if (!plastic_) return false;
  bool changed = false;
  const double l = c_.segment_length;
  for (int j = s.first - 1; j + 1 < s.n; ++j) {
    const double x = (s.segment(j).norm() - l) / l;
    // Return-mapped: the line the solve used, recorded for the commit.
    if (s.return_mapping) {
      line_[j] = static_cast<signed char>(law_.branch(x, upper_[j]));
      continue;
    }
    if (!law_.lineHolds(x, upper_[j], line_[j])) {
      line_[j] = static_cast<signed char>(law_.branch(x, upper_[j]));
      changed = true;
      s.flagChangedAt(j + 1);
    }
  }
  return changed;
}

void Stretching::beginStep(const NewtonView& s0) {
  s0.visit([&](const auto& s) { beginLines(s); });
}
bool Stretching::recheck(const NewtonView& s) {
  return s.visit([&](const auto& st) { return recheckLines(st); });
}

double Stretching::axialForce(const WireKinematics& k, int j) const {
  return stressOf(strain(k, j), j);
}

double Stretching::plasticStrain(int j) const {
  return plastic_ ? law_.plasticStrain(upper_[j]) : 0.0;
}

template <class Sink>
void Stretching::law(Sink& s) const {
  using Vec = typename Sink::Vec;
  using Mat = typename Sink::Mat;
  const double l = c_.segment_length;
  for (int j = s.first() - 1; j + 1 < s.n(); ++j) {
    const Vec d = s.segment(j);
    const double len = d.norm();
    const double x = (len - l) / l;
    const bool jacobian = s.jacobian(j);
    // (Forces alone, with the lines decided here: the stress alone.)
    double k = 0.0;
    const double tension =
        s.returnMapping() && !jacobian ? stressOf(x, j) : stressTangent(x, j, s.returnMapping(), k);
    const Vec t = d / len;
    s.addForce(j, tension * t);
    s.addForce(j + 1, -tension * t);
    if (!jacobian) continue;
    const Mat tt = t * t.transpose();
    const Mat kb = (k / l) * tt + (tension / len) * (Mat::Identity() - tt);
    s.addStiffness(j + 1, j + 1, -kb);
    s.addStiffness(j + 1, j, kb);
    s.addStiffness(j, j, -kb);
    s.addStiffness(j, j + 1, kb);
  }
}
template void Stretching::law(ExplicitSink&) const;
template void Stretching::law(PlanarSink&) const;
template void Stretching::law(SpatialSink&) const;

void Stretching::commit(const AcceptedStep& step) {
  if (!plastic_) return;
  // A Newton step's lines are the step's.
  if (step.newton)
    std::copy(line_.begin() + from_, line_.begin() + to_, line_committed_.begin() + from_);
  const WireKinematics& k = step.k;
  // Carried segments do not deform: nothing to commit.
  for (int j = c_.first - 1; j + 1 < c_.n; ++j) {
    const double x = strain(k, j);
    work_committed_ += c_.segment_length * law_.work(x_committed_[j], x, upper_[j]);
    upper_[j] = law_.movedUpper(x, upper_[j]);
    x_committed_[j] = x;
  }
}

double Stretching::elasticEnergy(const WireKinematics& k) const {
  double e = 0.0;
  for (int j = 0; j + 1 < c_.n; ++j) e += law_.elasticEnergy(axialForce(k, j));
  return e * c_.segment_length;
}

EffectEnergy Stretching::energy(const WireKinematics& k) const {
  const double e = elasticEnergy(k);
  return {e, plastic_ ? work_committed_ - e : 0.0};
}

double Stretching::virginWork(double x) const {
  if (!plastic_) return 0.5 * law_.elasticRigidity() * x * x * c_.segment_length;
  return c_.segment_length * law_.work(0.0, x, law_.initialUpper());
}

void Stretching::loadVirgin(const WireKinematics& k, int j) {
  const double x = strain(k, j);
  upper_[j] = law_.movedUpper(x, law_.initialUpper());
  x_committed_[j] = x;
  work_committed_ += c_.segment_length * law_.work(0.0, x, law_.initialUpper());
}

void Stretching::grow(const WireKinematics& k) {
  // The new segment arrives pre-stretched by the supply tension along the
  // virgin loading curve: its yield point and committed strain follow it.
  if (!plastic_) return;
  loadVirgin(k, c_.n - 2);
  line_[c_.n - 2] = line_committed_[c_.n - 2] = TwoLineLaw::kElastic;
}

void Stretching::shrink(const WireKinematics& k) {
  if (!plastic_) return;
  const int j = c_.n - 2;
  work_committed_ -= c_.segment_length * law_.elasticEnergy(axialForce(k, j));
  upper_[j] = law_.initialUpper();
  line_[j] = line_committed_[j] = TwoLineLaw::kElastic;
  x_committed_[j] = 0.0;
}

void Stretching::retireFront(int k) {
  if (!plastic_) return;
  const std::size_t drop = k, used = c_.n - 1;
  dropFront(upper_, drop, used, law_.initialUpper());
  dropFront(x_committed_, drop, used, 0.0);
  dropFront(line_, drop, used, static_cast<signed char>(TwoLineLaw::kElastic));
  dropFront(line_committed_, drop, used, static_cast<signed char>(TwoLineLaw::kElastic));
}

void Stretching::preload(const WireKinematics& k) {
  if (!plastic_) return;
  for (int j = 0; j + 1 < c_.n; ++j) loadVirgin(k, j);
}

void Stretching::appendHistory(std::vector<double>& out) const {
  if (!plastic_) return;
  out.insert(out.end(), upper_.begin(), upper_.begin() + (c_.n - 1));
  out.insert(out.end(), x_committed_.begin(), x_committed_.begin() + (c_.n - 1));
  out.push_back(work_committed_);
  // The implicit steps' lines: a continued run starts from the same ones.
  out.insert(out.end(), line_committed_.begin(), line_committed_.begin() + (c_.n - 1));
}

void Stretching::restoreHistory(HistoryReader& in) {
  if (!plastic_) return;
  for (int j = 0; j + 1 < c_.n; ++j) upper_[j] = in.next();
  for (int j = 0; j + 1 < c_.n; ++j) x_committed_[j] = in.next();
  work_committed_ = in.next();
  std::fill(line_committed_.begin(), line_committed_.end(), TwoLineLaw::kElastic);
  for (int j = 0; j + 1 < c_.n; ++j) {
    line_committed_[j] = static_cast<signed char>(
        in.nextInteger(TwoLineLaw::kLower, TwoLineLaw::kUpper, "stretching hysteresis line"));
  }
  line_ = line_committed_;
}

}  // namespace cws
