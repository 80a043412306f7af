// The winding cell's timing logic and options without a ROS master (plain
// gtest, no roscore): pacing, setpoint stamps, the replay's clock following,
// the sim/ topics' grid and the throttled warnings, all driven by a fake
// clock; the node's options and their checks.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "coil_winding_sim/core/run/simulation.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"
#include "coil_winding_sim/ros/bridge.hpp"
#include "coil_winding_sim/ros/cell_timing.hpp"
#include "coil_winding_sim/ros/node_options.hpp"

using cws_ros::PaceKeeper;

TEST(Pace, AheadAndBehindTheTargetFactor) {
  PaceKeeper pace;
  pace.setTarget(2.0);
  pace.restart(100.0, 0.5);
  // After 0.25 s of wall time the target is 0.5 + 2 x 0.25 = 1.0 s.
  EXPECT_NEAR(pace.ahead(100.25, 1.2), 0.2, 1e-12);
  EXPECT_NEAR(pace.ahead(100.25, 0.9), -0.1, 1e-12);
  // Keeping pace: no more than 50 ms of wall time (0.1 s simulated) behind.
  EXPECT_TRUE(pace.keeping(100.25, 0.95));
  EXPECT_FALSE(pace.keeping(100.25, 0.85));
  // A restart (pause, reset) forgives the time lost before it.
  pace.restart(200.0, 0.85);
  EXPECT_TRUE(pace.keeping(200.0, 0.85));
}

TEST(Pace, AsFastAsPossibleNeverWaitsAndAlwaysKeepsPace) {
  PaceKeeper pace;
  pace.setTarget(0.0);
  pace.restart(0.0, 0.0);
  EXPECT_LT(pace.ahead(10.0, 1e6), 0.0);
  EXPECT_TRUE(pace.keeping(1e6, 0.0));
}

// A slow cell's cause, from the integrator's work over the last stretch.
TEST(Pace, ASlowCellNamesItsStepsAndNewtonsWork) {
  cws::WorkCount from, to;
  from.t_s = 1.0;
  from.steps = 100;
  to = from;
  EXPECT_EQ(cws_ros::slowCause(from, to, 0, ""), "");  // no step: nothing to say
  to.t_s = 1.0072;
  to.steps = 200;  // 100 steps of 72 us
  to.rejected = 3;
  to.iterations = 810;
  to.factorizations = 490;
  EXPECT_EQ(cws_ros::slowCause(from, to, 0, ""),
            "steps of 7.2e-05 s on average, 3 of 103 retried, 8.1 Newton iterations and 4.9 "
            "factorizations a step");
  to.iterations = to.factorizations = 0;  // an explicit method
  EXPECT_EQ(cws_ros::slowCause(from, to, 1, "no convergence at 1e-7 s"),
            "steps of 7.2e-05 s on average, 3 of 103 retried; explicit steps where Newton could "
            "not go on (no convergence at 1e-7 s)");
}

TEST(ReplayClock, FollowsTheClockLessTheLagFromItsFirstValue) {
  cws_ros::ReplayClock replay(0.05, std::nullopt);
  EXPECT_LT(replay.target(ros::Time(), 0.0), 0.0);  // no /clock yet
  EXPECT_NEAR(replay.target(ros::Time(100.0), 0.0), -0.05, 1e-9);
  EXPECT_TRUE(replay.haveOrigin());
  EXPECT_NEAR(replay.origin().toSec(), 100.0, 1e-9);
  EXPECT_NEAR(replay.target(ros::Time(100.5), 1.0), 0.45, 1e-9);
}

