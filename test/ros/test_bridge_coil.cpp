// The bridge's view of a coil, without a ROS master (plain gtest): a late
// reversal on a drum (test_coil_layers) published as winding metrics and
// markers. The markers are checked against the drum's geometry: wire
// coloured as the first layer lies on the drum, wire marked as an overlap
// lies a layer further out.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "coil_winding_sim/core/external_forces/contact.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"
#include "coil_winding_sim/ros/bridge.hpp"

namespace {

const std::string kScene = std::string(CWS_SOURCE_DIR) + "/config/scenes/paper_case_3d.yaml";
constexpr double kDrumRadius = 5.0e-3;  // [m]

const visualization_msgs::Marker* find(const visualization_msgs::MarkerArray& a,
                                       const std::string& ns) {
  for (const visualization_msgs::Marker& k : a.markers) {
    if (k.ns == ns) return &k;
  }
  return nullptr;
}

// Distance of a world point from the core axis (the z axis through the
// origin in these scenes) [m].
double fromAxis(const geometry_msgs::Point& p) { return std::hypot(p.x, p.y); }

bool sameColor(const std_msgs::ColorRGBA& a, const std_msgs::ColorRGBA& b) {
  return a.r == b.r && a.g == b.g && a.b == b.b && a.a == b.a;
}

}  // namespace

TEST(BridgeCoil, OverlapOfALateReversalInMetricsAndMarkers) {
  // Flanges 4.5 mm apart, traverse 6 mm wide: turn 5 has no room and climbs
  // (test_coil_layers, ALateReversalIsReportedAtTheTurnWhereTheWireClimbs).
  const cws::Scene s = cws::loadScene(
      kScene,
      {"core.cylinders=[{center: [0.0, 0.0], radius: 5.0e-3}]",
       "start.position=[0.0, -5.5e-3, 0.0]", "supply.port_position=[-20.0e-3, -5.5e-3, 0.0]",
       "process.core_speed_rpm=1200", "process.turns=7", "physics.wire_contact=true",
       "solver.integrator=bdf2", "process.winding_width=6e-3", "core.flange_spacing=4.5e-3",
       "process.layers=2", "physics.flanges=true"});
  cws::Simulation sim(s);
  sim.run();
  const double d = s.wire.diameter;

  const coil_winding_sim::WindingMetrics m =
      cws_ros::toMetrics(sim, ros::Time(1.0), cws_ros::Frames(), cws_ros::Pace());
  EXPECT_EQ(m.turns, 7);  // the job's turns
  EXPECT_GT(m.turns_wound, 6.5);
  EXPECT_LT(m.turns_wound, 7.5);
  EXPECT_EQ(m.first_overlap_turn, 5);
  EXPECT_GE(m.overlaps, 1);
  EXPECT_GE(m.layers, 2);
  ASSERT_GE(m.bulging_per_layer.size(), 2u);
  // The headline bulging is the layers' largest, not their build-up: the
  // build-up is the largest stand-off from the core, which the climbing
  // turn lifts a layer's rise (sqrt(3)/2 d) above its bulging.
  EXPECT_EQ(m.bulging_height,
            *std::max_element(m.bulging_per_layer.begin(), m.bulging_per_layer.end()));
  EXPECT_EQ(m.build_up_height, cws::bulging(sim.model()).height_m);
  EXPECT_GT(m.build_up_height, m.bulging_height + 0.5 * d);

  const visualization_msgs::MarkerArray a =
      cws_ros::toMarkers(sim, ros::Time(1.0), cws_ros::Frames(), 40.0);
  const visualization_msgs::Marker* layers = find(a, "coil_layers");
  const visualization_msgs::Marker* defects = find(a, "coil_defects");
  ASSERT_NE(layers, nullptr);
  ASSERT_NE(defects, nullptr);
  ASSERT_EQ(layers->points.size(), layers->colors.size());
  ASSERT_EQ(layers->points.size(), static_cast<std::size_t>(cws::lastInContact(sim.model()) + 1));
  // The first layer's colour (that of the clamped end): every point resting
  // on the drum has it, at half a diameter out within the penalty law's
  // penetration; no point three quarters of a diameter further out (a layer
  // further, less a climb's slack) has it.
  const std_msgs::ColorRGBA first = layers->colors.front();
  const cws::Contact& contact = *sim.model().contact();
  int on_drum = 0, above = 0;
  for (std::size_t k = 0; k < layers->points.size(); ++k) {
    const double r = fromAxis(layers->points[k]);
    if (contact.surface(static_cast<int>(k), 0) >= 0) {
      ++on_drum;
      EXPECT_TRUE(sameColor(layers->colors[k], first)) << "point " << k;
      EXPECT_NEAR(r, kDrumRadius + 0.5 * d, 0.1 * d) << "point " << k;
    }
    if (r > kDrumRadius + 0.5 * d + 0.75 * d) {
      ++above;
      EXPECT_FALSE(sameColor(layers->colors[k], first)) << "point " << k;
    }
  }
  EXPECT_GT(on_drum, 100);
  EXPECT_GT(above, 30);
  // The overlap: red spheres, every one at least ~a layer out
  // (sqrt(3)/2 d above the first layer's centres in a groove, d on top).
  ASSERT_EQ(defects->action, visualization_msgs::Marker::ADD);
  int red = 0;
  for (std::size_t k = 0; k < defects->points.size(); ++k) {
    if (defects->colors[k].r != 1.0f || defects->colors[k].g != 0.0f) continue;
    ++red;
    EXPECT_GT(fromAxis(defects->points[k]), kDrumRadius + 0.5 * d + 0.7 * d) << "point " << k;
  }
  EXPECT_GT(red, 10);
}

