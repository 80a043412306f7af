// Unit tests of scene loading, validation and printing (cws::loadScene,
// cws::validateScene, cws::sceneToYamlText).
//
// The expected defaults are typed from Table 1 of the paper with the corrected
// line density (7.02e-3 kg/m) and the yields of shared/reference/wire-data.md;
// they are not read back from the code.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "coil_winding_sim/core/scene/scene.hpp"
#include "temp_dir_test.hpp"

namespace {

namespace fs = std::filesystem;

// A fresh directory per test, removed afterwards.
class SceneFiles : public cws_test::TempDirTest {
 protected:
  // Loads `yaml` (as a scene file, if not empty) with `overrides` and expects
  // a SceneError naming `key`, whose message names the key and contains
  // `why` (a word of the reason).
  void expectRefused(const std::string& yaml, const std::vector<std::string>& overrides,
                     const std::string& key, const std::string& why) {
    const std::string path = yaml.empty() ? std::string() : write("scene.yaml", yaml);
    try {
      cws::loadScene(path, overrides);
      ADD_FAILURE() << "accepted, expected a SceneError for '" << key << "'";
    } catch (const cws::SceneError& e) {
      EXPECT_EQ(e.key(), key) << "what(): " << e.what();
      const std::string what = e.what();
      EXPECT_NE(what.find("'" + key + "'"), std::string::npos) << "what(): " << what;
      EXPECT_NE(what.find(why), std::string::npos) << "what(): " << what << "\nmissing: " << why;
    }
  }
};

void expectVec(const Eigen::Vector3d& actual, const Eigen::Vector3d& expected,
               const std::string& what) {
  for (int i = 0; i < 3; ++i) EXPECT_EQ(actual[i], expected[i]) << what << "[" << i << "]";
}

// Every field of two scenes, exactly.
void expectSameScene(const cws::Scene& a, const cws::Scene& b) {
  EXPECT_EQ(a.wire.diameter, b.wire.diameter);
  EXPECT_EQ(a.wire.line_density, b.wire.line_density);
  EXPECT_EQ(a.wire.length, b.wire.length);
  EXPECT_EQ(a.wire.segment_length, b.wire.segment_length);
  const cws::HysteresisParams* ha[3] = {&a.wire.stretch, &a.wire.bend, &a.wire.torsion};
  const cws::HysteresisParams* hb[3] = {&b.wire.stretch, &b.wire.bend, &b.wire.torsion};
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(ha[i]->elastic_rigidity, hb[i]->elastic_rigidity) << "law " << i;
    EXPECT_EQ(ha[i]->plastic_rigidity, hb[i]->plastic_rigidity) << "law " << i;
    EXPECT_EQ(ha[i]->yield, hb[i]->yield) << "law " << i;
  }
  EXPECT_EQ(a.contact.static_friction, b.contact.static_friction);
  EXPECT_EQ(a.contact.kinetic_friction, b.contact.kinetic_friction);
  EXPECT_EQ(a.process.core_speed_rpm, b.process.core_speed_rpm);
  EXPECT_EQ(a.process.tension, b.process.tension);
  EXPECT_EQ(a.process.turns, b.process.turns);
  EXPECT_EQ(a.process.duration.has_value(), b.process.duration.has_value());
  if (a.process.duration && b.process.duration) {
    EXPECT_EQ(*a.process.duration, *b.process.duration);
  }
  EXPECT_EQ(a.solver.integrator, b.solver.integrator);
  EXPECT_EQ(a.solver.rtol, b.solver.rtol);
  EXPECT_EQ(a.solver.atol, b.solver.atol);
  EXPECT_EQ(a.solver.min_step, b.solver.min_step);
  EXPECT_EQ(a.solver.max_step, b.solver.max_step);
  EXPECT_EQ(a.solver.initial_step, b.solver.initial_step);
  EXPECT_EQ(a.solver.baumgarte_nu, b.solver.baumgarte_nu);
  EXPECT_EQ(a.physics.torsion, b.physics.torsion);
  EXPECT_EQ(a.physics.plasticity, b.physics.plasticity);
  EXPECT_EQ(a.physics.gravity, b.physics.gravity);
  EXPECT_EQ(a.physics.damping, b.physics.damping);
  expectVec(a.gravity.acceleration_world, b.gravity.acceleration_world, "gravity.acceleration");
  EXPECT_EQ(a.damping.translational, b.damping.translational);
  EXPECT_EQ(a.damping.rotational, b.damping.rotational);
  EXPECT_EQ(a.start.type, b.start.type);
  EXPECT_EQ(a.start.frame, b.start.frame);
  expectVec(a.start.position, b.start.position, "start.position");
  expectVec(a.start.direction, b.start.direction, "start.direction");
  EXPECT_EQ(a.end.type, b.end.type);
  ASSERT_EQ(a.end.load.size(), b.end.load.size());
  for (std::size_t i = 0; i < a.end.load.size(); ++i) {
    EXPECT_EQ(a.end.load[i].time, b.end.load[i].time) << "end.load[" << i << "]";
    expectVec(a.end.load[i].force_world, b.end.load[i].force_world, "force");
    expectVec(a.end.load[i].moment_world, b.end.load[i].moment_world, "moment");
  }
  EXPECT_EQ(a.output.progress_interval_s, b.output.progress_interval_s);
}