TEST(ReplayClock, ReachesTheBagsEndHalfASecondAfterTheClockDid) {
  cws_ros::ReplayClock replay(0.05, 2.0);
  replay.setOrigin(ros::Time(100.0));
  EXPECT_NEAR(replay.target(ros::Time(101.0), 0.0), 0.95, 1e-9);
  // The clock at the bag's end: the lag still holds for 0.5 s of wall time
  // (the last messages may be on their way), then the whole bag.
  EXPECT_NEAR(replay.target(ros::Time(102.0), 10.0), 1.95, 1e-9);
  EXPECT_NEAR(replay.target(ros::Time(102.0), 10.4), 1.95, 1e-9);
  EXPECT_NEAR(replay.target(ros::Time(102.0), 10.5), 2.0, 1e-9);
  // Never beyond the end.
  EXPECT_NEAR(replay.target(ros::Time(105.0), 11.0), 2.0, 1e-9);
}

TEST(ReplayClock, AClockStalledWithinTheLagOfTheEndCountsAsTheEnd) {
  cws_ros::ReplayClock replay(0.05, 2.0);
  replay.setOrigin(ros::Time(100.0));
  EXPECT_NEAR(replay.target(ros::Time(101.97), 0.0), 1.92, 1e-9);
  EXPECT_NEAR(replay.target(ros::Time(101.97), 4.9), 1.92, 1e-9);  // waiting
  EXPECT_NEAR(replay.target(ros::Time(101.97), 5.1), 1.92, 1e-9);  // stalled: end seen
  EXPECT_NEAR(replay.target(ros::Time(101.97), 5.7), 2.0, 1e-9);
}

// Pace judged over the last second: a run slower than its target is slow
// after a second of it; one that keeps the target's factor is not, even
// with an old deficit (a slow start); so is one near the pace.
TEST(PaceWindow, SlowOnlyAfterASecondBelowTheTargetsFactor) {
  auto run = [](double rtf, bool near_pace, double until_s, cws_ros::PaceWindow& w) {
    bool ever_slow = false;
    for (double t = 0.01; t <= until_s + 1e-9; t += 0.01) {
      w.update(t, rtf * t, 1.0, near_pace);
      ever_slow |= w.slow();
    }
    return ever_slow;
  };
  cws_ros::PaceWindow w;
  w.restart(0.0, 0.0);
  EXPECT_FALSE(run(1.0, true, 5.0, w));
  // At the target's factor but behind it (an old deficit): not slow.
  w.restart(0.0, 0.0);
  EXPECT_FALSE(run(1.0, false, 5.0, w));
  EXPECT_NEAR(w.factor(), 1.0, 1e-9);
  // At 0.8 of the target: slow, once a second of it has passed.
  w.restart(0.0, 0.0);
  for (double t = 0.01; t < 0.99; t += 0.01) {
    w.update(t, 0.8 * t, 1.0, false);
    EXPECT_FALSE(w.slow()) << t;
  }
  EXPECT_TRUE(run(0.8, false, 3.0, w));
  EXPECT_TRUE(w.slow());
  EXPECT_NEAR(w.factor(), 0.8, 1e-9);
  // At 0.5 of the target, near the pace again after each restart of the
  // pace (every quarter second, as the cell restarts it): slow all the same.
  w.restart(0.0, 0.0);
  bool slow = false;
  for (double t = 0.01; t <= 3.0; t += 0.01) {
    w.update(t, 0.5 * t, 1.0, std::fmod(t, 0.25) < 0.05);
    slow |= w.slow();
  }
  EXPECT_TRUE(slow);
  EXPECT_NEAR(w.factor(), 0.5, 1e-9);
  // As fast as possible (no target): never slow.
  w.restart(0.0, 0.0);
  for (double t = 0.01; t <= 3.0; t += 0.01) w.update(t, 0.1 * t, 0.0, false);
  EXPECT_FALSE(w.slow());
}

