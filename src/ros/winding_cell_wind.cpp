// The winding cell's `wind` action (winding_cell.hpp): a job of core turns
// or simulated time from the goal's start, optionally along a speed and
// tension profile; feedback at the state's rate; at its end (or on cancel)
// the result with the coil report and the summary, and the cell holds.
#include <cmath>
#include <limits>

#include "coil_winding_sim/core/base/text_format.hpp"
#include "coil_winding_sim/core/scene/setpoint_limits.hpp"
#include "coil_winding_sim/ros/bridge.hpp"
#include "coil_winding_sim/ros/winding_cell.hpp"

namespace cws_ros {

std::string windGoalRefusal(const coil_winding_sim::WindGoal& g, const cws::SetpointLimits& l) {
  const bool turns = g.turns > 0.0, duration = g.duration > 0.0;
  if (!std::isfinite(g.turns) || !std::isfinite(g.duration) || g.turns < 0.0 || g.duration < 0.0 ||
      turns == duration) {
    return "exactly one of turns and duration must be above 0 (turns " +
           cws::formatNumber(g.turns) + ", duration " + cws::formatNumber(g.duration) + " s)";
  }
  const std::size_t n = g.profile_time.size();
  if (g.profile_core_speed.size() != n ||
      (!g.profile_tension.empty() && g.profile_tension.size() != n)) {
    return "the profile has " + std::to_string(n) + " times, " +
           std::to_string(g.profile_core_speed.size()) + " core speeds and " +
           std::to_string(g.profile_tension.size()) +
           " tensions: one speed per time, and one tension per time or none";
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double t = g.profile_time[i];
    if (!std::isfinite(t) || (i == 0 && t != 0.0) || (i > 0 && !(t > g.profile_time[i - 1]))) {
      return "profile_time must start at 0 and increase (entry " + std::to_string(i) + ": " +
             cws::formatNumber(t) + " s)";
    }
    const std::string speed = cws::coreSpeedRefusal(l, g.profile_core_speed[i]);
    if (!speed.empty()) {
      return "profile_core_speed[" + std::to_string(i) + "] " +
             cws::formatNumber(g.profile_core_speed[i]) + " rad/s " + speed;
    }
    if (!g.profile_tension.empty()) {
      const std::string tension = cws::tensionRefusal(l, g.profile_tension[i]);
      if (!tension.empty()) {
        return "profile_tension[" + std::to_string(i) + "] " +
               cws::formatNumber(g.profile_tension[i]) + " N " + tension;
      }
    }
  }
  return "";
}

void WindingCell::startWindServer() {
  wind_server_ = std::make_unique<actionlib::SimpleActionServer<coil_winding_sim::WindAction>>(
      nh_, "wind", false);
  wind_server_->registerGoalCallback([this] { onWindGoal(); });
  wind_server_->registerPreemptCallback([this] { onWindPreempt(); });
  wind_server_->start();
}

// The server's callbacks run under its own lock: they only hand the goal or
// the cancel to the loop (wind_mutex_), which acts on them between chunks
// (takeWindRequests). So the loop may call the server with the simulation's
// lock held, and no two locks are ever taken in opposite orders.
void WindingCell::onWindGoal() {
  const auto goal = wind_server_->acceptNewGoal();
  std::lock_guard<std::mutex> lock(wind_mutex_);
  wind_goal_ = goal;
  wind_cancel_ = false;  // (a goal that replaces another: the server preempted that one)
}

void WindingCell::onWindPreempt() {
  std::lock_guard<std::mutex> lock(wind_mutex_);
  wind_cancel_ = true;
}

// A new goal starts (or is refused with the reason), a cancel ends the goal
// in progress (lock held).
void WindingCell::takeWindRequests() {
  boost::shared_ptr<const coil_winding_sim::WindGoal> goal;
  bool cancel = false;
  {
    std::lock_guard<std::mutex> lock(wind_mutex_);
    goal.swap(wind_goal_);
    cancel = wind_cancel_;
    wind_cancel_ = false;
  }
  if (goal) {
    wind_.active = false;  // one it replaces ended with the server's preemption
    startWind(*goal);
  } else if (cancel && wind_.active) {
    endWind("cancelled");
  }
}

void WindingCell::startWind(const coil_winding_sim::WindGoal& goal) {
  std::string why = windGoalRefusal(goal, limits());
  // A new coil first (its checks are then those of an empty bobbin).
  if (why.empty() && goal.new_coil) {
    if (o_.stop_at_end || o_.follow_clock) {
      why = o_.follow_clock ? "the cell replays a machine bag (~follow_clock)"
                            : "the cell runs the scene's job (~stop_at_end true)";
    } else {
      try {
        changeCoil();
      } catch (const std::exception& e) {
        why = std::string("the coil change failed: ") + e.what();
      }
    }
  }
  if (why.empty() && (o_.stop_at_end || o_.follow_clock)) {
    why = o_.follow_clock ? "the cell replays a machine bag (~follow_clock)"
                          : "the cell runs the scene's job (~stop_at_end true)";
  }
  if (why.empty() && failed_) why = "the simulation stopped (" + failure_ + "); reset or restore";
  if (why.empty() && storage_full_) {
    why = "the wire's storage is full (~max_points " + std::to_string(o_.max_points) +
          "); reset or restore";
  }
  if (why.empty() && !sim_->model().core() && goal.turns > 0.0) {
    why = "the scene has no core to turn (physics.contact false): give a duration";
  }
  // A goal of more turns than the bobbin has room for.
  if (why.empty() && sim_->model().core() && goal.turns > 0.0) {
    const double wound = std::abs(sim_->coreTurns()), holds = scene_.bobbinTurns();
    if (wound + goal.turns > holds * (1.0 + 1e-9)) {
      why = "the bobbin holds " + cws::formatNumber(holds, "%.4g") + " turns and has " +
            cws::formatNumber(wound, "%.4g") + " on it: room for " +
            cws::formatNumber(std::max(0.0, holds - wound), "%.4g") + " more, not " +
            cws::formatNumber(goal.turns, "%.4g");
    }
  }
  if (why.empty() && bobbin_full_) why = job_note_;
  if (!why.empty()) {
    ROS_WARN("winding_cell: wind goal refused: %s", why.c_str());
    coil_winding_sim::WindResult result;
    result.message = "refused: " + why;
    if (wind_server_->isActive()) wind_server_->setAborted(result, result.message);
    return;
  }
  wind_ = WindJob();
  wind_.active = true;
  wind_.start_s = sim_->time();
  wind_.start_angle_rad = sim_->model().core() ? sim_->model().core()->angle(wind_.start_s) : 0.0;
  wind_.turns = goal.turns;
  wind_.duration_s = goal.duration;
  wind_.time_s = goal.profile_time;
  wind_.speed = goal.profile_core_speed;
  wind_.tension = goal.profile_tension;
  // The job winds: a held job ends, a pause ends, a core at rest without a
  // profile takes the scene's speed.
  job_done_ = false;
  plan_stop_ = false;
  job_note_.clear();
  paused_ = false;
  run_until_.reset();
  if (wind_.time_s.empty() && speed_setpoint_ == 0.0) {
    speed_setpoint_ = cws::rpmToRadPerSec(scene_.process.core_speed_rpm);
    sim_->apply(cws::Setpoint::coreSpeed(speed_setpoint_));
  }
  if (!wind_.time_s.empty() || speed_setpoint_ != 0.0) at_rest_ = false;
  restartPace();
  ROS_INFO("winding_cell: wind goal from t = %.6g s: %s%s", wind_.start_s,
           wind_.turns > 0.0 ? (cws::formatNumber(wind_.turns) + " turns").c_str()
                             : (cws::formatNumber(wind_.duration_s) + " s").c_str(),
           wind_.time_s.empty() ? "" : ", along its profile");
}

// A goal in progress ends because the run was replaced (reset, restore;
// lock held).
void WindingCell::abortWind(const std::string& why) {
  if (!wind_.active) return;
  wind_.active = false;
  coil_winding_sim::WindResult result;
  result.message = "aborted: " + why;
  if (wind_server_->isActive()) wind_server_->setAborted(result, result.message);
}

// The profile's setpoints at the simulated time (lock held), before a step:
// every kProfilePeriod of simulated time, as a setpoint stream of 200 Hz
// would give them (each new speed restarts the core's ramp and the
// stepper's history: Simulation::setCoreSpeed).
void WindingCell::applyWindProfile() {
  constexpr double kProfilePeriod = 0.005;  // [s]
  if (!wind_.active || wind_.time_s.empty() || sim_->time() < wind_.next_profile_s) return;
  wind_.next_profile_s = sim_->time() + kProfilePeriod;
  const double t = sim_->time() - wind_.start_s;
  const std::vector<double>& ts = wind_.time_s;
  std::size_t i = 0;
  while (i + 1 < ts.size() && ts[i + 1] <= t) ++i;
  const double a = i + 1 < ts.size() ? (t - ts[i]) / (ts[i + 1] - ts[i]) : 0.0;
  auto at = [&](const std::vector<double>& v) {
    return i + 1 < v.size() ? v[i] + a * (v[i + 1] - v[i]) : v[i];
  };
  const double speed = at(wind_.speed);
  if (speed != speed_setpoint_) {
    speed_setpoint_ = speed;
    sim_->apply(cws::Setpoint::coreSpeed(speed));
    if (speed != 0.0) at_rest_ = false;
  }
  if (!wind_.tension.empty()) {
    const double tension = at(wind_.tension);
    if (tension != tension_setpoint_) {
      tension_setpoint_ = tension;
      sim_->apply(cws::Setpoint::supplyTension(tension));
    }
  }
}

// Turns of the core since the goal's start.
double WindingCell::windTurns(double t) const {
  const cws::RotatingCore* core = sim_->model().core();
  return core ? std::abs(core->angle(t) - wind_.start_angle_rad) / (2.0 * M_PI) : 0.0;
}

bool WindingCell::windEnded() const {
  const double t = sim_->time();
  if (wind_.duration_s > 0.0) return t >= wind_.start_s + wind_.duration_s * (1.0 - 1e-12);
  // At the end time found for the core's present command (windEndTime),
  // where the last step ends: the turns counted there may lie a few ulps of
  // the angle short (the core's angle evaluated again after the step), and
  // a goal that waited for them never ended (issue 58).
  const cws::RotatingCore* core = sim_->model().core();
  if (core && core->command() == wind_.end_command && t >= wind_.end_s) return true;
  return windTurns(t) >= wind_.turns * (1.0 - 1e-12);
}

// When the goal ends if the core keeps its present command [s] (+inf:
// never): steps end there, so that the job ends at its turns.
double WindingCell::windEndTime() const {
  if (wind_.duration_s > 0.0) return wind_.start_s + wind_.duration_s;
  // (Found again only when the command changes: the core's motion under
  // one command is one closed form.)
  const double command = sim_->model().core()->command();
  if (command != wind_.end_command) {
    wind_.end_command = command;
    wind_.end_s = timeAtTurns(wind_.start_angle_rad, wind_.turns);
  }
  return wind_.end_s;
}

// The goal's end (lock held): its result, and the cell holds.
void WindingCell::endWind(const std::string& how) {
  coil_winding_sim::WindResult r =
      toWindResult(*sim_, wind_.start_s, windTurns(sim_->time()), wind_.run_wall_s);
  r.message = how + ": " + cws::formatNumber(r.turns, "%.4g") + " turns in " +
              cws::formatNumber(r.duration, "%.6g") + " s simulated, real-time factor " +
              cws::formatNumber(r.real_time_factor, "%.3g");
  wind_.active = false;
  job_done_ = true;
  job_wall_s_ = wind_.run_wall_s;
  done_text_ = DoneText();
  job_start_sim_s_ = wind_.start_s;
  ROS_INFO("winding_cell: wind goal %s", r.message.c_str());
  if (how == "done") {
    wind_server_->setSucceeded(r, r.message);
  } else if (wind_server_->isActive()) {
    wind_server_->setPreempted(r, r.message);
  }
}

// Feedback at the state's rate while a goal runs (lock held).
void WindingCell::publishWindFeedback() {
  if (!wind_.active || !wind_server_->isActive()) return;
  Pace pace;
  pace.real_time_factor = realTimeFactor();
  pace.target_real_time_factor = pace_.target();
  pace.keeping_pace = keeping_pace_;
  const coil_winding_sim::WindFeedback f =
      toWindFeedback(*sim_, wind_.start_s, windTurns(sim_->time()), pace);
  wind_server_->publishFeedback(f);
}

}  // namespace cws_ros
