// The scene keys, each declared once: dotted name, field of the Scene
// struct, unit, allowed range and one line of documentation. The order is
// the printed scene's (sceneToYamlText) and the order in which values are
// read and their ranges checked. config/scenes/default.yaml documents the
// same keys (test_scene_keys.cpp holds both to that).
#include "coil_winding_sim/core/scene/scene_keys.hpp"

#include <cmath>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "coil_winding_sim/core/scene/integrators.hpp"
#include "coil_winding_sim/core/scene/wire_catalogue.hpp"
#include "scene_detail.hpp"

namespace cws {

namespace {
// ---------------------------------------------------------------------------
// Access to a field through a chain of pointers to members, e.g.
// Member<&Scene::contact, &ContactParams::stick_speed>.
template <class Obj, auto M, auto... Rest>
auto& walk(Obj& o) {
  if constexpr (sizeof...(Rest) == 0) {
    return o.*M;
  } else {
    return walk<std::remove_reference_t<decltype(o.*M)>, Rest...>(o.*M);
  }
}

template <auto... M>
struct Member {
  using T = std::remove_reference_t<decltype(walk<Scene, M...>(std::declval<Scene&>()))>;
  static T& ref(Scene& s) { return walk<Scene, M...>(s); }
  static const T& get(const Scene& s) { return walk<const Scene, M...>(s); }
};

// A key whose value is the field at the end of the member chain M.
template <auto... M>
SceneKey key(const char* name, const char* unit, KeyRange range, const char* doc) {
  using T = typename Member<M...>::T;
  return SceneKey{name, unit, std::move(range), doc,
                  KeyField<T>{&Member<M...>::ref, &Member<M...>::get}};
}

SceneKey list(const char* name, const char* unit, const ListKeyHandlers& handlers,
              const char* doc) {
  return SceneKey{name, unit, KeyRange{}, doc, &handlers};
}

KeyRange oneOf(std::vector<std::string> words) {
  return {KeyRange::kOneOf, std::move(words), 0, std::nullopt, ""};
}
// A whole number from 0 to `most`, at least `least` when that is given.
KeyRange count(int most, std::optional<int> least = std::nullopt) {
  return {KeyRange::kCount, {}, most, least, ""};
}

// Short names for the member chains of the table.
using S = Scene;
using Wire = WireParams;
using Law = HysteresisParams;
using Contact = ContactParams;
using Core = CoreParams;
using Shape = CoreShapeParams;
using Process = ProcessParams;
using Solver = SolverParams;
using Physics = PhysicsSwitches;
using Supply = SupplyParams;
using Tensioner = TensionerParams;

// ---------------------------------------------------------------------------
// The table: key<field's member chain>(dotted name, unit, range, doc), or
// list(dotted name, unit, handlers, doc). Numbers are also always finite.
std::vector<SceneKey> declareKeys() {
  using namespace detail;  // the list handlers
  const KeyRange kAny{KeyRange::kAny, {}, 0, std::nullopt, ""};
  const KeyRange kPositive{KeyRange::kPositive, {}, 0, std::nullopt, ""};
  const KeyRange kNonNegative{KeyRange::kNonNegative, {}, 0, std::nullopt, ""};
  const KeyRange kDirection{KeyRange::kDirection, {}, 0, std::nullopt, ""};
  const KeyRange kAutoStep{KeyRange::kPositive, {}, 0, std::nullopt, "auto"};
  return {
      key<&S::wire, &Wire::material>("wire.material", "", oneOf(wireMaterialNames()),
                                     "paper_table_1: the paper's measured wire; else the "
                                     "conductor whose values make the keys given as auto"),
      key<&S::wire, &Wire::nominal_diameter>("wire.nominal_diameter", "m", kNonNegative,
                                             "the bare conductor's (0: paper_table_1's)"),
      key<&S::wire, &Wire::insulation_grade>("wire.insulation_grade", "", count(3),
                                             "IEC 60317-0-1 enamel grade 1-3; 0: bare"),
      key<&S::wire, &Wire::diameter>("wire.diameter", "m", kPositive,
                                     "overall diameter: contact and the layers' geometry"),
      key<&S::wire, &Wire::line_density>("wire.line_density", "kg/m", kPositive,
                                         "mass per length (Table 1 prints 7.02e5, a typo)"),
      key<&S::wire, &Wire::length>("wire.length", "m", kPositive,
                                   "initial wire length of a scene without supply"),
      key<&S::wire, &Wire::segment_length>("wire.segment_length", "m", kPositive,
                                           "largest natural segment length l"),
      key<&S::wire, &Wire::stretch, &Law::elastic_rigidity>("wire.stretch.elastic_rigidity", "N",
                                                            kPositive, "axial rigidity EA"),
      key<&S::wire, &Wire::stretch, &Law::plastic_rigidity>(
          "wire.stretch.plastic_rigidity", "N", kNonNegative, "axial slope after yield"),
      key<&S::wire, &Wire::stretch, &Law::yield>("wire.stretch.yield_strain", "-", kPositive,
                                                 "first axial yield strain"),
      key<&S::wire, &Wire::bend, &Law::elastic_rigidity>("wire.bend.elastic_rigidity", "N m^2",
                                                         kPositive, "bending rigidity EI"),
      key<&S::wire, &Wire::bend, &Law::plastic_rigidity>("wire.bend.plastic_rigidity", "N m^2",
                                                         kNonNegative, "bending slope after yield"),
      key<&S::wire, &Wire::bend, &Law::yield>("wire.bend.yield_curvature", "1/m", kPositive,
                                              "first yield curvature"),
      key<&S::wire, &Wire::torsion, &Law::elastic_rigidity>(
          "wire.torsion.elastic_rigidity", "N m^2", kPositive, "torsional rigidity GJ"),
      key<&S::wire, &Wire::torsion, &Law::plastic_rigidity>(
          "wire.torsion.plastic_rigidity", "N m^2", kNonNegative, "torsional slope after yield"),
      key<&S::wire, &Wire::torsion, &Law::yield>("wire.torsion.yield_twist", "rad/m", kPositive,
                                                 "first yield twist"),

      key<&S::contact, &Contact::static_friction>("contact.static_friction", "-", kNonNegative,
                                                  "static friction coefficient mu_s"),
      key<&S::contact, &Contact::kinetic_friction>("contact.kinetic_friction", "-", kNonNegative,
                                                   "kinetic friction coefficient mu_d, <= mu_s"),
      key<&S::contact, &Contact::stiffness>("contact.stiffness", "N/m", kPositive,
                                            "virtual contact spring per mass point k_j"),
      key<&S::contact, &Contact::stick_stiffness>("contact.stick_stiffness", "N/m", kPositive,
                                                  "tangential spring holding a stuck point"),
      key<&S::contact, &Contact::stick_speed>("contact.stick_speed", "m/s", kPositive,
                                              "a slipping point sticks again below this speed"),
      key<&S::contact, &Contact::friction_law>("contact.friction_law", "",
                                               oneOf({"stick_speed", "elastic_slip"}),
                                               "stick below stick_speed, or elastic slip "
                                               "returned onto the friction cone"),
      key<&S::contact, &Contact::damping_ratio>("contact.damping_ratio", "-", kNonNegative,
                                                "dashpots of the normal and stick springs, "
                                                "fraction of critical; 0: the paper's"),

      key<&S::core, &Core::position_world>("core.position", "m", kAny,
                                           "a point of the core axis, world frame"),
      key<&S::core, &Core::axis_world>("core.axis", "-", kDirection,
                                       "rotation axis (core z), world frame"),
      key<&S::core, &Core::start_at_speed>("core.start_at_speed", "", kAny,
                                           "true: at process.core_speed_rpm from t = 0"),
      key<&S::core, &Core::max_angular_acceleration>("core.max_angular_acceleration", "rad/s^2",
                                                     kPositive,
                                                     "limit of the core's speed changes"),
      key<&S::core, &Core::shape, &Shape::kind>(
          "core.shape.kind", "", oneOf({"cylinders", "rounded_rectangle"}),
          "cylinders: core.cylinders and core.faces; rounded_rectangle: made from the three "
          "below"),
      key<&S::core, &Core::shape, &Shape::width>("core.shape.width", "m", kNonNegative,
                                                 "rounded_rectangle: along core x"),
      key<&S::core, &Core::shape, &Shape::height>("core.shape.height", "m", kNonNegative,
                                                  "rounded_rectangle: along core y"),
      key<&S::core, &Core::shape, &Shape::corner_radius>(
          "core.shape.corner_radius", "m", kNonNegative,
          "rounded_rectangle: radius of its corners (at most half the shorter side)"),
      list("core.cylinders", "m", kCylinderList, "cylinders: {center: [x, y], radius}"),
      list("core.faces", "m", kFaceList, "flat faces: {from: [x, y], to: [x, y]}"),
      key<&S::core, &Core::hull_faces>("core.hull_faces", "", kAny,
                                       "add the flat sides between neighbouring cylinders"),
      key<&S::core, &Core::flange_height>("core.flange_height", "m", kPositive,
                                          "with physics.flanges: their reach beyond the "
                                          "core's outermost surface"),
      key<&S::core, &Core::flange_spacing>("core.flange_spacing", "m", kNonNegative,
                                           "with physics.flanges: the distance between them "
                                           "(0: process.winding_width)"),

      key<&S::process, &Process::core_speed_rpm>("process.core_speed_rpm", "rpm", kAny,
                                                 "core speed, counter-clockwise positive"),
      key<&S::process, &Process::tension>("process.tension", "N", kNonNegative,
                                          "supply tension F_T"),
      key<&S::process, &Process::traverse_pitch>("process.traverse_pitch", "m", kAny,
                                                 "port travel along the core axis per core turn"),
      key<&S::process, &Process::winding_width>("process.winding_width", "m", kNonNegative,
                                                "between the flanges; the traverse reverses at "
                                                "its ends (0: never)"),
      key<&S::process, &Process::layers>("process.layers", "-", count(100000),
                                         "the job's planned traverse passes (0: no end); more "
                                         "turns go on in further layers up to the bobbin's"),
      key<&S::process, &Process::max_core_speed_rpm>("process.max_core_speed_rpm", "rpm", kPositive,
                                                     "setpoints beyond +- this are refused"),
      key<&S::process, &Process::max_tension>("process.max_tension", "N", kPositive,
                                              "setpoints above this are refused"),
      key<&S::process, &Process::turns>("process.turns", "-", kNonNegative,
                                        "core revolutions to simulate"),
      key<&S::process, &Process::duration>("process.duration", "s", kPositive,
                                           "when set (not ~), ends the run instead of turns"),
      list("process.commands", "s, rpm, N", kCommandList,
           "setpoints at simulated times {time, core_speed_rpm, tension}"),
      key<&S::process, &Process::traverse_stall_turn>(
          "process.traverse_stall_turn", "-", kNonNegative,
          "core turn at which the traverse stops (a fault; with traverse_stall_turns)"),
      key<&S::process, &Process::traverse_stall_turns>(
          "process.traverse_stall_turns", "-", kNonNegative,
          "core turns the traverse stays stopped, then goes on (0: never stops)"),

      key<&S::solver, &Solver::integrator>("solver.integrator", "", oneOf(integratorNames()),
                                           "time integrator"),
      key<&S::solver, &Solver::rtol>("solver.rtol", "-", kPositive, "relative tolerance"),
      key<&S::solver, &Solver::atol>("solver.atol", "m", kPositive,
                                     "absolute tolerance on positions"),
      key<&S::solver, &Solver::min_step>("solver.min_step", "s", kPositive,
                                         "step floor; below it the run stops"),
      key<&S::solver, &Solver::max_step>("solver.max_step", "s", kPositive, "largest step"),
      key<&S::solver, &Solver::initial_step>("solver.initial_step", "s", kAny,
                                             "first step, within [min_step, max_step]"),
      key<&S::solver, &Solver::fixed_step>("solver.fixed_step", "s", kAutoStep,
                                           "step of symplectic_euler; auto: 1/4 of l / c"),
      key<&S::solver, &Solver::baumgarte_nu>("solver.baumgarte_nu", "1/s", kNonNegative,
                                             "constraint stabilization nu, eq. (6)"),
      key<&S::solver, &Solver::implicit_step>("solver.implicit_step", "s", kPositive,
                                              "longest step of implicit_euler and bdf2"),
      key<&S::solver, &Solver::steps_per_revolution>(
          "solver.steps_per_revolution", "-", kNonNegative,
          "implicit steps per core revolution at the core's speed (0: implicit_step)"),
      key<&S::solver, &Solver::strike_step>(
          "solver.strike_step", "s", kNonNegative,
          "Newton steps where the core strikes the free span (0: no such steps)"),
      key<&S::solver, &Solver::newton_tol>("solver.newton_tol", "m", kPositive,
                                           "Newton's bound on the largest position update"),
      key<&S::solver, &Solver::newton_max_iterations>("solver.newton_max_iterations", "-",
                                                      count(1000, 1),
                                                      "Newton iterations before a retry at 1/4"),
      key<&S::solver, &Solver::carry_stuck_wire>("solver.carry_stuck_wire", "", kAny,
                                                 "stuck wound wire moves rigidly with the core"),

      key<&S::physics, &Physics::torsion>("physics.torsion", "", kAny, "twist and torsion"),
      key<&S::physics, &Physics::plasticity>("physics.plasticity", "", kAny,
                                             "false: linear elastic laws"),
      key<&S::physics, &Physics::gravity>("physics.gravity", "", kAny, "the wire's weight"),
      key<&S::physics, &Physics::damping>("physics.damping", "", kAny, "viscous damping"),
      key<&S::physics, &Physics::air_drag>("physics.air_drag", "", kAny,
                                           "quadratic drag of still air"),
      key<&S::physics, &Physics::contact>("physics.contact", "", kAny,
                                          "wire against the core's cylinders and faces"),
      key<&S::physics, &Physics::friction>("physics.friction", "", kAny,
                                           "static/kinetic friction on contact"),
      key<&S::physics, &Physics::flanges>("physics.flanges", "", kAny,
                                          "the core's flanges at the ends of "
                                          "process.winding_width (with contact, 3-D)"),
      key<&S::physics, &Physics::wire_contact>("physics.wire_contact", "", kAny,
                                               "wire against the wound wire the core carries, "
                                               "as capsules (3-D)"),
      key<&S::physics, &Physics::supply>("physics.supply", "", kAny,
                                         "wire drawn in through a port at constant tension"),
      key<&S::physics, &Physics::planar>("physics.planar", "", kAny,
                                         "motion in the plane normal to core.axis"),

      key<&S::supply, &Supply::port_position_world>("supply.port_position", "m", kAny,
                                                    "port p_s at t = 0, world frame"),
      key<&S::supply, &Supply::max_points>("supply.max_points", "-",
                                           KeyRange{KeyRange::kPointCount, {}, 0, std::nullopt, ""},
                                           "storage for this many live points (buried wire "
                                           "retires beyond them); 0: estimated"),
      key<&S::supply, &Supply::tensioner, &Tensioner::kind>(
          "supply.tensioner.kind", "", oneOf({"ideal", "dancer"}),
          "ideal: the port's tension is the setpoint; dancer: a spring-loaded arm and a "
          "servo pay-off between them"),
      key<&S::supply, &Supply::tensioner, &Tensioner::mass>(
          "supply.tensioner.mass", "kg", kPositive, "dancer: the arm's moving mass at its pulley"),
      key<&S::supply, &Supply::tensioner, &Tensioner::stiffness>(
          "supply.tensioner.stiffness", "N/m", kNonNegative,
          "dancer: its spring's rate about the centre"),
      key<&S::supply, &Supply::tensioner, &Tensioner::damping>("supply.tensioner.damping", "N s/m",
                                                               kNonNegative, "dancer: its damper"),
      key<&S::supply, &Supply::tensioner, &Tensioner::bandwidth>(
          "supply.tensioner.bandwidth", "rad/s", kPositive,
          "dancer: the pay-off's position loop (a double pole there)"),
      key<&S::supply, &Supply::tensioner, &Tensioner::span_length>(
          "supply.tensioner.span_length", "m", kPositive,
          "dancer: wire from the pay-off over the pulley to the nozzle"),
      key<&S::supply, &Supply::nozzle_friction>(
          "supply.nozzle_friction", "-", kNonNegative,
          "the nozzle's capstan friction: the port's tension is exp(mu theta) times the "
          "tensioner's while wire is drawn in"),
      key<&S::supply, &Supply::nozzle_wrap_angle>("supply.nozzle_wrap_angle", "rad", kNonNegative,
                                                  "the wire's wrap over the nozzle"),

      key<&S::gravity, &GravityParams::acceleration_world>(
          "gravity.acceleration", "m/s^2", kAny, "gravitational acceleration, world frame"),
      key<&S::damping, &DampingParams::translational>(
          "damping.translational", "N s/m^2", kNonNegative, "viscous force per length and speed"),
      key<&S::damping, &DampingParams::rotational>("damping.rotational", "N m s/m", kNonNegative,
                                                   "viscous moment per length and spin rate"),
      key<&S::air_drag, &AirDragParams::density>("air_drag.density", "kg/m^3", kNonNegative,
                                                 "density of the air"),
      key<&S::air_drag, &AirDragParams::drag_coefficient>(
          "air_drag.drag_coefficient", "-", kNonNegative,
          "drag coefficient of a cylinder across the flow"),

      key<&S::start, &StartParams::type>("start.type", "", oneOf({"clamped"}),
                                         "fixed end: position and direction held"),
      key<&S::start, &StartParams::frame>("start.frame", "", oneOf({"world", "core"}),
                                          "frame of the clamp"),
      key<&S::start, &StartParams::position>("start.position", "m", kAny,
                                             "clamp position in start.frame"),
      key<&S::start, &StartParams::direction>("start.direction", "-", kDirection,
                                              "wire tangent at the clamp"),

      key<&S::end, &EndParams::type>("end.type", "", oneOf({"free"}), "the last mass point"),
      list("end.load", "s, N, N m", kLoadList, "keyframes {time, force, moment}"),

      key<&S::output, &OutputParams::progress_interval_s>(
          "output.progress_interval_s", "s", kPositive, "wall time between progress lines"),
  };
}

// ---------------------------------------------------------------------------
// The table's own consistency, checked once when it is built: names unique
// and each range one its type can have.
struct RangeFits {
  const KeyRange::Kind kind;
  bool operator()(const KeyField<double>&) const { return number(); }
  bool operator()(const KeyField<std::optional<double>>&) const { return number(); }
  bool operator()(const KeyField<Eigen::Vector3d>&) const {
    return kind == KeyRange::kAny || kind == KeyRange::kDirection;
  }
  bool operator()(const KeyField<bool>&) const { return kind == KeyRange::kAny; }
  bool operator()(const KeyField<std::string>&) const { return kind == KeyRange::kOneOf; }
  bool operator()(const KeyField<int>&) const {
    return kind == KeyRange::kPointCount || kind == KeyRange::kCount;
  }
  bool operator()(const ListKeyHandlers*) const { return kind == KeyRange::kAny; }
  bool number() const {
    return kind == KeyRange::kAny || kind == KeyRange::kPositive || kind == KeyRange::kNonNegative;
  }
};

std::vector<SceneKey> checkedKeys() {
  std::vector<SceneKey> keys = declareKeys();
  for (std::size_t i = 0; i < keys.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (keys[i].name == keys[j].name) {
        throw std::logic_error("scene key '" + keys[i].name + "' is declared twice");
      }
    }
    if (!std::visit(RangeFits{keys[i].range.kind}, keys[i].access)) {
      throw std::logic_error("scene key '" + keys[i].name + "': its range does not fit its type");
    }
  }
  return keys;
}
}  // namespace