TEST(PublishGrid, TopicsFallDueOnTheirGridOfSimulatedTime) {
  cws_ros::PublishGrid grid(100.0, 50.0, 5.0);
  grid.restart(0.0);
  EXPECT_EQ(grid.next(), 0.0);
  cws_ros::PublishGrid::Due d = grid.take(0.0);
  EXPECT_TRUE(d.fast && d.frames && d.profile);
  EXPECT_NEAR(grid.next(), 0.01, 1e-15);
  d = grid.take(0.005);
  EXPECT_FALSE(d.fast || d.frames || d.profile);
  // A step that lands within rounding short of the grid counts as on it.
  d = grid.take(0.01 - 1e-16);
  EXPECT_TRUE(d.fast);
  EXPECT_FALSE(d.frames || d.profile);
  EXPECT_NEAR(grid.next(), 0.02, 1e-15);
  d = grid.take(0.02);
  EXPECT_TRUE(d.fast && d.frames);
  EXPECT_FALSE(d.profile);
  // A long step passes several grid times: one message, the grid moves past.
  d = grid.take(0.2);
  EXPECT_TRUE(d.fast && d.frames && d.profile);
  EXPECT_NEAR(grid.next(), 0.21, 1e-12);
  // A new run at 0.123 s: the next grid times after it.
  grid.restart(0.123);
  EXPECT_NEAR(grid.next(), 0.13, 1e-12);
  grid.take(0.13);
  EXPECT_NEAR(grid.next(), 0.14, 1e-12);
}

TEST(WallThrottle, OncePerSecondOfWallTimeCountingTheRest) {
  cws_ros::WallThrottle throttle;
  int skipped = -1;
  EXPECT_TRUE(throttle.due(10.0, skipped));
  EXPECT_EQ(skipped, 0);
  EXPECT_FALSE(throttle.due(10.5, skipped));
  EXPECT_FALSE(throttle.due(10.9, skipped));
  EXPECT_TRUE(throttle.due(11.0, skipped));
  EXPECT_EQ(skipped, 2);
}

// A burst inside one period with nothing after it: its last text and its
// number come out once the period has passed, once.
TEST(WallThrottle, HeldWarningsComeOutAfterThePeriod) {
  cws_ros::WallThrottle throttle;
  int skipped = -1;
  std::string text;
  EXPECT_TRUE(throttle.due(10.0, skipped, "first"));
  EXPECT_FALSE(throttle.overdue(11.5, text, skipped)) << "nothing was held back";
  EXPECT_TRUE(throttle.due(12.0, skipped, "second"));
  EXPECT_FALSE(throttle.due(12.1, skipped, "third"));
  EXPECT_FALSE(throttle.due(12.2, skipped, "fourth"));
  EXPECT_FALSE(throttle.overdue(12.9, text, skipped)) << "inside the period";
  EXPECT_TRUE(throttle.overdue(13.0, text, skipped));
  EXPECT_EQ(text, "fourth");
  EXPECT_EQ(skipped, 2);
  EXPECT_FALSE(throttle.overdue(20.0, text, skipped)) << "reported twice";
  // The report counts as one: the next warning waits a period after it.
  EXPECT_FALSE(throttle.due(13.5, skipped, "fifth"));
  EXPECT_TRUE(throttle.due(14.0, skipped, "sixth"));
  EXPECT_EQ(skipped, 1);
}

// The pace warning: once, then at most every 10 s of wall time.
TEST(WallThrottle, TenSecondPeriodForThePaceWarning) {
  cws_ros::WallThrottle throttle(10.0);
  int skipped = -1;
  EXPECT_TRUE(throttle.due(100.0, skipped));
  EXPECT_FALSE(throttle.due(101.0, skipped));
  EXPECT_FALSE(throttle.due(109.9, skipped));
  EXPECT_TRUE(throttle.due(110.0, skipped));
  EXPECT_EQ(skipped, 2);
}

