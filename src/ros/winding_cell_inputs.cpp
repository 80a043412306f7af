// The winding cell's setpoint topics: checked in the callbacks, applied by
// the simulation loop between chunks (winding_cell.hpp). Neither takes the
// simulation's lock: a burst of setpoints cannot hold up the simulation or
// the services.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <limits>
#include <stdexcept>

#include "coil_winding_sim/core/base/text_format.hpp"
#include "coil_winding_sim/core/external_forces/supply.hpp"
#include "coil_winding_sim/core/scene/setpoint_limits.hpp"
#include "coil_winding_sim/ros/bridge.hpp"
#include "coil_winding_sim/ros/winding_cell.hpp"

namespace cws_ros {

namespace {
// A stamp in nanoseconds and back (the inbox is ROS-free).
std::int64_t nanoseconds(const ros::Time& t) { return static_cast<std::int64_t>(t.toNSec()); }
ros::Time rosTime(std::int64_t ns) {
  ros::Time t;
  t.fromNSec(static_cast<std::uint64_t>(ns));
  return t;
}
}  // namespace

// The setpoint topics, one per row of the setpoint table that names one
// (cws::setpointTable), and with ~machine_inputs the machine's commands
// (docs/MACHINE_INTERFACE.md), one per row that names a machine topic:
// each message read by the bridge as its row's setpoint (setpointOf),
// checked and queued as every setpoint is.
void WindingCell::subscribeSetpoints() {
  for (const cws::SetpointRow& row : cws::setpointTable()) {
    const std::string topic = row.topic;
    const std::string machine = o_.machine_inputs ? row.machine_topic : "";
    if (topic.empty() && machine.empty()) continue;
    const bool read = visitRowMessages(row.kind, [&](auto m) {
      using Messages = decltype(m);
      if (!topic.empty()) {
        setpoint_subs_.push_back(subscribeRow<typename Messages::own>(row, topic, 100));
      }
      if (!machine.empty()) {
        setpoint_subs_.push_back(subscribeRow<typename Messages::machine>(row, machine, 1000));
      }
    });
    if (!read) {
      throw std::logic_error("the setpoint table names topic " + topic + " " + machine + " for " +
                             row.name + ", but the node reads no message for it");
    }
  }
}

template <class M>
ros::Subscriber WindingCell::subscribeRow(const cws::SetpointRow& row, const std::string& topic,
                                          uint32_t queue) {
  const cws::SetpointRow* r = &row;
  return nh_.subscribe<M>(
      topic, queue,
      boost::function<void(const typename M::ConstPtr&)>(
          [this, r, topic](const typename M::ConstPtr& msg) {
            // (A path's sample is refused while the cell holds before it is read.)
            if (r->path_sample && refusedWhileHolding(topic, "")) return;
            cws::Setpoint sp;
            std::string why;
            if (!setpointOf(*msg, o_.frames, sp, why)) {
              std::string keeping;
              if (!r->path_sample) {
                keeping = "; keeping " + cws::formatNumber(inUse(r->kind)) + " " + r->unit;
              }
              warn(warningsOf(topic).value, "refused " + topic + ": " + why + keeping);
              return;
            }
            if (r->path_sample) {
              pathInput(topic, sp, msg->header.stamp);
            } else {
              valueInput(topic, sp, msg->header.stamp);
            }
          }));
}

// The scene's limits, without the simulation's lock.
cws::SetpointLimits WindingCell::limits() const { return {max_speed_, max_tension_}; }

// The value in use of a setpoint the node keeps (speed, tension) [its unit].
double WindingCell::inUse(cws::Setpoint::Kind kind) const {
  return kind == cws::Setpoint::Kind::kCoreSpeed ? speed_setpoint_.load()
                                                 : tension_setpoint_.load();
}

// A value setpoint (core speed, tension): checked against its row's limit
// now, queued at its stamp's simulated time.
void WindingCell::valueInput(const std::string& topic, const cws::Setpoint& setpoint,
                             const ros::Time& stamp) {
  const cws::SetpointRow& row = cws::setpointRow(setpoint.kind);
  const std::string value = cws::formatNumber(setpoint.value) + " " + row.unit;
  if (refusedWhileHolding(topic, value)) return;
  const std::string why = row.refusal ? row.refusal(limits(), setpoint) : "";
  if (!why.empty()) {
    warn(warningsOf(topic).value, "refused " + topic + " " + value + ", which " + why +
                                      "; keeping " + cws::formatNumber(inUse(setpoint.kind)) + " " +
                                      row.unit);
    return;
  }
  if (admitStamp(topic, stamp)) inbox_.put({topic, nanoseconds(stamp), setpoint});
}

// A path's sample (the port's position, finite and in the world frame):
// stamps as for the other setpoints; the simulation refuses a port inside
// the core or in the past (feedPort) with a warning.
void WindingCell::pathInput(const std::string& topic, const cws::Setpoint& setpoint,
                            const ros::Time& stamp) {
  if (!admitStamp(topic, stamp)) return;
  // (Its simulated time is found by the loop: drainInputs.)
  inbox_.put({topic, nanoseconds(stamp), setpoint});
}

// A machine axis's trajectory: checked and read by the bridge here, its
// setpoints queued at their times by the loop (drainInputs).
void WindingCell::onTrajectory(const trajectory_msgs::JointTrajectory::ConstPtr& msg) {
  const std::string topic = "joint_trajectory";
  if (refusedWhileHolding(topic, "")) return;
  TrajectorySetpoints setpoints;
  std::string why;
  if (!fromTrajectory(*msg, setpoints, why)) {
    warn(warningsOf(topic).value, "refused " + topic + ": " + why);
    return;
  }
  for (const auto& [t, w] : setpoints.spindle) {
    why = cws::coreSpeedRefusal(limits(), w);
    if (!why.empty()) {
      warn(warningsOf(topic).value, "refused " + topic + ": spindle velocity " +
                                        cws::formatNumber(w) + " rad/s at " + cws::formatNumber(t) +
                                        " s " + why);
      return;
    }
  }
  if (!admitStamp(topic, msg->header.stamp)) return;
  cws::SetpointInbox::Schedule in{topic, nanoseconds(msg->header.stamp), {}};
  for (const auto& [t, w] : setpoints.spindle)
    in.points.emplace_back(t, cws::Setpoint::coreSpeed(w));
  for (const auto& [t, p] : setpoints.port) {
    in.points.emplace_back(t, cws::Setpoint::portPosition(p, t));
  }
  inbox_.put(std::move(in));
}

double WindingCell::simTimeOf(const ros::Time& stamp) const {
  if (stamp.isZero()) return sim_->time();
  if (o_.follow_clock) return (stamp - replay_.origin()).toSec();
  if (o_.publish_clock) return stamp.toSec() - clock_offset_;
  // Another node's clock: as far ahead of the simulated time as of it.
  if (ros::Time::isSimTime()) return sim_->time() + (stamp - ros::Time::now()).toSec();
  return stamp.toSec() - stamp_origin_s_;
}

bool WindingCell::refusedWhileHolding(const std::string& topic, const std::string& what) {
  if (o_.follow_clock) return false;
  std::string why, todo = "call ~reset or ~restore to wind again";
  if (job_done_ && o_.stop_at_end) {
    why = "the job is done and the cell holds its state (~stop_at_end true)";
  } else if (job_done_ && plan_stop_ && !bobbin_full_) {
    // The spindle stopped at the scene's plan: a setpoint winds on.
    resume_ = true;
    return false;
  } else if (job_done_) {
    why = "the wind goal is done and the cell holds its state";
    todo = "send a wind goal, or call ~reset or ~restore, to wind again";
  } else if (storage_full_) {
    why = "the wire's storage is full and the cell holds its state (~max_points " +
          std::to_string(o_.max_points) + ")";
  } else {
    return false;
  }
  warn(warningsOf(topic).value,
       "refused " + topic + (what.empty() ? "" : " " + what) + ": " + why + "; " + todo);
  return true;
}

// The node's clock: its own /clock with ~publish_clock, else ROS time.
ros::Time WindingCell::nodeClock() const {
  return o_.publish_clock ? ros::Time(clock_s_.load()) : ros::Time::now();
}

WindingCell::TopicWarnings& WindingCell::warningsOf(const std::string& topic) {
  std::lock_guard<std::mutex> lock(warnings_mutex_);
  return warnings_[topic];  // std::map: references stay valid
}

// Refusals held back by a throttle with nothing after them (the end of a
// burst): reported once their period has passed, with their number.
void WindingCell::reportHeldWarnings() {
  std::lock_guard<std::mutex> lock(warnings_mutex_);
  const double now = wallNow();
  for (auto& [topic, w] : warnings_) {
    for (WallThrottle* t : {&w.value, &w.ahead, &w.order}) {
      std::string text;
      int held = 0;
      if (t->overdue(now, text, held)) {
        ROS_WARN("winding_cell: %s (the last of %d like it held back since the last report)",
                 text.c_str(), held);
      }
    }
  }
}

bool WindingCell::admitStamp(const std::string& topic, const ros::Time& stamp) {
  const ros::Time clock = nodeClock();
  // Without ~publish_clock and before the first /clock, ROS time is zero:
  // there is no clock to compare with yet.
  const bool have_clock = o_.publish_clock || !clock.isZero();
  std::string why;
  switch (inbox_.admit(topic, nanoseconds(stamp), nanoseconds(clock), have_clock, why)) {
    case cws::SetpointInbox::Verdict::kAdmitted:
      return true;
    case cws::SetpointInbox::Verdict::kAhead:
      warn(warningsOf(topic).ahead, why);
      return false;
    case cws::SetpointInbox::Verdict::kOutOfOrder:
      warn(warningsOf(topic).order, why);
      return false;
  }
  return false;
}

// Moves the setpoints the callbacks received into the loop's queues (with
// ~follow_clock once the origin is known): speed and tension by the
// simulated time of their stamp with ~follow_clock, else at once; port
// samples in arrival order (stamps only grow: admitStamp drops older ones);
// a trajectory's points at their times.
void WindingCell::drainInputs() {
  if (o_.follow_clock && !replay_.haveOrigin()) return;
  constexpr double kNow = -std::numeric_limits<double>::infinity();
  const double kUnset = std::numeric_limits<double>::quiet_NaN();
  inbox_.take(
      [&](cws::SetpointInbox::Received& in) {
        const ros::Time stamp = rosTime(in.stamp_ns);
        if (in.setpoint.kind != cws::Setpoint::Kind::kPortPosition) {
          // (After equal times: arrival order kept.)
          inbox_.due().add(
              o_.follow_clock && !stamp.isZero() ? (stamp - replay_.origin()).toSec() : kNow,
              in.setpoint);
          return;
        }
        double t_s = kUnset;  // reached ~port_move_time from now
        if (o_.follow_clock && !stamp.isZero()) {
          t_s = (stamp - replay_.origin()).toSec();
        } else if (o_.publish_clock && stamp.toSec() > clock_offset_ + sim_->time()) {
          t_s = stamp.toSec() - clock_offset_;
        }
        inbox_.ports().push_back({t_s, in.setpoint.p_world, in.topic});
      },
      // Trajectories: each replaces what remains of the one before from its
      // start; points in the past apply at once.
      [&](cws::SetpointInbox::Schedule& in) {
        const double t0 = simTimeOf(rosTime(in.stamp_ns));
        bool speeds = false, ports = false;
        for (const auto& [t, sp] : in.points) {
          (sp.kind == cws::Setpoint::Kind::kCoreSpeed ? speeds : ports) = true;
        }
        if (speeds) {
          inbox_.due().dropFrom(t0, cws::Setpoint::Kind::kCoreSpeed);
          for (const auto& [t, sp] : in.points) {
            if (sp.kind == cws::Setpoint::Kind::kCoreSpeed) inbox_.due().add(t0 + t, sp);
          }
          at_rest_ = false;  // (~start at_rest: the controller has taken over)
        }
        if (!ports) return;
        const cws::Supply* supply = sim_->model().supply();
        if (!supply) {
          warn(warningsOf(in.topic).value,
               "refused " + in.topic + "'s port joints: the scene has no supply port");
          return;
        }
        for (const auto& [t, sp] : in.points) {
          if (sp.kind != cws::Setpoint::Kind::kPortPosition) continue;
          // An axis the trajectory leaves out: where the port's path ends now.
          const Eigen::Vector3d end =
              supply->port(std::max(sim_->time(), sim_->portCommandEnd())).p_world;
          Eigen::Vector3d p_world = sp.p_world;
          for (int a = 0; a < 3; ++a) {
            if (std::isnan(p_world[a])) p_world[a] = end[a];
          }
          // (A point at or before the present: reached ~port_move_time from now.)
          const double t_s = t0 + t > sim_->time() ? t0 + t : kUnset;
          inbox_.ports().push_back({t_s, p_world, in.topic});
        }
      });
}

// Applies the queued speed and tension setpoints whose time has come.
void WindingCell::applyDue() {
  inbox_.due().takeDue(sim_->time(), [&](double, const cws::Setpoint& c) {
    // (Checked on receipt against the limits then in force; a restore may
    // have changed them since.)
    try {
      sim_->apply(c);
    } catch (const std::exception& e) {
      warn(warningsOf(c.name()).value, std::string("refused a ") + c.name() +
                                           " setpoint: " + e.what() + "; keeping the value in use");
      return;
    }
    if (c.kind == cws::Setpoint::Kind::kSupplyTension) {
      tension_setpoint_ = c.value;
    } else if (c.kind == cws::Setpoint::Kind::kCoreSpeed) {
      speed_setpoint_ = c.value;
      // (~start at_rest: the controller has taken over.)
      if (!o_.follow_clock) at_rest_ = false;
    }
  });
}

// Hands queued port samples to the simulation's path while it has room.
void WindingCell::feedPort() {
  std::deque<cws::SetpointInbox::PortSample>& queue = inbox_.ports();
  while (!queue.empty() && sim_->portCommandRoom() > 1) {
    const cws::SetpointInbox::PortSample& s = queue.front();
    const double t_s = std::isnan(s.t_s) ? sim_->time() + o_.port_move_time_s : s.t_s;
    try {
      sim_->apply(cws::Setpoint::portPosition(s.p_world, t_s));
    } catch (const std::invalid_argument& e) {
      warn(warningsOf("port_position_setpoint").value, "refused " + s.topic + ": " + e.what());
    }
    queue.pop_front();
  }
}

// Makes `scene` the scene in use (its limits apply to the setpoints).
void WindingCell::setScene(const cws::Scene& scene) {
  scene_ = scene;
  const cws::SetpointLimits l = cws::SetpointLimits::of(scene_.process);
  max_speed_ = l.max_core_speed_rad_s;
  max_tension_ = l.max_tension_N;
}

}  // namespace cws_ros