// Table 1 (corrected line density) and wire-data.md yields and process data.
void expectTable1Defaults(const cws::Scene& s) {
  EXPECT_DOUBLE_EQ(s.wire.diameter, 1.0e-3);
  EXPECT_DOUBLE_EQ(s.wire.line_density, 7.02e-3);  // not the printed 7.02e5
  EXPECT_DOUBLE_EQ(s.wire.stretch.elastic_rigidity, 4.89e4);
  EXPECT_DOUBLE_EQ(s.wire.stretch.plastic_rigidity, 1.10e3);
  EXPECT_DOUBLE_EQ(s.wire.stretch.yield, 8.0e-4);
  EXPECT_DOUBLE_EQ(s.wire.bend.elastic_rigidity, 3.06e-3);
  EXPECT_DOUBLE_EQ(s.wire.bend.plastic_rigidity, 1.13e-4);
  EXPECT_DOUBLE_EQ(s.wire.bend.yield, 1.6);
  EXPECT_DOUBLE_EQ(s.wire.torsion.elastic_rigidity, 4.32e-3);
  EXPECT_DOUBLE_EQ(s.wire.torsion.plastic_rigidity, 9.0e-5);
  EXPECT_DOUBLE_EQ(s.wire.torsion.yield, 1.31);
  EXPECT_DOUBLE_EQ(s.contact.static_friction, 0.23);
  EXPECT_DOUBLE_EQ(s.contact.kinetic_friction, 0.17);
  EXPECT_DOUBLE_EQ(s.process.core_speed_rpm, 600.0);
  EXPECT_DOUBLE_EQ(s.process.tension, 30.0);
  EXPECT_DOUBLE_EQ(s.process.turns, 1.75);
  EXPECT_FALSE(s.process.duration.has_value());
}

// The corrected line density is the mass of 1 m of 1.0 mm copper wire.
TEST(SceneDefaults, LineDensityIsCopperMassPerLength) {
  const cws::Scene s;
  const double pi = 3.14159265358979323846;
  const double area = pi * s.wire.diameter * s.wire.diameter / 4.0;  // 7.854e-7 m^2
  EXPECT_NEAR(s.wire.line_density, 8940.0 * area, 0.005 * s.wire.line_density);
}

TEST(SceneDefaults, BuiltInDefaultsAreTable1) {
  const cws::Scene s;
  expectTable1Defaults(s);
  EXPECT_NO_THROW(cws::validateScene(s));
}

TEST(SceneDefaults, LoadWithoutFileGivesTable1) {
  const cws::Scene s = cws::loadScene("", {});
  expectTable1Defaults(s);
  expectSameScene(s, cws::Scene{});
}

// Derived quantities, closed form: 0.05 m in segments of at most 1 mm is 50
// segments; 0.01 m in segments of at most 3 mm is ceil(3.33) = 4 segments of
// 2.5 mm; 1.75 turns at 600 rpm take 0.175 s; a duration overrides turns.
TEST(SceneDefaults, DerivedSegmentsAndEndTime) {
  cws::Scene s;
  EXPECT_EQ(s.segmentCount(), 50);
  EXPECT_NEAR(s.naturalSegmentLength(), 1.0e-3, 1e-15);
  EXPECT_NEAR(s.endTime(), 0.175, 1e-15);
  s.wire.length = 0.01;
  s.wire.segment_length = 0.003;
  EXPECT_EQ(s.segmentCount(), 4);
  EXPECT_NEAR(s.naturalSegmentLength(), 0.0025, 1e-15);
  s.process.core_speed_rpm = 1200.0;
  EXPECT_NEAR(s.endTime(), 0.0875, 1e-15);
  s.process.duration = 2.0e-4;
  EXPECT_EQ(s.endTime(), 2.0e-4);
}