namespace {
// validateNodeOptions' message for options changed by `change`, or "" when
// they pass.
template <class Change>
std::string refusal(Change change, bool sim_time = false) {
  cws_ros::NodeOptions o;
  change(o);
  try {
    cws_ros::validateNodeOptions(o, sim_time);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(NodeOptions, DefaultsPassAndEachBadValueIsNamed) {
  EXPECT_EQ(refusal([](cws_ros::NodeOptions&) {}), "");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_NE(refusal([&](auto& o) { o.real_time_factor = -1.0; }).find("~real_time_factor"),
            std::string::npos);
  EXPECT_NE(refusal([&](auto& o) { o.real_time_factor = nan; }).find("~real_time_factor"),
            std::string::npos);
  EXPECT_NE(refusal([&](auto& o) { o.state_rate_hz = 0.0; }).find("~state_rate"),
            std::string::npos);
  EXPECT_NE(refusal([&](auto& o) { o.spindle_rate_hz = inf; }).find("~spindle_rate"),
            std::string::npos);
  EXPECT_NE(refusal([&](auto& o) { o.port_move_time_s = 0.0; }).find("~port_move_time"),
            std::string::npos);
  EXPECT_NE(refusal([&](auto& o) { o.replay_lag_s = -0.1; }).find("~replay_lag"),
            std::string::npos);
  EXPECT_NE(refusal([&](auto& o) {
              o.setpoint_stamp_tolerance_s = nan;
            }).find("~setpoint_stamp_tolerance"),
            std::string::npos);
  EXPECT_NE(refusal([&](auto& o) { o.tf_rate_hz = -5.0; }).find("~tf_rate"), std::string::npos);
  EXPECT_NE(refusal([&](auto& o) { o.max_points = 0; }).find("~max_points"), std::string::npos);
  EXPECT_NE(refusal([&](auto& o) { o.max_points = cws::kMaxScenePoints + 1; }).find("~max_points"),
            std::string::npos);
}

// TF and joint_states: ten samples a revolution at the scene's largest
// speed unless ~tf_rate says otherwise, never fewer than ~state_rate.
TEST(NodeOptions, FramesComeTenTimesARevolutionAtTheLargestSpeed) {
  cws::Scene scene;
  scene.process.max_core_speed_rpm = 1200.0;  // 20 revolutions a second
  cws_ros::NodeOptions o;
  EXPECT_DOUBLE_EQ(cws_ros::frameRateHz(o, scene), 200.0);
  scene.process.max_core_speed_rpm = 60.0;
  EXPECT_DOUBLE_EQ(cws_ros::frameRateHz(o, scene), o.state_rate_hz);
  o.tf_rate_hz = 30.0;
  EXPECT_DOUBLE_EQ(cws_ros::frameRateHz(o, scene), 30.0);
}

TEST(NodeOptions, StartIsOneOfThreeAndExitNeedsAnEnd) {
  for (const char* start : {"running", "paused", "at_rest"}) {
    EXPECT_EQ(refusal([&](auto& o) { o.start = start; }), "") << start;
  }
  const std::string bad = refusal([](auto& o) { o.start = "stopped"; });
  EXPECT_NE(bad.find("~start"), std::string::npos) << bad;
  EXPECT_NE(bad.find("'stopped'"), std::string::npos) << bad;
  // The cell runs until stopped by default: an exit needs a job that ends.
  EXPECT_FALSE(cws_ros::NodeOptions().stop_at_end);
  const std::string no_end = refusal([](auto& o) { o.exit_at_end = true; });
  EXPECT_NE(no_end.find("~exit_at_end"), std::string::npos) << no_end;
  EXPECT_EQ(refusal([](auto& o) {
              o.exit_at_end = true;
              o.stop_at_end = true;
            }),
            "");
}

// Several cells on one TF tree (multi_spindle.launch): ~frame_prefix puts
// the core and port frames under the prefix, as wire_sim urdf --frame-prefix
// names the links; the world stays shared.
TEST(NodeOptions, AFramePrefixNamesTheCellsOwnFrames) {
  cws_ros::NodeOptions o;
  o.frame_prefix = "spindle3/";
  cws_ros::validateNodeOptions(o, false);
  EXPECT_EQ(o.frames.world, "world");
  EXPECT_EQ(o.frames.core, "spindle3/core");
  EXPECT_EQ(o.frames.port, "spindle3/supply_port");
  cws_ros::NodeOptions none;
  cws_ros::validateNodeOptions(none, false);
  EXPECT_EQ(none.frames.core, "core");
  for (const char* bad : {"/spindle1", "spindle 1"}) {
    const std::string why = refusal([&](auto& x) { x.frame_prefix = bad; });
    EXPECT_NE(why.find("~frame_prefix"), std::string::npos) << bad << ": " << why;
  }
}

TEST(NodeOptions, FollowingTheClockNeedsSimTimeAndAnotherNodesClock) {
  EXPECT_NE(refusal([](auto& o) { o.follow_clock = true; }, false).find("/use_sim_time"),
            std::string::npos);
  EXPECT_NE(refusal(
                [](auto& o) {
                  o.follow_clock = true;
                  o.publish_clock = true;
                },
                true)
                .find("~publish_clock"),
            std::string::npos);
  cws_ros::NodeOptions o;
  o.follow_clock = true;
  o.real_time_factor = 5.0;
  cws_ros::validateNodeOptions(o, true);
  EXPECT_EQ(o.real_time_factor, 0.0);  // as fast as the clock allows
}

// A machine axis's trajectory as the cell's setpoints: velocities as given;
// positions alone give the speed that reaches the next point (0 at the
// last); the port from its joints' positions, an axis not named left NaN;
// bad trajectories refused by what is wrong.
TEST(Trajectory, SpindleSpeedsAndPortPositionsAtTheirTimes) {
  auto point = [](double t, std::vector<double> pos, std::vector<double> vel) {
    trajectory_msgs::JointTrajectoryPoint p;
    p.time_from_start = ros::Duration(t);
    p.positions = std::move(pos);
    p.velocities = std::move(vel);
    return p;
  };
  trajectory_msgs::JointTrajectory msg;
  msg.joint_names = {"spindle", "port_y"};
  msg.points = {point(0.0, {0.0, 0.01}, {10.0, 0.0}), point(0.5, {3.0, 0.02}, {20.0, 0.0})};
  cws_ros::TrajectorySetpoints out;
  std::string why;
  ASSERT_TRUE(cws_ros::fromTrajectory(msg, out, why)) << why;
  ASSERT_EQ(out.spindle.size(), 2u);
  EXPECT_EQ(out.spindle[1], std::make_pair(0.5, 20.0));
  ASSERT_EQ(out.port.size(), 2u);
  EXPECT_EQ(out.port[1].first, 0.5);
  EXPECT_EQ(out.port[1].second.y(), 0.02);
  EXPECT_TRUE(std::isnan(out.port[1].second.x()) && std::isnan(out.port[1].second.z()));

  // Positions alone: 3 rad in 0.5 s, then 1 rad in 0.25 s, then stop.
  msg.joint_names = {"spindle"};
  msg.points = {point(0.0, {0.0}, {}), point(0.5, {3.0}, {}), point(0.75, {4.0}, {})};
  ASSERT_TRUE(cws_ros::fromTrajectory(msg, out, why)) << why;
  ASSERT_EQ(out.spindle.size(), 3u);
  EXPECT_DOUBLE_EQ(out.spindle[0].second, 6.0);
  EXPECT_DOUBLE_EQ(out.spindle[1].second, 4.0);
  EXPECT_DOUBLE_EQ(out.spindle[2].second, 0.0);
  EXPECT_TRUE(out.port.empty());

  auto refusal = [&](const trajectory_msgs::JointTrajectory& m) {
    cws_ros::TrajectorySetpoints o;
    std::string w;
    return cws_ros::fromTrajectory(m, o, w) ? std::string() : w;
  };
  trajectory_msgs::JointTrajectory bad = msg;
  bad.joint_names = {"elbow"};
  EXPECT_NE(refusal(bad).find("joint 'elbow'"), std::string::npos);
  bad.joint_names = {"spindle", "spindle"};
  EXPECT_NE(refusal(bad).find("named twice"), std::string::npos);
  bad = msg;
  bad.points = {point(0.0, {0.0}, {})};
  EXPECT_NE(refusal(bad).find("positions at two points"), std::string::npos);
  bad = msg;
  bad.points[2].time_from_start = ros::Duration(0.5);
  EXPECT_NE(refusal(bad).find("time_from_start"), std::string::npos);
  bad = msg;
  bad.joint_names = {"port_x"};
  bad.points[1].positions = {std::numeric_limits<double>::quiet_NaN()};
  EXPECT_NE(refusal(bad).find("port's joints need a finite position"), std::string::npos);
  bad.points.clear();
  EXPECT_NE(refusal(bad).find("no points"), std::string::npos);
}

// The wire's compact form for recordings against the simulation itself:
// read message by message (each sending only the carried points not sent
// before), the reader holds the whole wire: the carried part in the core
// frame and the rest in the world frame, each point where the simulation
// has it (to float precision); a reader that missed a message waits for
// one that starts from point 0.
TEST(CompactWire, TheReaderHoldsTheWholeWireFromMessagesThatSendTheCarriedWireOnce) {
  cws::Simulation sim(cws::loadScene(
      std::string(CWS_SOURCE_DIR) + "/config/scenes/winding_cell.yaml", {"process.turns=5"}));
  const cws_ros::Frames frames;
  cws_ros::CompactWire reader;
  int sent = 0;
  std::size_t carried_sent = 0, messages = 0;
  for (double t = 0.02; t <= 0.5 + 1e-9; t += 0.02) {
    while (sim.time() < t) sim.step(t);
    const coil_winding_sim::WireStateCompact msg =
        cws_ros::toWireStateCompact(sim, ros::Time(1.0), frames, sent);
    sent = cws_ros::carriedBlock(sim);
    carried_sent += msg.carried_force.size();
    ++messages;
    std::string why;
    ASSERT_TRUE(reader.add(msg, why)) << why;
  }
  const cws::WireModel& m = sim.model();
  const int carried = cws_ros::carriedBlock(sim);
  ASSERT_GT(carried, 100);  // three turns and more lie carried
  EXPECT_LT(carried_sent, static_cast<std::size_t>(carried) + messages);  // each sent once
  EXPECT_EQ(reader.points(), m.constants().n);
  const visualization_msgs::MarkerArray markers = reader.markers(ros::Time(1.0), 60.0);
  ASSERT_EQ(markers.markers.size(), 2u);
  const auto& core_part = markers.markers[0].points;
  const auto& world_part = markers.markers[1].points;
  ASSERT_EQ(core_part.size(), static_cast<std::size_t>(carried));
  ASSERT_EQ(world_part.size(), static_cast<std::size_t>(m.constants().n - carried));
  EXPECT_EQ(markers.markers[0].header.frame_id, frames.core);
  double worst = 0.0;
  for (int i = 0; i < m.constants().n; ++i) {
    const Eigen::Vector3d p_world = m.committed().p_world.col(i);
    const Eigen::Vector3d p = i < carried ? m.core()->pointCore(sim.time(), p_world) : p_world;
    const geometry_msgs::Point& q = i < carried ? core_part[i] : world_part[i - carried];
    worst = std::max(worst, (p - Eigen::Vector3d(q.x, q.y, q.z)).norm());
  }
  EXPECT_LT(worst, 1e-8) << "[m]";
  // A reader that joins late: refused until a message starts from point 0.
  cws_ros::CompactWire late;
  std::string why;
  EXPECT_FALSE(late.add(cws_ros::toWireStateCompact(sim, ros::Time(1.0), frames, sent), why));
  EXPECT_NE(why.find("waiting for one from point 0"), std::string::npos) << why;
  EXPECT_TRUE(late.add(cws_ros::toWireStateCompact(sim, ros::Time(1.0), frames, 0), why)) << why;
}
