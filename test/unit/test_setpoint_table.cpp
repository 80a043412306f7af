// The setpoint table (run/setpoint.hpp): one row per kind, each applied
// through Simulation::apply, checked against the scene key its row names,
// and logged.
#include <gtest/gtest.h>

#include <set>
#include <stdexcept>
#include <string>

#include "coil_winding_sim/core/run/setpoint.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace {
const std::string kDefault = std::string(CWS_SOURCE_DIR) + "/config/scenes/default.yaml";

// A setpoint of each kind that the default scene (with damping on) takes.
cws::Setpoint allowed(cws::Setpoint::Kind kind, const cws::Simulation& sim) {
  using Kind = cws::Setpoint::Kind;
  switch (kind) {
    case Kind::kCoreSpeed:
      return cws::Setpoint::coreSpeed(50.0);
    case Kind::kSupplyTension:
      return cws::Setpoint::supplyTension(40.0);
    case Kind::kPortPosition:
      return cws::Setpoint::portPosition(
          sim.model().supply()->port(sim.time()).p_world + Eigen::Vector3d(-1e-5, 0.0, 0.0),
          sim.time() + 1e-3);
    case Kind::kFriction:
      return cws::Setpoint::friction(0.3, 0.2);
    case Kind::kDamping:
      return cws::Setpoint::damping(1.0, 1e-6);
  }
  return {};
}
}  // namespace

TEST(SetpointTable, OneRowPerKindInTheOrderOfTheKinds) {
  const std::vector<cws::SetpointRow>& rows = cws::setpointTable();
  ASSERT_EQ(rows.size(), 5u);
  std::set<std::string> names, topics;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const cws::SetpointRow& row = rows[k];
    EXPECT_EQ(static_cast<std::size_t>(row.kind), k) << row.name;
    EXPECT_TRUE(names.insert(row.name).second) << "two rows named " << row.name;
    EXPECT_NE(row.target, nullptr) << row.name;
    EXPECT_EQ(cws::setpointRowNamed(row.name), &row);
    if (*row.topic) {
      EXPECT_TRUE(topics.insert(row.topic).second) << "two rows on topic " << row.topic;
      EXPECT_STRNE(row.message_field, "") << row.name;
    }
    EXPECT_EQ(&cws::setpointRow(row.kind), &row);
  }
}

// Every kind reaches the model through apply() and is logged; the row's
// limit refuses a value far beyond it, naming its scene key, and the
// refused one is neither applied nor logged.
TEST(SetpointTable, EveryKindIsAppliedCheckedAndLogged) {
  cws::Simulation sim(cws::loadScene(kDefault, {"solver.integrator=bdf2", "physics.damping=true"}));
  sim.step(sim.endTime());
  std::size_t logged = 0;
  for (const cws::SetpointRow& row : cws::setpointTable()) {
    const cws::Setpoint sp = allowed(row.kind, sim);
    EXPECT_NO_THROW(sim.apply(sp)) << row.name;
    ASSERT_EQ(sim.inputs().inputs().size(), ++logged) << row.name;
    EXPECT_EQ(sim.inputs().inputs().back().setpoint.kind, row.kind);
    if (!row.refusal) continue;
    cws::Setpoint beyond = sp;
    beyond.value = 1e12;
    try {
      sim.apply(beyond);
      ADD_FAILURE() << row.name << " " << beyond.value << " was taken";
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(row.name, 0), 0u) << what;
      EXPECT_NE(what.find(row.limit_key), std::string::npos) << what;
    }
    EXPECT_EQ(sim.inputs().inputs().size(), logged) << row.name;
  }
  // The values applied are the model's now.
  EXPECT_EQ(sim.model().core()->command(), 50.0);
  EXPECT_EQ(sim.scene().contact.static_friction, 0.3);
  EXPECT_EQ(sim.scene().damping.translational, 1.0);
  EXPECT_TRUE(sim.portCommanded());
}

// Each row's snapshot field keeps what its target drives: a simulation
// restored from the state saved after every kind was applied holds the
// same values, and each row's machine topic is one of the machine
// interface's (docs/MACHINE_INTERFACE.md), on a topic of its own.
TEST(SetpointTable, EveryKindsValueSurvivesASnapshot) {
  cws::Simulation sim(cws::loadScene(kDefault, {"solver.integrator=bdf2", "physics.damping=true"}));
  sim.step(sim.endTime());
  std::set<std::string> machine_topics;
  for (const cws::SetpointRow& row : cws::setpointTable()) {
    sim.apply(allowed(row.kind, sim));
    if (!*row.machine_topic) continue;
    EXPECT_EQ(std::string(row.machine_topic).rfind("machine/", 0), 0u) << row.name;
    EXPECT_TRUE(machine_topics.insert(row.machine_topic).second) << row.machine_topic;
  }
  // The rows that hold a value keep it in the state; the core's speed and
  // the port's path are the model's state.
  cws::SimulationState state = sim.saveState();
  std::set<std::string> held;
  for (const cws::Setpoint& sp : state.held) EXPECT_TRUE(held.insert(sp.name()).second);
  EXPECT_EQ(held, (std::set<std::string>{"tension", "friction", "damping"}));
  const std::unique_ptr<cws::Simulation> back = cws::Simulation::fromState(state);
  EXPECT_EQ(back->model().core()->command(), 50.0);
  EXPECT_EQ(back->model().supply()->tension(), 40.0);
  EXPECT_TRUE(back->portCommanded());
  EXPECT_EQ(back->portCommandEnd(), sim.portCommandEnd());
  EXPECT_EQ(back->scene().contact.static_friction, 0.3);
  EXPECT_EQ(back->scene().contact.kinetic_friction, 0.2);
  EXPECT_EQ(back->scene().damping.translational, 1.0);
  EXPECT_EQ(back->scene().damping.rotational, 1e-6);
  // A held value passes its row's check on restore.
  cws::holdSetpoint(state, cws::Setpoint::supplyTension(1e6));
  try {
    cws::Simulation::fromState(state);
    ADD_FAILURE() << "a tension beyond the limit was restored";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("process.max_tension"), std::string::npos) << e.what();
  }
}