// ---------------------------------------------------------------------------
// Print, then load: every field survives.
TEST_F(SceneFiles, PrintedDefaultSceneLoadsBackIdentical) {
  const cws::Scene s;
  const std::string path = write("printed.yaml", cws::sceneToYamlText(s));
  expectSameScene(cws::loadScene(path, {}), s);
}

TEST_F(SceneFiles, PrintedNonDefaultSceneLoadsBackIdentical) {
  cws::Scene s;
  s.wire.diameter = 1.234567891e-3;
  s.wire.line_density = 6.5e-3;
  s.wire.length = 0.0314159;
  s.wire.segment_length = 7.5e-4;
  s.wire.stretch = {5.1e4, 2.2e3, 9.5e-4};
  s.wire.bend = {2.5e-3, 1.0e-4, 1.7};
  s.wire.torsion = {4.0e-3, 0.0, 1.25};
  s.contact.static_friction = 0.4;
  s.contact.kinetic_friction = 0.4;
  s.process.core_speed_rpm = -1200.0;
  s.process.tension = 70.0;
  s.process.turns = 2.5;
  s.process.duration = 1.5e-3;
  s.solver.rtol = 2.5e-7;
  s.solver.atol = 3.0e-10;
  s.solver.min_step = 1.0e-13;
  s.solver.max_step = 5.0e-5;
  s.solver.initial_step = 2.0e-8;
  s.solver.baumgarte_nu = 1234.5;
  s.physics = {false, false, true, true};
  s.gravity.acceleration_world = {0.5, -9.80665, 1.25e-3};
  s.damping.translational = 0.125;
  s.damping.rotational = 3.0e-6;
  s.start.position = {0.1, -0.2, 0.3};
  s.start.direction = {0.0, 0.6, 0.8};
  s.end.load.clear();
  s.end.load.push_back({0.0, {1.0, 2.0, 3.0}, {0.0, 0.0, 0.0}});
  s.end.load.push_back({1.0e-3, {-4.5, 0.0, 6.25e-2}, {1.0e-4, -2.0e-4, 3.0e-4}});
  s.end.load.push_back({2.0e-3, {0.0, 0.0, 0.0}, {7.0, 8.0, 9.0}});
  s.output.progress_interval_s = 0.25;
  ASSERT_NO_THROW(cws::validateScene(s));
  const std::string text = cws::sceneToYamlText(s);
  const cws::Scene back = cws::loadScene(write("printed.yaml", text), {});
  SCOPED_TRACE(text);
  expectSameScene(back, s);
}

// An empty file is refused (most likely a failed write); `{}` asks for the
// defaults.
TEST_F(SceneFiles, EmptyFileIsRefusedEmptyMapGivesDefaults) {
  for (const char* text : {"", "\n  \n", "# only a comment\n"}) {
    const std::string path = write("empty.yaml", text);
    try {
      cws::loadScene(path, {});
      ADD_FAILURE() << "an empty scene file was accepted: '" << text << "'";
    } catch (const cws::SceneError& e) {
      EXPECT_EQ(e.key(), "(file)");
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("no settings"), std::string::npos) << e.what();
    }
  }
  expectSameScene(cws::loadScene(write("defaults.yaml", "{}\n"), {}), cws::Scene{});
}

TEST_F(SceneFiles, PartialFileKeepsOtherDefaults) {
  const cws::Scene s = cws::loadScene(
      write("partial.yaml", "wire:\n  bend:\n    yield_curvature: 2.5\nprocess:\n  tension: 70\n"),
      {});
  EXPECT_EQ(s.wire.bend.yield, 2.5);
  EXPECT_EQ(s.process.tension, 70.0);
  EXPECT_EQ(s.wire.bend.elastic_rigidity, 3.06e-3);
  EXPECT_EQ(s.wire.stretch.yield, 8.0e-4);
  EXPECT_EQ(s.process.core_speed_rpm, 600.0);
}

