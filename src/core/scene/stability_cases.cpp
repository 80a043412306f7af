// The stability matrix's cases (stability_cases.hpp).
#include "coil_winding_sim/core/scene/stability_cases.hpp"

#include <stdexcept>

#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

namespace {
std::vector<StabilityCase> makeCases() {
  const char* x100[] = {
      "wire.stretch.elastic_rigidity=4.89e6", "wire.stretch.plastic_rigidity=1.10e5",
      "wire.bend.elastic_rigidity=0.306",     "wire.bend.plastic_rigidity=1.13e-2",
      "wire.torsion.elastic_rigidity=0.432",  "wire.torsion.plastic_rigidity=9.0e-3"};
  std::vector<StabilityCase> cases;
  cases.push_back({"baseline", "the paper's case (1 3/4 turns)", {}, {}});
  cases.push_back({"rigidity_x100", "all rigidities x100, 1/2 turn", {x100, x100 + 6}, {}});
  cases.back().overrides.push_back("process.turns=0.5");
  cases.push_back({"segment_0.2mm",
                   "segments of 0.2 mm, 1/10 turn",
                   {"wire.segment_length=2e-4", "process.turns=0.1"},
                   {}});
  // The paper's 2.5 mm cylinders refuse segments longer than their radius
  // (a segment could pass through one); a core of 5 mm cylinders (25 x 15
  // mm) takes them.
  const std::vector<std::string> core_r5mm = {
      "wire.segment_length=5e-3",
      "core.cylinders=[{center: [7.5e-3, 2.5e-3], radius: 5e-3}, "
      "{center: [-7.5e-3, 2.5e-3], radius: 5e-3}, "
      "{center: [-7.5e-3, -2.5e-3], radius: 5e-3}, "
      "{center: [7.5e-3, -2.5e-3], radius: 5e-3}]",
      "start.position=[7.5e-3, -8.0e-3, 0]", "supply.port_position=[-27.5e-3, -8.0e-3, 0]"};
  cases.push_back({"segment_5mm", "segments of 5 mm", {"wire.segment_length=5e-3"}, {}});
  cases.push_back({"segment_5mm_core_r5mm",
                   "segments of 5 mm on a core of 5 mm-radius cylinders",
                   core_r5mm,
                   {}});
  cases.push_back({"core_20000rpm",
                   "core speed 0 -> 20,000 rpm in one instant at t = 0",
                   {"process.core_speed_rpm=20000", "process.max_core_speed_rpm=20000",
                    "core.start_at_speed=false", "core.max_angular_acceleration=1e12"},
                   {}});
  cases.push_back({"tension_0N", "slack wire: supply tension 0 N", {"process.tension=0"}, {}});
  cases.push_back(
      {"tension_300N", "supply tension 300 N (far past axial yield)", {"process.tension=300"}, {}});
  cases.push_back({"friction_0",
                   "no friction (mu_s = mu_d = 0)",
                   {"contact.static_friction=0", "contact.kinetic_friction=0"},
                   {}});
  cases.push_back({"friction_1",
                   "mu_s = mu_d = 1",
                   {"contact.static_friction=1", "contact.kinetic_friction=1"},
                   {}});
  cases.push_back({"perfectly_plastic",
                   "zero plastic rigidities",
                   {"wire.stretch.plastic_rigidity=0", "wire.bend.plastic_rigidity=0",
                    "wire.torsion.plastic_rigidity=0"},
                   {}});
  cases.push_back({"purely_elastic", "no plasticity", {"physics.plasticity=false"}, {}});
  // The core at rest, then 1200 rpm within one step (the acceleration
  // limit raised far above any machine's).
  cases.push_back({"speed_step",
                   "core speed 0 -> 1200 rpm in one instant at t = 0",
                   {"core.start_at_speed=false", "core.max_angular_acceleration=1e12"},
                   {}});
  // Forward half a turn, then reversed at the scene's acceleration limit:
  // with the supply, until the wire is drawn back through the port (which
  // the supply cannot do: a stated stop); without it, a 50 mm wire clamped
  // on the core whips round and back.
  cases.push_back({"reversal",
                   "1200 rpm, reversed to -1200 rpm at t = 25 ms, until t = 75 ms",
                   {"core.start_at_speed=true", "process.duration=0.075"},
                   {{0.025, cws::rpmToRadPerSec(-1200.0)}}});
  cases.push_back({"reversal_no_supply",
                   "as reversal, a 50 mm wire clamped on the core without supply",
                   {"core.start_at_speed=true", "process.duration=0.075", "physics.supply=false"},
                   {{0.025, cws::rpmToRadPerSec(-1200.0)}}});
  // Planar winding on a round drum: one 5 mm cylinder, 10 turns, where the
  // frames once left the plane (docs/MODEL.md). (The model has no
  // wire-on-wire contact: the turns lie on one another at the drum's radius,
  // 0.35 m of wire in about 190 points, within the storage estimate.)
  cases.push_back(
      {"planar_drum",
       "10 turns on a single 5 mm-radius drum, planar",
       {"core.cylinders=[{center: [0, 0], radius: 5e-3}]", "start.position=[5.5e-3, 0, 0]",
        "start.direction=[0, 1, 0]", "supply.port_position=[5.5e-3, -0.03, 0]", "process.turns=10",
        "physics.planar=true"},
       {}});
  // A coil in two layers (3-D, 1 mm segments as wire contact assumes):
  // four turns on the core between flanges 5 mm apart, the reversal at the
  // far flange, four turns back in the grooves. (It ends with the second
  // pass: a port held after it piles the wire onto the turn just laid.)
  cases.push_back({"two_layers",
                   "two layers of 4 turns between flanges 5 mm apart, wire on wire, 3-D",
                   {"wire.segment_length=1e-3", "physics.planar=false", "physics.torsion=true",
                    "process.traverse_pitch=1e-3", "process.winding_width=5e-3", "process.layers=2",
                    "physics.flanges=true", "physics.wire_contact=true", "process.turns=8"},
                   {}});
  // A long run at production speed (the scene's speed limit for setpoints):
  // 100 turns take 1 s. On the paper's core with 2 mm segments they feed
  // 2,900 points; with 5 mm segments on the larger core, 1,500. Little of
  // that wire is carried (5-11 points: the spans between the cylinders
  // vibrate faster than contact.stick_speed), so each step grows with the
  // wire: RKF45 needs about 2 1/4 hours on a 2-core machine.
  std::vector<std::string> long_run = core_r5mm;
  long_run.push_back("process.turns=100");
  long_run.push_back("process.core_speed_rpm=6000");
  cases.push_back(
      {"turns_100", "100 turns at 6000 rpm, 5 mm segments on the 5 mm-radius core", long_run, {}});
  return cases;
}
}  // namespace

const std::vector<StabilityCase>& stabilityCases() {
  static const std::vector<StabilityCase> cases = makeCases();
  return cases;
}

const StabilityCase& stabilityCase(const std::string& name) {
  for (const StabilityCase& c : stabilityCases()) {
    if (c.name == name) return c;
  }
  throw std::out_of_range("no stability case named '" + name + "'");
}

}  // namespace cws
