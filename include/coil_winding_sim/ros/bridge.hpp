// The ROS bridge: conversions between the simulation core and ROS messages
// and TF. With snapshot_bag.hpp (snapshots as messages and bag files) and
// snapshot_reader.hpp (reading an untrusted snapshot bag in a child
// process), the only place where core types meet ROS types.
#pragma once

#include <geometry_msgs/PointStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <ros/time.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/PointCloud2.h>
#include <trajectory_msgs/JointTrajectory.h>
#include <visualization_msgs/MarkerArray.h>

#include <string>
#include <utility>
#include <vector>

#include "coil_winding_sim/CoilDone.h"
#include "coil_winding_sim/CoreSpeedSetpoint.h"
#include "coil_winding_sim/ErrorEstimate.h"
#include "coil_winding_sim/TensionSetpoint.h"
#include "coil_winding_sim/WindAction.h"
#include "coil_winding_sim/WindingMetrics.h"
#include "coil_winding_sim/WireState.h"
#include "coil_winding_sim/WireStateCompact.h"
#include "coil_winding_sim/WireTension.h"
#include "coil_winding_sim/core/run/coil_report.hpp"
#include "coil_winding_sim/core/run/error_estimate.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"

namespace cws_ros {

struct Frames {
  std::string world = "world";
  std::string core = "core";
  std::string port = "supply_port";
};

// Pace figures the node adds to the metrics.
struct Pace {
  double real_time_factor = 0.0;
  double target_real_time_factor = 1.0;
  bool keeping_pace = true;
};

// The coil report when the scene winds wire onto wire (the only scenes
// whose turns lie in layers); false otherwise.
bool coilOf(const cws::Simulation& sim, cws::CoilReport& out);

// A wind goal's result (started at simulated time start_s [s], `turns`
// turned, wall_s [s] of stepping): its figures, the coil's and the run's
// summary (summary.json's JSON).
// A coil taken off the cell: its figures now (coil: its number).
coil_winding_sim::CoilDone toCoilDone(const cws::Simulation& sim, const ros::Time& stamp,
                                      const Frames& frames, int coil);
coil_winding_sim::WindResult toWindResult(const cws::Simulation& sim, double start_s, double turns,
                                          double wall_s);
coil_winding_sim::WindFeedback toWindFeedback(const cws::Simulation& sim, double start_s,
                                              double turns, const Pace& pace);

coil_winding_sim::WireState toWireState(const cws::Simulation& sim, const ros::Time& stamp,
                                        const Frames& frames);
coil_winding_sim::WindingMetrics toMetrics(const cws::Simulation& sim, const ros::Time& stamp,
                                           const Frames& frames, const Pace& pace);

// The wire as line strips coloured by axial force (blue 0 N .. red at
// `force_scale_N`), the core's cylinders and faces (in the core frame) and
// the supply port. Strips are split to stay within `max_points_per_marker`,
// at fixed points of the whole wire: a strip of wire retired from the live
// arrays (WireModel::retireBuriedWire) is rigid on the core and is sent in
// the core frame, and only where it holds points from `retired_from` on
// (whole-wire index; 0: every strip). With wire contact, also the live
// wound wire coloured by layer, or with `enamel_risk` by the share of its
// enamel's limits used (quality_report.hpp: pale blue within half, yellow
// to red at a limit, magenta past one) ("coil_layers"), and its overlaps and
// gaps ("coil_defects").
visualization_msgs::MarkerArray toMarkers(const cws::Simulation& sim, const ros::Time& stamp,
                                          const Frames& frames, double force_scale_N,
                                          std::size_t max_points_per_marker = 10000,
                                          int retired_from = 0, bool enamel_risk = false);
// What the overlay shows besides the simulation.
struct Overlay {
  std::string state;                   // the cell's state in words
  Pace pace;                           // real-time factor, target, keeping pace
  bool winding = true;                 // false: paused, held or stopped (no pace)
  double tension_setpoint_N = 0.0;     // [N]
  double force_min_N = 0.0;            // the wire's colour range [N]
  double force_max_N = 1.0;            // [N]
  double profile_magnification = 0.0;  // 0: no profile marker
  bool enamel_risk = false;            // the wound wire coloured by its enamel's risk
};
// rviz overlay: the figures as text beside the core ("cell_status"), an
// arrow and the height at the bulge ("bulge"), and the wound wire's profile
// with its stand-off magnified ("profile"; DELETE when off).
visualization_msgs::MarkerArray toOverlayMarkers(const cws::Simulation& sim, const ros::Time& stamp,
                                                 const Frames& frames, const Overlay& o);

// One DELETEALL marker (sent on reset and restore).
visualization_msgs::MarkerArray deleteAllMarkers(const ros::Time& stamp, const Frames& frames);

// TF world -> core (turning with the core) and world -> supply_port. False
// when the scene has no core / no supply.
bool coreTransform(const cws::Simulation& sim, const ros::Time& stamp, const Frames& frames,
                   geometry_msgs::TransformStamped& out);
bool portTransform(const cws::Simulation& sim, const ros::Time& stamp, const Frames& frames,
                   geometry_msgs::TransformStamped& out);

// ---- The machine recording interface (docs/MACHINE_INTERFACE.md) --------
// The simulation's side of the `sim/` topics, each stamped `stamp`.
// Spindle (joint `spindle`): command = the core's commanded angular velocity
// [rad/s]; state = its angle since the start [rad] and angular velocity.
extern const char* const kSpindleJoint;
// A finished job's error estimate at its end time sim_time_s [s]; with an
// empty `failure`, from `e` (bulging_error NaN when nothing was wound), else
// NaN figures and the failure.
coil_winding_sim::ErrorEstimate toErrorEstimateMsg(const cws::ErrorEstimate& e, double sim_time_s,
                                                   int inputs, const std::string& failure,
                                                   const ros::Time& stamp);

sensor_msgs::JointState toSpindleCommand(const cws::Simulation& sim, const ros::Time& stamp);
sensor_msgs::JointState toSpindleState(const cws::Simulation& sim, const ros::Time& stamp);
// The cell's joints (joint_states, for robot_state_publisher and the URDF of
// `wire_sim urdf`): spindle (the core's angle [rad] and speed [rad/s]) and,
// with a supply, port_x, port_y, port_z (the port's world position [m]).
sensor_msgs::JointState toJointStates(const cws::Simulation& sim, const ros::Time& stamp);
// Tension: command = the supply tension [N]; measured = the wire's axial
// force at the port (its last segment) [N]. Zero without a supply.
coil_winding_sim::TensionSetpoint toTensionCommand(const cws::Simulation& sim,
                                                   const ros::Time& stamp);
coil_winding_sim::WireTension toTensionMeasured(const cws::Simulation& sim, const ros::Time& stamp);
// The supply port's position [m] in the world frame. The simulated port is
// where it is commanded to be, so command and position carry the same
// point (the traverse law's without commands). False without a supply.
bool toPortPosition(const cws::Simulation& sim, const ros::Time& stamp, const Frames& frames,
                    geometry_msgs::PointStamped& out);
// The wound wire's mass points (the fixed end to the last point touching
// the core; all points without contact) in the core frame: float32 fields
// x, y, z [m] and stand_off [m] from the winding surface (NaN without
// cylinders). Empty without a core.
// `turns` > 0: the last `turns` turns of it only (about the core axis, back
// from the last point touching the core), as a line sensor near the
// winding point sees it; 0: all of it.
sensor_msgs::PointCloud2 toProfile(const cws::Simulation& sim, const ros::Time& stamp,
                                   const Frames& frames, double turns = 0.0);

// Machine commands to simulation inputs (bridge_machine.cpp). Each returns
// false and says why in `why` for a message that cannot be used.
// The `spindle` joint's commanded velocity [rad/s] (finite).
bool spindleVelocity(const sensor_msgs::JointState& msg, double& omega, std::string& why);
// A point [m] in the world frame (finite; frame_id empty or `frames.world`).
bool portPoint(const geometry_msgs::PointStamped& msg, const Frames& frames,
               Eigen::Vector3d& p_world, std::string& why);

// The messages of the setpoint table's topics (cws::SetpointRow::topic,
// the node's own) and of its machine topics (SetpointRow::machine_topic,
// the machine interface's, docs/MACHINE_INTERFACE.md; the node subscribes
// to them with ~machine_inputs, and a machine bag's replay reads them).
// visitRowMessages calls f(RowMessages<...>{}) with the two message
// types of `kind`'s row, `own` and `machine`, and whether a machine bag's
// replay needs its machine topic; false for a kind with none. setpointOf
// reads a message as its row's setpoint. Adding a message: its place
// here and its setpointOf.
template <class Own, class Machine, bool kMachineRequired>
struct RowMessages {
  using own = Own;
  using machine = Machine;
  static constexpr bool machine_required = kMachineRequired;
};
template <class F>
bool visitRowMessages(cws::Setpoint::Kind kind, F&& f) {
  using Kind = cws::Setpoint::Kind;
  switch (kind) {
    case Kind::kCoreSpeed:
      f(RowMessages<coil_winding_sim::CoreSpeedSetpoint, sensor_msgs::JointState, true>{});
      return true;
    case Kind::kSupplyTension:
      f(RowMessages<coil_winding_sim::TensionSetpoint, coil_winding_sim::TensionSetpoint, true>{});
      return true;
    case Kind::kPortPosition:
      f(RowMessages<geometry_msgs::PointStamped, geometry_msgs::PointStamped, false>{});
      return true;
    default:
      return false;
  }
}
// (A port position's time is left NaN: the caller sets it from the
// stamp.) False with why for a message that cannot be used.
bool setpointOf(const coil_winding_sim::CoreSpeedSetpoint& msg, const Frames& frames,
                cws::Setpoint& sp, std::string& why);
bool setpointOf(const sensor_msgs::JointState& msg, const Frames& frames, cws::Setpoint& sp,
                std::string& why);
bool setpointOf(const coil_winding_sim::TensionSetpoint& msg, const Frames& frames,
                cws::Setpoint& sp, std::string& why);
bool setpointOf(const geometry_msgs::PointStamped& msg, const Frames& frames, cws::Setpoint& sp,
                std::string& why);

// The wire in its compact form (bridge_compact.cpp): the carried block
// from point `carried_from` (clamped to the carried wire, which may have
// shrunk since) and the rest of the wire.
coil_winding_sim::WireStateCompact toWireStateCompact(const cws::Simulation& sim,
                                                      const ros::Time& stamp, const Frames& frames,
                                                      int carried_from);
// Points the core carries rigidly (0 to this, exclusive), as the compact
// form sends them.
int carriedBlock(const cws::Simulation& sim);

// A reader of compact messages: the whole wire as the last message left it,
// and its markers (replay).
class CompactWire {
 public:
  // False, with why, for a message that does not continue the wire held
  // (its carried block starts beyond it: a reader that missed messages
  // waits for the next one from 0).
  bool add(const coil_winding_sim::WireStateCompact& msg, std::string& why);
  int points() const { return static_cast<int>(force_.size()); }
  // The wire as line strips coloured as the cell's (0 N blue to
  // force_scale_N red): the carried part in the core frame, the rest in the
  // world frame.
  visualization_msgs::MarkerArray markers(const ros::Time& stamp, double force_scale_N) const;

 private:
  std::vector<float> carried_xyz_, carried_force_;
  std::vector<float> free_xyz_, force_;  // force_: the whole wire's, carried first
  std::string world_, core_;
  float diameter_ = 0.0f;
};

// A trajectory_msgs/JointTrajectory of the cell's joints (bridge_trajectory.cpp)
// as setpoints at times from the trajectory's start [s]: the spindle's
// speed [rad/s] from each point's velocity, or, with positions alone, the
// speed that reaches the next point's position (0 at the last); the port's
// position [m, world] from the positions of port_x, port_y, port_z (an axis
// not named: NaN, the position in use).
struct TrajectorySetpoints {
  std::vector<std::pair<double, double>> spindle;
  std::vector<std::pair<double, Eigen::Vector3d>> port;
};
bool fromTrajectory(const trajectory_msgs::JointTrajectory& msg, TrajectorySetpoints& out,
                    std::string& why);

}  // namespace cws_ros