// Overrides apply in order, after the file, so the last one wins.
TEST_F(SceneFiles, OverridesApplyInOrderAndWinOverFile) {
  const std::string path =
      write("s.yaml", "process:\n  tension: 50\n  turns: 3\nwire:\n  length: 0.02\n");
  const cws::Scene s = cws::loadScene(
      path, {"process.tension=60", "wire.length=0.03", "process.tension=70",
             "gravity.acceleration=[1, 2, 3]", "physics.gravity=true", "process.duration=1e-3"});
  EXPECT_EQ(s.process.tension, 70.0);
  EXPECT_EQ(s.wire.length, 0.03);
  EXPECT_EQ(s.process.turns, 3.0);  // from the file, not overridden
  expectVec(s.gravity.acceleration_world, Eigen::Vector3d(1.0, 2.0, 3.0), "gravity");
  EXPECT_TRUE(s.physics.gravity);
  ASSERT_TRUE(s.process.duration.has_value());
  EXPECT_EQ(*s.process.duration, 1e-3);
  // Without a file too.
  EXPECT_EQ(cws::loadScene("", {"process.tension=1", "process.tension=2"}).process.tension, 2.0);
}

TEST_F(SceneFiles, EndLoadListFromFile) {
  const cws::Scene s = cws::loadScene(write("s.yaml",
                                            "end:\n  load:\n    - {time: 0, force: [0, 0, 1]}\n"
                                            "    - {time: 0.5, moment: [0, 0.25, 0]}\n"),
                                      {});
  ASSERT_EQ(s.end.load.size(), 2u);
  EXPECT_EQ(s.end.load[0].time, 0.0);
  expectVec(s.end.load[0].force_world, Eigen::Vector3d(0, 0, 1), "force0");
  expectVec(s.end.load[0].moment_world, Eigen::Vector3d::Zero(), "moment0");
  EXPECT_EQ(s.end.load[1].time, 0.5);
  expectVec(s.end.load[1].force_world, Eigen::Vector3d::Zero(), "force1");
  expectVec(s.end.load[1].moment_world, Eigen::Vector3d(0, 0.25, 0), "moment1");
}

// ---------------------------------------------------------------------------
// Refused input: each names the offending key and says why.
TEST_F(SceneFiles, RefusesUnknownKeys) {
  expectRefused("wirre:\n  diameter: 1e-3\n", {}, "wirre", "unknown key");
  expectRefused("wire:\n  diamter: 1e-3\n", {}, "wire.diamter", "unknown key");
  expectRefused("wire:\n  stretch:\n    yield: 1e-3\n", {}, "wire.stretch.yield", "unknown key");
  expectRefused("solver:\n  rtol: 1e-6\n  order: 5\n", {}, "solver.order", "unknown key");
}

TEST_F(SceneFiles, RefusesRemovedKeysSayingWhatReplacedThem) {
  // In a file and as an override: the key named, and what stands in its place.
  expectRefused("solver:\n  strike_speed: 2.0\n", {}, "solver.strike_speed",
                "was removed: a landing counts as a strike from 1 m/s");
  expectRefused("", {"solver.line_search_halvings=3"}, "solver.line_search_halvings",
                "was removed: a Newton step that does not lower the residual is halved up to five");
  // Every key that went names itself and says it was removed, never
  // "unknown key".
  for (const char* key : {"solver.flag_rounds=3", "solver.flag_check_tol=1e-5",
                          "solver.return_mapping_round=1", "solver.predictor_tol=1e-3",
                          "solver.strike_window=1e-4", "solver.newton_energy_tol=3e-8"}) {
    const std::string name = std::string(key).substr(0, std::string(key).find('='));
    expectRefused("", {key}, name, "was removed: ");
  }
  // An integrator that went, and the key that went with it.
  expectRefused("", {"solver.integrator=rosenbrock2"}, "solver.integrator",
                "'rosenbrock2' was removed: ");
  expectRefused("solver:\n  integrator: generalized_alpha\n", {}, "solver.integrator",
                "'generalized_alpha' was removed: ");
  expectRefused("", {"solver.rho_infinity=0.5"}, "solver.rho_infinity",
                "was removed with the integrator generalized_alpha");
}

