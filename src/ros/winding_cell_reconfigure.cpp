// The winding cell's live parameters (dynamic_reconfigure, cfg/
// WindingCell.cfg): the pace, the publish rates, the end, the force colours,
// the friction coefficients and the damping. A change is checked by the
// node's and the scene's own rules; a refused one is named in a warning and
// the server shows the values in use again (winding_cell.hpp).
#include <cmath>
#include <string>
#include <vector>

#include "coil_winding_sim/core/base/text_format.hpp"
#include "coil_winding_sim/ros/winding_cell.hpp"

namespace cws_ros {

namespace {
using Config = coil_winding_sim::WindingCellConfig;

// The physics the server shows: the scene's friction and damping.
void showPhysics(const cws::Scene& scene, Config& c) {
  c.static_friction = scene.contact.static_friction;
  c.kinetic_friction = scene.contact.kinetic_friction;
  c.damping_translational = scene.damping.translational;
  c.damping_rotational = scene.damping.rotational;
}
}  // namespace

// The server starts from the values in use (the node's parameters and its
// scene), not from the .cfg's defaults.
void WindingCell::startReconfigure() {
  Config c;
  c.real_time_factor = o_.real_time_factor;
  c.state_rate = o_.state_rate_hz;
  c.marker_rate = o_.marker_rate_hz;
  c.stop_at_end = o_.stop_at_end;
  c.exit_at_end = o_.exit_at_end;
  c.force_color_max = o_.force_color_max_N;
  showPhysics(scene_, c);
  applied_ = c;
  reconfigure_ = std::make_unique<dynamic_reconfigure::Server<Config>>(reconfigure_mutex_, pnh_);
  reconfigure_->updateConfig(c);
  reconfigure_->setCallback([this](Config& config, uint32_t) { onReconfigure(config); });
}

// After a restore: the snapshot's friction and damping, in the server and
// in the values the next change is compared with.
void WindingCell::showSceneInReconfigure() {
  if (!reconfigure_) return;
  Config c;
  {
    std::lock_guard<std::mutex> lock(sim_mutex_);
    c = applied_;
    showPhysics(scene_, c);
    applied_ = c;
  }
  reconfigure_->updateConfig(c);
}

void WindingCell::onReconfigure(Config& c) {
  std::lock_guard<std::mutex> lock(sim_mutex_);
  std::vector<std::string> refused;
  // The pace: not while following a replay's clock.
  if (c.real_time_factor != applied_.real_time_factor) {
    if (o_.follow_clock) {
      refused.push_back("real_time_factor: a replay follows the clock (~follow_clock)");
      c.real_time_factor = applied_.real_time_factor;
    } else if (!(c.real_time_factor >= 0.0) || !std::isfinite(c.real_time_factor)) {
      refused.push_back("real_time_factor must be >= 0 (0: as fast as possible)");
      c.real_time_factor = applied_.real_time_factor;
    } else {
      o_.real_time_factor = c.real_time_factor;
      pace_.setTarget(c.real_time_factor);
      restartPace();
    }
  }
  state_rate_hz_ = o_.state_rate_hz = c.state_rate;
  marker_rate_hz_ = o_.marker_rate_hz = c.marker_rate;
  // The end: exiting needs a job that ends.
  if (c.exit_at_end && !c.stop_at_end && !o_.follow_clock) {
    refused.push_back("exit_at_end needs stop_at_end (a job that ends)");
    c.stop_at_end = applied_.stop_at_end;
    c.exit_at_end = applied_.exit_at_end;
  }
  o_.stop_at_end = c.stop_at_end;
  o_.exit_at_end = c.exit_at_end;
  if (job_done_ && o_.exit_at_end) exit_requested_ = true;
  // The force colours.
  o_.force_color_max_N = c.force_color_max;
  force_max_N_ =
      c.force_color_max > 0.0 ? c.force_color_max : std::max(1.0, 2.0 * scene_.process.tension);
  // Physics: by the scene's rules, in the running simulation and in the
  // scene a reset starts from.
  if (c.static_friction != applied_.static_friction ||
      c.kinetic_friction != applied_.kinetic_friction) {
    try {
      sim_->apply(cws::Setpoint::friction(c.static_friction, c.kinetic_friction));
      scene_.contact.static_friction = c.static_friction;
      scene_.contact.kinetic_friction = c.kinetic_friction;
    } catch (const cws::SceneError& e) {
      refused.push_back(std::string("friction: ") + e.what());
      c.static_friction = applied_.static_friction;
      c.kinetic_friction = applied_.kinetic_friction;
    }
  }
  if (c.damping_translational != applied_.damping_translational ||
      c.damping_rotational != applied_.damping_rotational) {
    try {
      // (Through apply: logged, so that a job's error estimate repeats it.)
      sim_->apply(cws::Setpoint::damping(c.damping_translational, c.damping_rotational));
      scene_.damping = sim_->scene().damping;
    } catch (const cws::SceneError& e) {
      refused.push_back(std::string("damping: ") + e.what());
      c.damping_translational = applied_.damping_translational;
      c.damping_rotational = applied_.damping_rotational;
    }
  }
  for (const std::string& why : refused) {
    ROS_WARN("winding_cell: dynamic_reconfigure: refused %s; keeping the value in use",
             why.c_str());
    refused_ = "dynamic_reconfigure: " + why + "; the value in use is kept";
  }
  applied_ = c;
}

}  // namespace cws_ros
