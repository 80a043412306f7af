// rostest of the node's dynamic_reconfigure (reconfigure.test), through its
// set_parameters service as `dynparam set` calls it: a new target pace shows
// in winding_metrics; new friction coefficients act in the simulation (its
// scene, shown in /diagnostics); coefficients the scene's rules refuse
// (kinetic above static) are refused, the server answering with the values
// in use. A restore brings back the snapshot's friction, in the simulation
// and in the server.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <unistd.h>

#include <cstdio>
#include <map>
#include <mutex>
#include <string>

#include "coil_winding_sim/Restore.h"
#include "coil_winding_sim/Snapshot.h"
#include "coil_winding_sim/WindingMetrics.h"
#include "ros_test_support.hpp"

namespace {

using cws_ros_test::waitFor;

// Sets doubles; returns the server's answer (the values now in use).
std::map<std::string, double> set(const std::map<std::string, double>& values) {
  dynamic_reconfigure::Reconfigure srv;
  for (const auto& [name, value] : values) {
    dynamic_reconfigure::DoubleParameter p;
    p.name = name;
    p.value = value;
    srv.request.config.doubles.push_back(p);
  }
  std::map<std::string, double> in_use;
  EXPECT_TRUE(ros::service::call("/winding_cell/set_parameters", srv));
  for (const auto& p : srv.response.config.doubles) in_use[p.name] = p.value;
  return in_use;
}

struct Listener {
  Listener() {
    ros::NodeHandle nh;
    metrics_sub = nh.subscribe("winding_metrics", 10, &Listener::onMetrics, this);
    diag_sub = nh.subscribe("/diagnostics", 10, &Listener::onDiagnostics, this);
  }
  void onMetrics(const coil_winding_sim::WindingMetrics::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    target = m->target_real_time_factor;
  }
  void onDiagnostics(const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    for (const auto& s : m->status) {
      for (const auto& kv : s.values) {
        if (kv.key == "kinetic friction") kinetic = std::stod(kv.value);
      }
    }
  }
  std::mutex mutex;
  double target = -1.0, kinetic = -1.0;
  ros::Subscriber metrics_sub, diag_sub;
};

TEST(Reconfigure, PaceAndFrictionTakeEffectAndABadPairIsRefused) {
  Listener l;
  ASSERT_TRUE(ros::service::waitForService("/winding_cell/set_parameters", 30000));
  auto kinetic = [&] {
    std::lock_guard<std::mutex> lock(l.mutex);
    return l.kinetic;
  };
  auto target = [&] {
    std::lock_guard<std::mutex> lock(l.mutex);
    return l.target;
  };
  ASSERT_TRUE(waitFor([&] { return kinetic() > 0.0 && target() > 0.0; }, 30.0));
  EXPECT_EQ(target(), 1.0);

  std::map<std::string, double> in_use = set({{"real_time_factor", 0.25}});
  EXPECT_EQ(in_use["real_time_factor"], 0.25);
  EXPECT_TRUE(waitFor([&] { return target() == 0.25; }, 10.0)) << target();

  in_use = set({{"static_friction", 0.5}, {"kinetic_friction", 0.4}});
  EXPECT_EQ(in_use["static_friction"], 0.5);
  EXPECT_EQ(in_use["kinetic_friction"], 0.4);
  EXPECT_TRUE(waitFor([&] { return kinetic() == 0.4; }, 10.0)) << kinetic();

  // Kinetic above static: refused, the values in use stay.
  in_use = set({{"kinetic_friction", 0.6}});
  EXPECT_EQ(in_use["kinetic_friction"], 0.4);
  EXPECT_EQ(in_use["static_friction"], 0.5);
  ros::WallDuration(1.5).sleep();  // a diagnostics period
  EXPECT_EQ(kinetic(), 0.4);
}

// Friction changed after a snapshot: the restore brings back the
// snapshot's, which the server then shows and compares the next change
// with.
TEST(Reconfigure, RestoreShowsTheSnapshotsFriction) {
  Listener l;
  ASSERT_TRUE(ros::service::waitForService("/winding_cell/set_parameters", 30000));
  ASSERT_TRUE(ros::service::waitForService("/winding_cell/restore", 30000));
  auto kinetic = [&] {
    std::lock_guard<std::mutex> lock(l.mutex);
    return l.kinetic;
  };
  std::map<std::string, double> in_use = set({});
  const double mu_s = in_use["static_friction"], mu_d = in_use["kinetic_friction"];
  ASSERT_GT(mu_s, 0.0);
  const std::string path = "/tmp/test_reconfigure_" + std::to_string(getpid()) + ".bag";
  coil_winding_sim::Snapshot snap;
  snap.request.path = path;
  ASSERT_TRUE(ros::service::call("/winding_cell/snapshot", snap) && snap.response.success)
      << snap.response.message;

  in_use = set({{"static_friction", 0.7}, {"kinetic_friction", 0.45}});
  ASSERT_EQ(in_use["kinetic_friction"], 0.45);
  ASSERT_TRUE(waitFor([&] { return kinetic() == 0.45; }, 10.0)) << kinetic();

  coil_winding_sim::Restore restore;
  restore.request.path = path;
  ASSERT_TRUE(ros::service::call("/winding_cell/restore", restore) && restore.response.success)
      << restore.response.message;
  EXPECT_TRUE(waitFor([&] { return kinetic() == mu_d; }, 10.0)) << kinetic();
  in_use = set({});
  EXPECT_EQ(in_use["static_friction"], mu_s);
  EXPECT_EQ(in_use["kinetic_friction"], mu_d);
  // The next change is compared with the restored values: setting the
  // pre-restore pair again takes effect.
  in_use = set({{"static_friction", 0.7}, {"kinetic_friction", 0.45}});
  EXPECT_EQ(in_use["kinetic_friction"], 0.45);
  EXPECT_TRUE(waitFor([&] { return kinetic() == 0.45; }, 10.0)) << kinetic();
  std::remove(path.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_reconfigure");
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
