#include "coil_winding_sim/core/external_forces/supply.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "coil_winding_sim/core/base/quaternion.hpp"

namespace cws {

namespace {

// Strain on the virgin loading curve of the stretch law at axial force f.
double virginStrain(const HysteresisParams& p, double f) {
  const double yield_force = p.elastic_rigidity * p.yield;
  if (f <= yield_force || p.plastic_rigidity <= 0.0) return f / p.elastic_rigidity;
  return p.yield + (f - yield_force) / p.plastic_rigidity;
}
}  // namespace

Supply::Supply(const WireConstants& c, const Scene& s, const RotatingCore* core)
    : SinkEffect(c),
      core_(core),
      port0_world_(s.supply.port_position_world),
      axis_world_(s.core.axis_world.normalized()),
      profile_(TraverseProfile::of(s.process.traverse_pitch, s.process.winding_width,
                                   s.wire.diameter, s.traverseLayers())
                   .stalled(s.process.traverse_stall_turn, s.process.traverse_stall_turns)),
      core_origin_world_(s.core.position_world),
      setpoint_(s.process.tension),
      tension_(s.process.tension),
      nozzle_exponent_(s.supply.nozzle_friction * s.supply.nozzle_wrap_angle),
      stick_speed_(s.contact.stick_speed),
      segment_length_(c.segment_length) {
  if (s.supply.tensioner.kind == "dancer") {
    tensioner_.emplace(s.supply.tensioner, s.wire.stretch.elastic_rigidity, setpoint_);
  }
  machine_ = tensioner_ || nozzle_exponent_ > 0.0;
  // Room for a ripple per turn of the run (turns beyond it count in the
  // largest and the mean only).
  const double turns = s.process.duration ? 0.0 : s.process.turns;
  trace_.ripple_per_turn.reserve(static_cast<std::size_t>(std::min(1.5 * turns, 1.0e6)) + 64);
  for (const CylinderParams& cyl : s.core.cylinders) {
    swept_radius_ = std::max(swept_radius_, cyl.center_core.norm() + cyl.radius + c.radius);
  }
  stretch_ = s.wire.stretch;
  if (!s.physics.plasticity) stretch_.plastic_rigidity = stretch_.elastic_rigidity;
  strain_ = virginStrain(stretch_, tension_);
}

void Supply::setTension(double tension) {
  setpoint_ = tension;
  if (tensioner_) {
    tensioner_->setSetpoint(tension);
    return;  // the arm's load: the port follows through the arm
  }
  updatePortTension();
}

void Supply::updatePortTension() {
  const double behind = tensioner_ ? tensioner_->tension() : setpoint_;
  tension_ = nozzle_exponent_ > 0.0
                 ? behind * capstanRatio(nozzle_exponent_, 1.0, draw_in_, stick_speed_)
                 : behind;
  strain_ = virginStrain(stretch_, tension_);
}

void Supply::afterStep(double t, double fed_length_m, double measured_N, double core_turns) {
  trace_.note(core_turns, measured_N);
  // The last step's end: the newest draw-in sample (the start: none).
  const double t_last = fed_samples_ > 0 ? fed_at_t_[fed_newest_] : 0.0;
  const double fed_last = fed_samples_ > 0 ? fed_at_m_[fed_newest_] : 0.0;
  if (!machine_ || !(t > t_last)) return;
  // The draw-in speed over the step, held while the tensioner follows it;
  // the port's tension pulled through the step (tension_) did the work.
  draw_in_ = drawInSpeed(t, fed_length_m);
  port_work_ += tension_ * (fed_length_m - fed_last) * (1.0 + strain_);
  if (tensioner_) tensioner_->advance(t, draw_in_);
  updatePortTension();
}

double Supply::drawInSpeed(double t, double fed_length_m) {
  fed_newest_ = (fed_newest_ + 1) % kFedSamples;
  fed_at_t_[fed_newest_] = t;
  fed_at_m_[fed_newest_] = fed_length_m;
  fed_samples_ = std::min(fed_samples_ + 1, kFedSamples);
  // Back from the newest sample to the first one a segment's length or
  // more behind it (or the oldest held; the start counts as one).
  double t0 = 0.0, m0 = 0.0;
  bool found = false;
  for (int i = 1; i < fed_samples_; ++i) {
    const int j = (fed_newest_ - i + kFedSamples) % kFedSamples;
    t0 = fed_at_t_[j];
    m0 = fed_at_m_[j];
    if (std::abs(fed_length_m - m0) >= segment_length_) {
      found = true;
      break;
    }
  }
  if (!found && fed_samples_ < kFedSamples) t0 = m0 = 0.0;
  return t > t0 ? (fed_length_m - m0) / (t - t0) : 0.0;
}

void TensionTrace::note(double core_turns, double tension_N) {
  const int now = static_cast<int>(std::floor(core_turns));
  if (!seen) {
    peak = low = turn_max = turn_min = tension_N;
    turn = now;
    seen = true;
    return;
  }
  if (now != turn) {
    // A whole turn ended (a turn the core ran backwards through counts too).
    const double ripple = turn_max - turn_min;
    if (ripple_per_turn.size() < ripple_per_turn.capacity()) ripple_per_turn.push_back(ripple);
    ripple_max = std::max(ripple_max, ripple);
    ripple_sum += ripple;
    ++ripple_turns;
    turn = now;
    turn_max = turn_min = tension_N;
  }
  peak = std::max(peak, tension_N);
  low = std::min(low, tension_N);
  turn_max = std::max(turn_max, tension_N);
  turn_min = std::min(turn_min, tension_N);
}

MachineEnergy Supply::machineEnergy() const {
  MachineEnergy e;
  if (!tensioner_) return e;
  // The tensioner and the nozzle within the balance: the port's work on the
  // wire drawn in is theirs, what the span did not take the nozzle lost.
  e.kinetic = tensioner_->kinetic();
  e.elastic = tensioner_->elastic();
  e.dissipated = tensioner_->damped() + (port_work_ - tensioner_->drawnWork());
  e.work_done = tensioner_->loadWork() + tensioner_->payOffWork() + port_work_;
  return e;
}

void Supply::appendHistory(std::vector<double>& out) const {
  out.insert(out.end(),
             {draw_in_, port_work_, trace_.peak, trace_.low, trace_.seen ? 1.0 : 0.0,
              static_cast<double>(trace_.turn), trace_.turn_max, trace_.turn_min, trace_.ripple_max,
              trace_.ripple_sum, static_cast<double>(trace_.ripple_turns),
              static_cast<double>(trace_.ripple_per_turn.size())});
  out.insert(out.end(), trace_.ripple_per_turn.begin(), trace_.ripple_per_turn.end());
  if (tensioner_) {
    double v[Tensioner::kValues];
    tensioner_->save(v);
    out.insert(out.end(), v, v + Tensioner::kValues);
  }
  if (machine_) {
    // The draw-in samples, oldest first.
    out.push_back(fed_samples_);
    for (int i = fed_samples_ - 1; i >= 0; --i) {
      const int j = (fed_newest_ - i + kFedSamples) % kFedSamples;
      out.insert(out.end(), {fed_at_t_[j], fed_at_m_[j]});
    }
  }
}

void Supply::restoreHistory(HistoryReader& in) {
  draw_in_ = in.next();
  port_work_ = in.next();
  trace_.peak = in.next();
  trace_.low = in.next();
  trace_.seen = in.nextInteger(0, 1, "tension trace flag") == 1;
  trace_.turn = in.nextInteger(-1000000000, 1000000000, "tension trace turn");
  trace_.turn_max = in.next();
  trace_.turn_min = in.next();
  trace_.ripple_max = in.next();
  trace_.ripple_sum = in.next();
  trace_.ripple_turns = in.nextInteger(0, 1000000000, "tension trace whole turns");
  const int turns = in.nextInteger(0, 100000000, "tension trace turns");
  trace_.ripple_per_turn.clear();
  trace_.ripple_per_turn.reserve(
      std::max(trace_.ripple_per_turn.capacity(), static_cast<std::size_t>(turns)));
  for (int i = 0; i < turns; ++i) trace_.ripple_per_turn.push_back(in.next());
  if (tensioner_) {
    double v[Tensioner::kValues];
    for (double& x : v) x = in.next();
    tensioner_->restore(v);
  }
  if (machine_) {
    fed_samples_ = in.nextInteger(0, kFedSamples, "draw-in samples");
    fed_newest_ = fed_samples_ > 0 ? fed_samples_ - 1 : 0;
    for (int i = 0; i < fed_samples_; ++i) {
      fed_at_t_[i] = in.next();
      fed_at_m_[i] = in.next();
    }
  }
  updatePortTension();
}

void Supply::commit(const AcceptedStep& step) { command_.commit(step.t); }

void Supply::commandPort(double t_s, const Eigen::Vector3d& p_world, double t_now) {
  if (swept_radius_ > 0.0 && p_world.allFinite()) {
    // Distance from the core axis: inside the swept core the wire could not
    // leave the port.
    const Eigen::Vector3d r = p_world - core_origin_world_;
    const double radial = (r - r.dot(axis_world_) * axis_world_).norm();
    if (radial < swept_radius_) {
      std::ostringstream msg;
      msg << "port command (" << p_world.x() << ", " << p_world.y() << ", " << p_world.z()
          << ") m at t = " << t_s << " s lies inside the turning core: " << radial
          << " m from its axis, the core with the wire reaches " << swept_radius_ << " m";
      throw std::invalid_argument(msg.str());
    }
  }
  command_.append(t_s, p_world, t_now, port(t_now).p_world);
}

PortMotion Supply::port(double t) const {
  if (command_.active()) return command_.at(t);
  PortMotion m;
  m.p_world = port0_world_;
  if (core_ && profile_.pitch != 0.0) {
    // The traverse, geared to the core's angle (traverse_profile.hpp).
    const TraverseProfile::Position tp = profile_.at(core_->angle(t));
    m.p_world += tp.offset * axis_world_;
    m.v_world = tp.per_rad * core_->omega(t) * axis_world_;
    m.a_world = tp.per_rad * core_->angularAcceleration(t) * axis_world_;
  }
  return m;
}

}  // namespace cws
