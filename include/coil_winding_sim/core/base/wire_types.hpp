// Shared types of the discrete wire: its constants, per-point kinematics,
// generalized forces and the history readers of snapshots (the interface
// of a physical effect is assembly/force_effect.hpp).
//
// Indexing (0-based): mass points 0..n-1 from the fixed end; segment j joins
// points j and j+1; frame i (quaternion q_i) belongs to point i and, for
// i >= 1, its zeta axis is kept parallel to segment i-1 by the rotational
// constraint (5). Frame 0 is the clamp's frame. Joint j (0 <= j <= n-2) is
// the rotational spring between frames j and j+1, at point j.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace cws {

// Constants of one wire, derived from the scene once; only n changes, when a
// supply draws wire in.
struct WireConstants {
  int n = 0;  // mass points now
  // First integrated point: points 0..first-1 follow prescribed motion (the
  // clamp, and wound wire the core carries, solver.carry_stuck_wire); the
  // effects skip what lies wholly among them.
  int first = 1;
  int capacity = 0;  // most mass points the live arrays hold
  // Points retired in front of point 0 (WireModel::retireBuriedWire): buried
  // wound wire kept compactly, so that point i here is point retired + i of
  // the wire from its fixed end.
  int retired = 0;
  double segment_length = 0.0;  // natural length l [m]
  double point_mass = 0.0;      // M = rho L / n [kg], eq. (1); rho l with a supply
  double point_inertia = 0.0;   // 2/5 M r^2 [kg m^2], eq. (2)
  double radius = 0.0;          // r [m]
  double line_density = 0.0;    // [kg/m]
  double point_length = 0.0;    // wire length a point stands for, M / rho [m]
};

// Moves entries drop..used-1 of v to the front and fills the `drop` entries
// after them with `fill` (EffectHistory::retireFront's arrays; no allocation).
template <class T>
void dropFront(std::vector<T>& v, std::size_t drop, std::size_t used, const T& fill) {
  if (drop == 0) return;
  drop = std::min(drop, used);
  std::move(v.begin() + drop, v.begin() + used, v.begin());
  std::fill(v.begin() + (used - drop), v.begin() + used, fill);
}

// Positions, velocities, quaternions and quaternion rates of all n points
// (column i is point i; point 0 is the clamped end).
struct WireKinematics {
  Eigen::Matrix3Xd p_world;  // [m]
  Eigen::Matrix3Xd v_world;  // [m/s]
  Eigen::Matrix4Xd q;        // (q0, q1, q2, q3), scalar first
  Eigen::Matrix4Xd qd;       // [1/s]
  // The core material's velocity u = core_g_world (p - core_origin_world)
  // [m/s] as the step that led to this state moved the core, where that
  // step's scheme gives it one (Newton steps, WireModel::acceptCoreVelocity).
  bool scheme_core = false;
  Eigen::Matrix3d core_g_world = Eigen::Matrix3d::Zero();
  Eigen::Vector3d core_origin_world = Eigen::Vector3d::Zero();

  // The core material's velocity at p_world [m/s] to measure this state's
  // velocities against, for decisions at the speed stick_speed [m/s]
  // (contact.stick_speed): its exact velocity u_exact, or the scheme's
  // where that differs from it by more than a tenth of stick_speed. A
  // Newton step's velocity of wire at rest on a turning core is the
  // scheme's, off the exact one by the scheme's error (BDF2:
  // h^2 omega^3 r / 3, 1.1 mm/s at 2890 rpm, r = 12 mm and 1e-4 s). (Below
  // a tenth the exact velocity serves: late-reversal coils are sensitive
  // to the least change in what is taken on or stuck when,
  // docs/history/2026-11-27-carried-wire-at-speed.md.)
  Eigen::Vector3d coreVelocity(const Eigen::Vector3d& p_world, const Eigen::Vector3d& u_exact,
                               double stick_speed) const {
    if (!scheme_core) return u_exact;
    const Eigen::Vector3d u = core_g_world * (p_world - core_origin_world);
    return (u - u_exact).norm() > 0.1 * stick_speed ? u : u_exact;
  }