TEST(BridgeCoil, ScenesWithoutWireContactPublishNoCoil) {
  cws::Simulation sim(cws::loadScene(kScene, {"process.turns=0.05"}));
  sim.run();
  const coil_winding_sim::WindingMetrics m =
      cws_ros::toMetrics(sim, ros::Time(1.0), cws_ros::Frames(), cws_ros::Pace());
  EXPECT_EQ(m.turns, 0);
  EXPECT_TRUE(m.bulging_per_layer.empty());
  const visualization_msgs::MarkerArray a =
      cws_ros::toMarkers(sim, ros::Time(1.0), cws_ros::Frames(), 40.0);
  EXPECT_EQ(find(a, "coil_layers"), nullptr);
  EXPECT_EQ(find(a, "coil_defects"), nullptr);
  EXPECT_NE(find(a, "wire"), nullptr);
}

// The rviz overlay on the paper's 2-D case after 1 3/4 turns: the text
// states the figures of the model (time, turns, tension, bulging, the colour
// range), the arrow ends at the bulge point's surface side and the label
// gives its height, the profile follows the wound points with the stand-off
// magnified, and switching the profile off deletes its marker.
TEST(BridgeOverlay, FiguresBulgeArrowAndProfile) {
  const cws::Scene s = cws::loadScene(std::string(CWS_SOURCE_DIR) + "/config/scenes/default.yaml",
                                      {"solver.integrator=bdf2", "wire.segment_length=2e-3"});
  cws::Simulation sim(s);
  sim.run();
  const cws::BulgeReport b = cws::bulging(sim.model());
  ASSERT_TRUE(b.valid);
  cws_ros::Overlay o;
  o.state = "job done";
  o.tension_setpoint_N = 30.0;
  o.force_max_N = 60.0;
  o.profile_magnification = 10.0;
  const visualization_msgs::MarkerArray a =
      cws_ros::toOverlayMarkers(sim, ros::Time(1.0), cws_ros::Frames(), o);
  std::string text;
  const visualization_msgs::Marker* label = nullptr;
  const visualization_msgs::Marker* arrow = nullptr;
  const visualization_msgs::Marker* profile = nullptr;
  for (const visualization_msgs::Marker& k : a.markers) {
    if (k.ns == "cell_status") text += k.text + "\n";
    if (k.ns == "bulge" && k.type == visualization_msgs::Marker::ARROW) arrow = &k;
    if (k.ns == "bulge" && k.type == visualization_msgs::Marker::TEXT_VIEW_FACING) label = &k;
    if (k.ns == "profile") profile = &k;
  }
  char bulge[32];
  std::snprintf(bulge, sizeof bulge, "%.3f mm", 1e3 * b.height_m);
  for (const std::string& part :
       {std::string("job done"), std::string("1.750 turns"), std::string("tension 30 N set"),
        "bulging " + std::string(bulge), std::string("force 0 N blue to 60 N red")}) {
    EXPECT_NE(text.find(part), std::string::npos) << part << " not in\n" << text;
  }
  ASSERT_TRUE(arrow && label && profile);
  ASSERT_EQ(arrow->points.size(), 2u);
  EXPECT_EQ(arrow->header.frame_id, "core");
  // The arrow points at the bulge (its tip 0.8 mm off the point, outside).
  const Eigen::Vector3d tip(arrow->points[1].x, arrow->points[1].y, arrow->points[1].z);
  EXPECT_NEAR((tip - b.p_core).norm(), 0.8e-3, 1e-9);
  EXPECT_GT(std::hypot(tip.x(), tip.y()), std::hypot(b.p_core.x(), b.p_core.y()));
  EXPECT_NE(label->text.find(bulge), std::string::npos) << label->text;
  // The profile: one point per wound point, each moved out by 9 stand-offs.
  ASSERT_EQ(profile->points.size(), static_cast<std::size_t>(b.wound_points));
  const cws::RotatingCore* core = sim.model().core();
  const Eigen::Vector3d p =
      core->pointCore(sim.time(), cws::wirePoint(sim.model(), b.index).p_world);
  const geometry_msgs::Point& q = profile->points[b.index];
  EXPECT_NEAR(std::hypot(q.x, q.y) - std::hypot(p.x(), p.y()), 9.0 * b.height_m, 1e-9);
  o.profile_magnification = 0.0;
  const visualization_msgs::MarkerArray off =
      cws_ros::toOverlayMarkers(sim, ros::Time(1.0), cws_ros::Frames(), o);
  const visualization_msgs::Marker* gone = find(off, "profile");
  ASSERT_TRUE(gone);
  EXPECT_EQ(gone->action, visualization_msgs::Marker::DELETE);
}