const std::vector<SceneKey>& sceneKeys() {
  static const std::vector<SceneKey> keys = checkedKeys();
  return keys;
}

const SceneKey* findSceneKey(const std::string& name) {
  for (const SceneKey& k : sceneKeys()) {
    if (k.name == name) return &k;
  }
  return nullptr;
}

namespace {
struct TypeName {
  const char* operator()(const KeyField<double>&) const { return "number"; }
  const char* operator()(const KeyField<std::optional<double>>&) const { return "optional number"; }
  const char* operator()(const KeyField<Eigen::Vector3d>&) const { return "vector"; }
  const char* operator()(const KeyField<bool>&) const { return "switch"; }
  const char* operator()(const KeyField<std::string>&) const { return "word"; }
  const char* operator()(const KeyField<int>&) const { return "count"; }
  const char* operator()(const ListKeyHandlers*) const { return "list"; }
};
}  // namespace

const char* SceneKey::type() const { return std::visit(TypeName{}, access); }

// ---------------------------------------------------------------------------
// Checks from the table.
namespace detail {

void requirePositive(double v, const std::string& key) {
  if (!(v > 0.0)) throw SceneError(key, "must be positive, got " + fmt(v));
}

void requireNonNegative(double v, const std::string& key) {
  if (!(v >= 0.0)) throw SceneError(key, "must not be negative, got " + fmt(v));
}

namespace {
// A direction: not zero, and short enough that its length does not overflow
// (normalizing [1e300, 1e300, 0] would give the zero vector).
void requireDirection(const Eigen::Vector3d& v, const std::string& key) {
  const double norm = v.norm();
  if (!(norm > 1e-12) || !std::isfinite(norm)) {
    throw SceneError(key,
                     "must be a direction: a vector of length above 1e-12 whose length "
                     "does not overflow, got length " +
                         fmt(norm));
  }
}

void requireNumber(const KeyRange& range, double v, const std::string& key) {
  if (range.kind == KeyRange::kPositive) requirePositive(v, key);
  if (range.kind == KeyRange::kNonNegative) requireNonNegative(v, key);
}

// "unknown integrator 'x' (available: rkf45, ...)": the noun is the key's
// last name.
void requireWord(const KeyRange& range, const std::string& v, const std::string& key) {
  std::string available;
  for (const std::string& w : range.words) {
    if (v == w) return;
    available += (available.empty() ? "" : ", ") + w;
  }
  if (const char* why = removedSceneWord(key, v)) throw SceneError(key, "'" + v + "' " + why);
  const std::string noun = key.substr(key.rfind('.') + 1);
  throw SceneError(key,
                   "unknown " + noun + " '" + printable(v) + "' (available: " + available + ")");
}

struct RangeCheck {
  const SceneKey& k;
  const Scene& s;
  void operator()(const KeyField<double>& f) const { requireNumber(k.range, f.get(s), k.name); }
  void operator()(const KeyField<std::optional<double>>& f) const {
    if (f.get(s)) requireNumber(k.range, *f.get(s), k.name);  // unset is allowed
  }
  void operator()(const KeyField<Eigen::Vector3d>& f) const {
    if (k.range.kind == KeyRange::kDirection) requireDirection(f.get(s), k.name);
  }
  void operator()(const KeyField<bool>&) const {}
  void operator()(const KeyField<std::string>& f) const { requireWord(k.range, f.get(s), k.name); }
  // Reading checks that a count is whole (and within [0, most]); a point
  // count's range applies with physics.supply only: a cross-key rule
  // (scene_validation.cpp).
  void operator()(const KeyField<int>& f) const {
    if (k.range.kind == KeyRange::kCount && k.range.least && f.get(s) < *k.range.least) {
      throw SceneError(k.name, "must be at least " + std::to_string(*k.range.least) + ", got " +
                                   std::to_string(f.get(s)));
    }
  }
  void operator()(const ListKeyHandlers* list) const { list->check(s, k.name); }
};

struct NumberWalk {
  const SceneKey& k;
  const Scene& s;
  const NumberVisitor& fn;
  void operator()(const KeyField<double>& f) const { fn(k.name, f.get(s)); }
  void operator()(const KeyField<std::optional<double>>& f) const {
    if (f.get(s)) fn(k.name, *f.get(s));
  }
  void operator()(const KeyField<Eigen::Vector3d>& f) const {
    for (int i = 0; i < 3; ++i) fn(k.name + "[" + std::to_string(i) + "]", f.get(s)[i]);
  }
  void operator()(const KeyField<bool>&) const {}
  void operator()(const KeyField<std::string>&) const {}
  void operator()(const KeyField<int>&) const {}
  void operator()(const ListKeyHandlers* list) const { list->forEachNumber(s, k.name, fn); }
};
}  // namespace

void checkRange(const SceneKey& key, const Scene& s) { std::visit(RangeCheck{key, s}, key.access); }

void forEachNumber(const Scene& s, const NumberVisitor& fn) {
  for (const SceneKey& k : sceneKeys()) std::visit(NumberWalk{k, s, fn}, k.access);
}

}  // namespace detail
}  // namespace cws