  void resize(int n) {
    p_world.resize(3, n);
    v_world.resize(3, n);
    q.resize(4, n);
    qd.resize(4, n);
  }
};

// Generalized forces conjugate to p and q, plus power bookkeeping for the
// energy balance.
struct WireForces {
  Eigen::Matrix3Xd f_world;  // [N]
  Eigen::Matrix4Xd f_q;      // generalized force on quaternions [N m]
  // Work and dissipation rates. Each is a part that does not depend on the
  // wire's velocities (e.g. a moving surface's force times its velocity)
  // plus the velocity-paired forces below: the work rate adds
  // sum f_work . v + fq_work . qd, the dissipation rate subtracts
  // sum f_dissipative . v + fq_dissipative . qd. Kept apart so that an
  // integrator can book the work its own velocities do (symplectic Euler
  // moves the positions with the velocities at the step's end).
  double power_external = 0.0;           // [W]
  double power_dissipated = 0.0;         // [W]
  Eigen::Matrix3Xd f_work_world;         // applied loads [N]
  Eigen::Matrix4Xd fq_work;              // applied moments, on q [N m]
  Eigen::Matrix3Xd f_dissipative_world;  // friction and damping [N]
  Eigen::Matrix4Xd fq_dissipative;       // damping moments, on q [N m]

  void resize(int n) {
    f_world.resize(3, n);
    f_q.resize(4, n);
    f_work_world.setZero(3, n);
    fq_work.setZero(4, n);
    f_dissipative_world.setZero(3, n);
    fq_dissipative.setZero(4, n);
  }
  // Zeroes the forces on points first..first+count-1 and the powers (the
  // effects add only to points from the boundary of the integrated wire on).
  void setZero(int first, int count) {
    f_world.middleCols(first, count).setZero();
    f_q.middleCols(first, count).setZero();
    f_work_world.middleCols(first, count).setZero();
    fq_work.middleCols(first, count).setZero();
    f_dissipative_world.middleCols(first, count).setZero();
    fq_dissipative.middleCols(first, count).setZero();
    power_external = 0.0;
    power_dissipated = 0.0;
  }
  // The work and dissipation rates [W] at the velocities v_world, qd of
  // points first..n-1.
  double workRate(const Eigen::Matrix3Xd& v_world, const Eigen::Matrix4Xd& qd, int first,
                  int n) const {
    double p = power_external;
    for (int i = first; i < n; ++i)
      p += f_work_world.col(i).dot(v_world.col(i)) + fq_work.col(i).dot(qd.col(i));
    return p;
  }
  double dissipationRate(const Eigen::Matrix3Xd& v_world, const Eigen::Matrix4Xd& qd, int first,
                         int n) const {
    double p = power_dissipated;
    for (int i = first; i < n; ++i)
      p -= f_dissipative_world.col(i).dot(v_world.col(i)) + fq_dissipative.col(i).dot(qd.col(i));
    return p;
  }
};

// Reads back what appendHistory wrote (snapshots).
class HistoryReader {
 public:
  explicit HistoryReader(const std::vector<double>& v) : v_(v) {}
  double next() {
    if (pos_ >= v_.size()) throw std::runtime_error("snapshot history is too short");
    return v_[pos_++];
  }
  // The next value as an integer in [lo, hi]; `what` names it in the error.
  int nextInteger(int lo, int hi, const char* what) {
    const double v = next();
    if (!(v >= lo && v <= hi) || v != static_cast<double>(static_cast<int>(v))) {
      throw std::runtime_error(std::string("snapshot ") + what + " " + std::to_string(v) +
                               " is not an integer from " + std::to_string(lo) + " to " +
                               std::to_string(hi));
    }
    return static_cast<int>(v);
  }
  bool atEnd() const { return pos_ == v_.size(); }

 private:
  const std::vector<double>& v_;
  std::size_t pos_ = 0;
};

}  // namespace cws