TEST_F(SceneFiles, RefusesWrongTypes) {
  expectRefused("wire:\n  diameter: thick\n", {}, "wire.diameter", "number");
  expectRefused("wire:\n  diameter: {value: 1e-3}\n", {}, "wire.diameter", "number");
  expectRefused("wire:\n  diameter: [1e-3]\n", {}, "wire.diameter", "number");
  expectRefused("gravity:\n  acceleration: [0, -9.81]\n", {}, "gravity.acceleration", "three");
  expectRefused("start:\n  direction: 1\n", {}, "start.direction", "three");
  expectRefused("start:\n  position: [0, zero, 0]\n", {}, "start.position[1]", "number");
  expectRefused("physics:\n  gravity: maybe\n", {}, "physics.gravity", "true or false");
  expectRefused("wire: 3\n", {}, "wire", "map");
  expectRefused("- 1\n- 2\n", {}, "(top level)", "map");
  expectRefused("end:\n  load: 5\n", {}, "end.load", "list");
  expectRefused("end:\n  load: []\n", {}, "end.load", "non-empty");
}

TEST_F(SceneFiles, RefusesNonFiniteNumbers) {
  expectRefused("wire:\n  length: .nan\n", {}, "wire.length", "finite");
  expectRefused("wire:\n  length: .inf\n", {}, "wire.length", "finite");
  expectRefused("process:\n  tension: -.inf\n", {}, "process.tension", "finite");
  expectRefused("", {"wire.bend.yield_curvature=.nan"}, "wire.bend.yield_curvature", "finite");
  expectRefused("", {"gravity.acceleration=[0, .inf, 0]"}, "gravity.acceleration[1]", "finite");
}

TEST_F(SceneFiles, RefusesNonPositiveElasticRigidity) {
  for (const char* law : {"stretch", "bend", "torsion"}) {
    const std::string key = std::string("wire.") + law + ".elastic_rigidity";
    expectRefused("", {key + "=0"}, key, "positive");
    expectRefused("", {key + "=-1"}, key, "positive");
  }
}

TEST_F(SceneFiles, RefusesNegativePlasticRigidity) {
  for (const char* law : {"stretch", "bend", "torsion"}) {
    const std::string key = std::string("wire.") + law + ".plastic_rigidity";
    expectRefused("", {key + "=-1e-6"}, key, "negative");
  }
}

TEST_F(SceneFiles, RefusesPlasticRigidityAboveElastic) {
  // Each plastic rigidity just above its Table 1 elastic rigidity.
  expectRefused("", {"wire.stretch.plastic_rigidity=4.9e4"}, "wire.stretch.plastic_rigidity",
                "above the elastic");
  expectRefused("", {"wire.bend.plastic_rigidity=3.1e-3"}, "wire.bend.plastic_rigidity",
                "above the elastic");
  expectRefused("", {"wire.torsion.plastic_rigidity=4.4e-3"}, "wire.torsion.plastic_rigidity",
                "above the elastic");
  // Equal rigidities (no hysteresis) are a valid limit.
  EXPECT_NO_THROW(cws::loadScene("", {"wire.bend.plastic_rigidity=3.06e-3"}));
}

TEST_F(SceneFiles, RefusesNonPositiveYield) {
  expectRefused("", {"wire.stretch.yield_strain=0"}, "wire.stretch.yield_strain", "positive");
  expectRefused("", {"wire.bend.yield_curvature=-1"}, "wire.bend.yield_curvature", "positive");
  expectRefused("", {"wire.torsion.yield_twist=0"}, "wire.torsion.yield_twist", "positive");
}

TEST_F(SceneFiles, RefusesContactDampingOutOfRange) {
  expectRefused("", {"contact.damping_ratio=-0.5"}, "contact.damping_ratio", "negative");
  expectRefused("", {"contact.damping_ratio=3"}, "contact.damping_ratio", "above 2");
  EXPECT_NO_THROW(cws::loadScene(write("z.yaml", "contact:\n  damping_ratio: 2.0\n"), {}));
}

TEST_F(SceneFiles, RefusesATraverseThatCannotMove) {
  const std::string three_d = "physics:\n  planar: false\n";
  expectRefused(three_d, {"process.winding_width=5e-3"}, "process.winding_width",
                "traverse_pitch is 0");
  expectRefused(three_d, {"process.traverse_pitch=1e-3", "process.winding_width=1e-4"},
                "process.winding_width", "wider than the wire");
  EXPECT_NO_THROW(cws::loadScene(
      write("t.yaml", three_d),
      {"process.traverse_pitch=1e-3", "process.winding_width=5e-3", "process.layers=2"}));
}

