// The scene keys and key values that went (issue 61: a knob stays where a
// default or a reference uses it, or a measured reason documents it), each
// with what took its place: a scene that still sets one is refused with
// it (scene_load.cpp, scene_keys.cpp's word check).
#include <string>

#include "coil_winding_sim/core/scene/scene_keys.hpp"

namespace cws {

const char* removedSceneKey(const std::string& name) {
  struct Removed {
    const char* name;
    const char* why;
  };
  static const Removed kRemoved[] = {
      {"solver.strike_speed",
       "was removed: a landing counts as a strike from 1 m/s relative to the core, as the "
       "strike steps were measured (docs/MODEL.md, \"Steps through a struck span\")"},
      {"solver.line_search_halvings",
       "was removed: a Newton step that does not lower the residual is halved up to five "
       "times (docs/MODEL.md, \"Implicit integration of planar scenes\")"},
      {"solver.flag_rounds",
       "was removed: a Newton step is solved again after a contact, stick or slip change up "
       "to eight times (docs/MODEL.md, \"Implicit integration of planar scenes\")"},
      {"solver.flag_check_tol",
       "was removed: a solve whose Newton step falls below 3e-7 m rechecks its flags before "
       "it converges (docs/MODEL.md, \"Implicit integration of planar scenes\")"},
      {"solver.return_mapping_round",
       "was removed: from a step's second flag round on, the solve return-maps the "
       "hysteresis lines (docs/MODEL.md, \"Implicit integration of planar scenes\")"},
      {"solver.strike_window",
       "was removed: the steps stay at solver.strike_step for 1.5e-4 s after a strike "
       "(docs/MODEL.md, \"Steps through a struck span\")"},
      {"solver.newton_energy_tol",
       "was removed: a Newton solve converges when no point moves more than solver.newton_tol "
       "(the energy tolerance's figures: "
       "docs/history/2026-12-06-newton-energy-tolerance-figures.md)"},
      {"solver.rho_infinity",
       "was removed with the integrator generalized_alpha (docs/history/"
       "2026-12-06-friction-law-and-generalized-alpha-figures.md); the Newton-step methods "
       "are implicit_euler and bdf2"},
      {"solver.predictor_tol",
       "was removed: a step whose solution lies farther than 1e-4 m from its predictor is "
       "retried at a quarter (docs/MODEL.md, \"Implicit integration of planar scenes\")"},
  };
  for (const Removed& r : kRemoved) {
    if (name == r.name) return r.why;
  }
  return nullptr;
}

// Values of a word key that went (issue 61): the integrators.
const char* removedSceneWord(const std::string& key, const std::string& value) {
  struct Removed {
    const char* key;
    const char* value;
    const char* why;
  };
  static const Removed kRemoved[] = {
      {"solver.integrator", "rosenbrock2",
       "was removed: it stopped on every winding scene (contact and stick/slip hold its step "
       "below the explicit limit); use bdf2, or rkf45 (docs/history/"
       "2026-12-06-integrators-and-solver-keys-that-went.md)"},
      {"solver.integrator", "generalized_alpha",
       "was removed: bdf2 with strike steps, the default, meets the accuracy target faster; "
       "use bdf2 (docs/history/2026-12-06-integrators-and-solver-keys-that-went.md)"},
  };
  for (const Removed& r : kRemoved) {
    if (key == r.key && value == r.value) return r.why;
  }
  return nullptr;
}

}  // namespace cws
