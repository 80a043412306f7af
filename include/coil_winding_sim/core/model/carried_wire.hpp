// The wound wire the core carries rigidly (solver.carry_stuck_wire): each
// carried point's pose in the core frame, placed in the world as the core
// turns; the kinetic energy the core gives it; its stand-off from the
// winding surface, fixed while it is carried; and the decision after each
// accepted step of what the core carries (carry_decision.cpp), which
// WireModel carries out (wound_wire.cpp).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <limits>
#include <vector>

#include "coil_winding_sim/core/base/wire_types.hpp"

namespace cws {

class Contact;
class CoreSection;
class RotatingCore;
class Stretching;

class CarriedWire {
 public:
  // Storage for `capacity` points when `enabled` (else none).
  CarriedWire(int capacity, bool enabled);
  bool enabled() const { return enabled_; }

  // Point i's pose in the core frame: position [m] and frame.
  const Eigen::Vector3d& positionCore(int i) const { return p_core_[i]; }
  const Eigen::Vector4d& orientationCore(int i) const { return q_core_[i]; }
  // All positions (index i: point i), for contact with the wound wire.
  const std::vector<Eigen::Vector3d>& positionsCore() const { return p_core_; }

  // Takes point i on at time t [s] from its world pose (p_world [m], q).
  void takeOn(const RotatingCore& core, double t, int i, const Eigen::Vector3d& p_world,
              const Eigen::Vector4d& q);
  // Sets point i's pose from a snapshot (core frame).
  void setPose(int i, const Eigen::Vector3d& p_core, const Eigen::Vector4d& q_core);
  // Writes point i's pose and rigid motion with the core at time t [s]
  // into k (the core's pose is found once per t).
  void place(const RotatingCore& core, double t, int i, WireKinematics& k);

  // The kinetic energy the core gives points 1..first-1, turning rigidly
  // with it, from t0 to t1 [s] [J].
  double energyChange(const RotatingCore& core, const WireConstants& c, double t0, double t1) const;
  // Point i's stand-off from the winding surface [m] (found once while it
  // is carried; `radius` the wire's [m]).
  double standOff(const CoreSection& section, double radius, int i) const;
  // Points 0..k-1 retire (WireModel::retireBuriedWire; `used` points in
  // use, c the wire's constants): the poses of the rest move to the front;
  // the moment of inertia of old points 1..k (k becomes the clamp) stays
  // in the core's work on the carried wire.
  void retireFront(int k, int used, const WireConstants& c);
  // Moment of inertia about the core axis of the retired wire [kg m^2]
  // (and its restore from a snapshot).
  double retiredInertia() const { return retired_inertia_; }
  void setRetiredInertia(double inertia) { retired_inertia_ = inertia; }
  // Points changed (a release, a restored snapshot): the energy's sum and
  // the stand-offs are found anew, the core's pose too.
  void forgetSums();
  void forgetAll();

  // What the core carries after an accepted step at t [s], from the
  // committed kinematics k (points first..n-1 integrated) and the
  // contact's stick and slip: the new first integrated point, and whether
  // that is a release (wound wire slipped: points from `first` on are
  // integrated again) rather than points taken on (those below `first`).
  struct Decision {
    int first;
    bool release;
  };
  // (stretching: the axial law, for the tension the carried wire holds at
  // the boundary; null: none known.)
  Decision decide(const Contact& contact, const Stretching* stretching, const RotatingCore& core,
                  const WireConstants& c, const WireKinematics& k, double t) const;

 private:
  // The first point, going back from point `from` to `down_to`, where the
  // wire has turned half a turn about the core axis (-1: it does not).
  int halfTurnBehind(const RotatingCore& core, const WireConstants& c, const WireKinematics& k,
                     double t, int from, int down_to) const;

  bool enabled_;
  std::vector<Eigen::Vector3d> p_core_;
  std::vector<Eigen::Vector4d> q_core_;
  // Stand-off of carried points [m] where known (a cache).
  mutable std::vector<double> stand_off_;
  mutable std::vector<unsigned char> stand_off_known_;
  // Moment of inertia about the core axis, M r^2 + I each [kg m^2], of
  // points 1..inertia_first_-1 (a cache for energyChange; -1: sum anew).
  mutable int inertia_first_ = -1;
  mutable double inertia_ = 0.0;
  double retired_inertia_ = 0.0;  // [kg m^2]
  // The core's pose at the time of the last place() (NaN: none yet).
  double frame_time_ = std::numeric_limits<double>::quiet_NaN();
  Eigen::Matrix3d rot_;
  Eigen::Quaterniond q_;
  Eigen::Vector3d w_;
};

}  // namespace cws