// Four layers of 1 mm wire stand at least 1 + 3 sqrt(3) / 2 = 3.598 mm
// high (orthocyclic, the closest packing): above flanges of 3 mm, below
// flanges of 3.7 mm; three layers (2.732 mm) fit under 3 mm.
TEST_F(SceneFiles, RefusesAnOverFullBobbin) {
  const std::string bobbin = std::string(CWS_SOURCE_DIR) + "/config/scenes/two_layers.yaml";
  auto load = [&](const std::string& layers, const std::string& height) {
    return cws::loadScene(
        bobbin, {"process.layers=" + layers, "core.flange_height=" + height, "wire.diameter=1e-3"});
  };
  try {
    load("4", "3e-3");
    ADD_FAILURE() << "an over-full bobbin was accepted";
  } catch (const cws::SceneError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.key(), "process.layers") << what;
    EXPECT_NE(what.find("over-full"), std::string::npos) << what;
    EXPECT_NE(what.find("0.003598"), std::string::npos) << what;
  }
  EXPECT_NO_THROW(load("3", "3e-3"));
  EXPECT_NO_THROW(load("4", "3.7e-3"));
  // With no end to the layers, or without flanges, nothing to check.
  EXPECT_NO_THROW(load("0", "3e-3"));
  EXPECT_NO_THROW(cws::loadScene(bobbin, {"process.layers=4", "physics.flanges=false"}));
}

// A job longer than its planned layers goes on in further layers up to what
// the bobbin holds (two_layers.yaml: 25 turns a layer, 3 mm flanges hold 3
// layers of 1 mm wire, 75 turns); one turn more is refused, with the
// capacity in turns.
TEST_F(SceneFiles, AJobPastItsPlannedLayersGoesOnUpToWhatTheBobbinHolds) {
  const std::string bobbin = std::string(CWS_SOURCE_DIR) + "/config/scenes/two_layers.yaml";
  const cws::Scene planned = cws::loadScene(bobbin, {});
  EXPECT_DOUBLE_EQ(planned.turnsPerLayer(), 25.0);
  EXPECT_EQ(planned.plannedLayers(), 2);  // 50 turns: exactly the plan
  EXPECT_EQ(planned.bobbinLayers(), 3);
  EXPECT_DOUBLE_EQ(planned.bobbinTurns(), 75.0);
  // The traverse lays what the bobbin holds: wire wound on after the job
  // lies in a further layer.
  EXPECT_EQ(planned.traverseLayers(), 3);
  EXPECT_EQ(cws::loadScene(bobbin, {"process.turns=50.05"}).plannedLayers(), 2);  // rounding
  EXPECT_EQ(cws::loadScene(bobbin, {"process.turns=51"}).plannedLayers(), 3);
  EXPECT_EQ(cws::loadScene(bobbin, {"process.turns=75"}).plannedLayers(), 3);
  // A job set by its duration keeps the plan.
  EXPECT_EQ(cws::loadScene(bobbin, {"process.duration=9"}).plannedLayers(), 2);
  // Without flanges the traverse stops after the job's layers.
  EXPECT_EQ(cws::loadScene(bobbin, {"physics.flanges=false"}).traverseLayers(), 2);
  try {
    cws::loadScene(bobbin, {"process.turns=76"});
    ADD_FAILURE() << "a full bobbin was accepted";
  } catch (const cws::SceneError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.key(), "process.turns") << what;
    EXPECT_NE(what.find("75 turns"), std::string::npos) << what;
    EXPECT_NE(what.find("full"), std::string::npos) << what;
  }
}

TEST_F(SceneFiles, RefusesKineticFrictionAboveStatic) {
  expectRefused("contact:\n  static_friction: 0.2\n  kinetic_friction: 0.25\n", {},
                "contact.kinetic_friction", "above static");
  // Equal is allowed.
  EXPECT_NO_THROW(cws::loadScene(
      write("eq.yaml", "contact:\n  static_friction: 0.2\n  kinetic_friction: 0.2\n"), {}));
}

TEST_F(SceneFiles, RefusesBadSegmentLength) {
  expectRefused("", {"wire.segment_length=0"}, "wire.segment_length", "positive");
  expectRefused("", {"wire.segment_length=-1e-3"}, "wire.segment_length", "positive");
  expectRefused("", {"wire.length=0.01", "wire.segment_length=0.02"}, "wire.segment_length",
                "longer");
}

