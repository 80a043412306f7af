// The interface of a physical effect (a spring law, gravity, damping,
// contact, the supply), and of the history some effects keep between steps
// (yield points, stick, the lines a Newton solve freezes).
//
// ForceEffect: the forces, added to one of the three sinks
// (force_sink.hpp), and the energy the effect holds. SinkEffect<Law> writes
// the three from one law. EffectHistory: what an effect with history does
// besides; the model and the Newton formulations reach only the effects
// that have one (EffectSet::histories), so a stateless effect (gravity,
// damping) is never called between steps.
#pragma once

#include <vector>

#include "coil_winding_sim/core/assembly/force_sink.hpp"

namespace cws {

// What an effect holds [J]: recoverable elastic energy now, and the work
// turned into plastic deformation since the start.
struct EffectEnergy {
  double elastic = 0.0;
  double plastic = 0.0;
};

class ForceEffect {
 public:
  virtual ~ForceEffect() = default;
  virtual const char* name() const = 0;
  // Adds this effect's forces at the sink's state and time, and on a
  // Newton sink their Jacobian blocks. Must not allocate and must not
  // change history (it runs for trial stages and Newton iterates; a Newton
  // solve's flags are frozen, see EffectHistory).
  virtual void addForces(ExplicitSink& s) const = 0;
  virtual void addForces(PlanarSink& s) const = 0;
  virtual void addForces(SpatialSink& s) const = 0;
  // At the committed kinematics k (reports and the energy balance).
  virtual EffectEnergy energy(const WireKinematics& /*k*/) const { return {}; }
};

// A Newton step's state, in either formulation: visit(f) hands it to a
// generic lambda, or an effect reads the one it handles.
class NewtonView {
 public:
  explicit NewtonView(const PlanarState& s) : planar_(&s) {}
  explicit NewtonView(const SpatialState& s) : spatial_(&s) {}
  const PlanarState* planar() const { return planar_; }
  const SpatialState* spatial() const { return spatial_; }
  template <class F>
  auto visit(F&& f) const {
    if (planar_) return f(*planar_);
    return f(*spatial_);
  }

 private:
  const PlanarState* planar_ = nullptr;
  const SpatialState* spatial_ = nullptr;
};

// An accepted step: its end time [s] and state, and whether it was a Newton
// step (its frozen flags, as last rechecked, are then the step's).
struct AcceptedStep {
  double t;
  const WireKinematics& k;
  bool newton;
};

class EffectHistory {
 public:
  virtual ~EffectHistory() = default;
  // Flags a Newton step keeps frozen within one solve (contact, stick and
  // slip, the laws' lines): set from the committed state at the start of
  // every solve of a step (a retried one too); after a converged solve,
  // rechecked at its end state (true: a flag changed, and the step is to be
  // solved again with the new flags). A 3-D recheck names the highest point
  // whose blocks a changed flag alters (SpatialState::flagChangedAt);
  // without one, the whole system is factored again.
  virtual void beginStep(const NewtonView& /*s0*/) {}
  virtual bool recheck(const NewtonView& /*s*/) { return false; }
  // The one commit, after every accepted step: the Newton step's flags
  // become the committed ones, and history moves on (yield points, stick).
  virtual void commit(const AcceptedStep& step) = 0;
  // Point n-1 was just appended (a wire supply drew it in): initialize the
  // state of the new point, segment n-2 and joint n-2. Runs between steps.
  virtual void grow(const WireKinematics& /*k*/) {}
  // Point n-1 is about to leave (wire drawn back out through the supply
  // port): forget the state of point n-1, segment n-2 and joint n-2, and
  // take their recoverable energy out of the committed work, so that the
  // plastic work done in them stays counted. Runs between steps, before n
  // shrinks.
  virtual void shrink(const WireKinematics& /*k*/) {}
  // Points 0..k-1, carried wire buried under later turns, leave the live
  // arrays (WireModel::retireBuriedWire): drop the state of those points,
  // of segments and joints 0..k-1, and number the rest from 0. The new
  // point 0 (carried) becomes the clamp. Runs between steps, before the
  // model's counts change; the model keeps the retired energy.
  virtual void retireFront(int /*k*/) {}
  // Appends the history (yield points, work bookkeeping, flags) to `out`,
  // for snapshots and tests; restores it for the present number of points
  // (throws on bad data).
  virtual void appendHistory(std::vector<double>& /*out*/) const {}
  virtual void restoreHistory(HistoryReader& /*in*/) {}
};

// A ForceEffect whose law is written once, on a sink: Law derives from
// SinkEffect<Law> and defines `template <class Sink> void law(Sink& s)
// const`.
template <class Law>
class SinkEffect : public ForceEffect {
 public:
  explicit SinkEffect(const WireConstants& c) : c_(c) {}
  void addForces(ExplicitSink& s) const final { static_cast<const Law*>(this)->law(s); }
  void addForces(PlanarSink& s) const final { static_cast<const Law*>(this)->law(s); }
  void addForces(SpatialSink& s) const final { static_cast<const Law*>(this)->law(s); }

 protected:
  const WireConstants& c_;  // the model's: n grows with a supply
};

}  // namespace cws