TEST_F(SceneFiles, RefusesSolverSettings) {
  expectRefused("", {"solver.min_step=1e-3", "solver.max_step=1e-4"}, "solver.max_step", "below");
  expectRefused("", {"solver.integrator=euler"}, "solver.integrator", "unknown integrator");
  expectRefused("", {"solver.integrator=euler"}, "solver.integrator", "euler");
}

TEST_F(SceneFiles, RefusesLoadTimesNotIncreasing) {
  expectRefused("end:\n  load:\n    - {time: 0}\n    - {time: 0.1}\n    - {time: 0.1}\n", {},
                "end.load[2].time", "increase");
  expectRefused("end:\n  load:\n    - {time: 0.2}\n    - {time: 0.1}\n", {}, "end.load[1].time",
                "increase");
}

TEST_F(SceneFiles, RefusesUnknownKeyInLoadEntry) {
  expectRefused("end:\n  load:\n    - {time: 0, forse: [1, 0, 0]}\n", {}, "end.load[0].forse",
                "unknown key");
  expectRefused("end:\n  load:\n    - {time: 0}\n    - {time: 1, torque: [0, 0, 1]}\n", {},
                "end.load[1].torque", "unknown key");
}

TEST_F(SceneFiles, RefusesMalformedOverride) {
  expectRefused("", {"wire.length"}, "wire.length", "key.path=value");
  expectRefused("", {"=0.01"}, "=0.01", "key.path=value");
  expectRefused("", {"wire..length=0.01"}, "wire..length", "empty key");
}

TEST_F(SceneFiles, RefusesOverrideOfUnknownKey) {
  expectRefused("", {"wire.diamter=1e-3"}, "wire.diamter", "unknown key");
  expectRefused("", {"nosuch=1"}, "nosuch", "unknown key");
  expectRefused("", {"wire.stretch.yield=1"}, "wire.stretch.yield", "unknown key");
  // A later bad override is refused even after good ones.
  expectRefused("", {"process.tension=40", "process.tensoin=41"}, "process.tensoin", "unknown key");
}

TEST_F(SceneFiles, RefusesOverrideOfWrongType) {
  expectRefused("", {"process.tension=strong"}, "process.tension", "number");
  expectRefused("", {"start.direction=[1, 0]"}, "start.direction", "three");
}

TEST_F(SceneFiles, RefusesMissingFile) {
  const std::string missing = (dir_ / "no_such_scene.yaml").string();
  try {
    cws::loadScene(missing, {});
    ADD_FAILURE() << "a missing scene file was accepted";
  } catch (const cws::SceneError& e) {
    EXPECT_EQ(e.key(), "(file)");
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos) << e.what();
  }
}

TEST_F(SceneFiles, RefusesInvalidYaml) {
  const std::string path = write("broken.yaml", "wire: [1, 2\nprocess: {tension: 3\n");
  try {
    cws::loadScene(path, {});
    ADD_FAILURE() << "invalid YAML was accepted";
  } catch (const cws::SceneError& e) {
    EXPECT_EQ(e.key(), "(file)");
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not valid YAML"), std::string::npos) << e.what();
  }
}

// validateScene on structs directly (no YAML involved).
TEST(SceneValidate, NamesFirstBadKeyOfStruct) {
  auto keyOf = [](const cws::Scene& s) -> std::string {
    try {
      cws::validateScene(s);
    } catch (const cws::SceneError& e) {
      return e.key();
    }
    return "(accepted)";
  };
  EXPECT_EQ(keyOf(cws::Scene{}), "(accepted)");
  {
    cws::Scene s;
    s.wire.torsion.yield = 0.0;
    EXPECT_EQ(keyOf(s), "wire.torsion.yield_twist");
  }
  {
    cws::Scene s;
    s.wire.stretch.plastic_rigidity = 2.0 * s.wire.stretch.elastic_rigidity;
    EXPECT_EQ(keyOf(s), "wire.stretch.plastic_rigidity");
  }
  {
    cws::Scene s;
    s.contact.kinetic_friction = 0.5;
    EXPECT_EQ(keyOf(s), "contact.kinetic_friction");
  }
  {
    cws::Scene s;
    s.end.load = {cws::LoadKeyframe{}, cws::LoadKeyframe{}};  // both at t = 0
    EXPECT_EQ(keyOf(s), "end.load[1].time");
  }
  {
    cws::Scene s;
    s.solver.integrator = "rk4";
    EXPECT_EQ(keyOf(s), "solver.integrator");
  }
}

}  // namespace
