#include "coil_winding_sim/core/run/output.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "coil_winding_sim/core/run/quality_report.hpp"
#include "coil_winding_sim/core/scene/integrators.hpp"

namespace cws {

namespace fs = std::filesystem;

namespace {
std::string num(double v) {
  if (!std::isfinite(v)) return "null";
  std::ostringstream s;
  s << std::setprecision(12) << v;
  return s.str();
}

// The files writeOutputs writes.
const char* const kOutputFiles[] = {"summary.json", "wire.csv", "shape_core.csv"};
// A JSON string's content: quotes, backslashes and control characters
// escaped.
std::string jsonEscaped(const std::string& text) {
  std::string out;
  for (const char ch : text) {
    if (ch == '"' || ch == '\\') {
      out += '\\';
      out += ch;
    } else if (static_cast<unsigned char>(ch) < 0x20) {
      char code[8];
      std::snprintf(code, sizeof code, "\\u%04x", static_cast<unsigned>(ch));
      out += code;
    } else {
      out += ch;
    }
  }
  return out;
}
}  // namespace

void writeFileAtomically(const std::string& path, const std::string& text) {
  const fs::path tmp = path + ".partial";
  std::error_code ec;
  try {
    std::ofstream f(tmp);
    if (!f) throw std::runtime_error("cannot write '" + tmp.string() + "'");
    f << text;
    f.flush();
    if (!f) throw std::runtime_error("failed writing '" + tmp.string() + "'");
  } catch (...) {
    fs::remove(tmp, ec);  // no half-written file left behind
    throw;
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    const std::string why = ec.message();
    fs::remove(tmp, ec);
    throw std::runtime_error("cannot rename to '" + path + "': " + why);
  }
}

void removeOutputs(const std::string& dir) {
  for (const char* name : kOutputFiles) {
    for (const char* suffix : {"", ".partial"}) {
      const fs::path p = fs::path(dir) / (std::string(name) + suffix);
      std::error_code ec;
      fs::remove(p, ec);
      if (ec) {
        throw std::runtime_error("cannot remove the earlier result '" + p.string() +
                                 "': " + ec.message());
      }
    }
  }
}

void writeSummaryJson(const Simulation& sim, std::ostream& out, const ErrorEstimate* estimate,
                      const RunStop* stop) {
  const EnergyReport e = sim.energy();
  const StepCounts& n = sim.stepper().counts();
  out << "{\n";
  // A run that ended early: the state it reached, and why (only then).
  if (stop) {
    out << "  \"stopped\": {\"cause\": \"" << jsonEscaped(stop->cause) << "\", \"message\": \""
        << jsonEscaped(stop->message) << "\", \"end_time_s\": " << num(sim.endTime()) << "},\n";
  }
  out << "  \"sim_time_s\": " << num(sim.time()) << ",\n"
      << "  \"wall_time_s\": " << num(sim.wallTime()) << ",\n"
      << "  \"real_time_factor\": " << num(sim.realTimeFactor()) << ",\n"
      << "  \"integrator\": \"" << sim.stepper().name() << "\",\n"
      << "  \"steps_accepted\": " << n.accepted << ",\n"
      << "  \"steps_rejected\": " << n.rejected << ",\n"
      << "  \"derivative_evaluations\": " << n.derivative_evaluations << ",\n"
      << "  \"last_step_s\": " << num(sim.stepper().lastStep()) << ",\n";
  if (const NewtonCounts* nc = sim.stepper().newtonCounts()) {
    const double steps = std::max<long>(1, n.accepted);
    out << "  \"newton_iterations_per_step\": " << num(nc->iterations / steps) << ",\n"
        << "  \"newton_factorizations_per_step\": " << num(nc->factorizations / steps) << ",\n"
        << "  \"newton_flag_rounds\": " << nc->flag_rounds << ",\n"
        << "  \"newton_line_searches\": " << nc->line_searches << ",\n"
        << "  \"newton_retried_steps\": " << nc->retried_steps << ",\n"
        << "  \"newton_predictor_retries\": " << nc->predictor_retries << ",\n"
        << "  \"newton_return_mapped_solves\": " << nc->return_mapped_solves << ",\n"
        << "  \"newton_strike_windows\": " << nc->strike_windows << ",\n"
        << "  \"newton_fallback_stretches\": " << nc->fallback_stretches << ",\n"
        << "  \"newton_fallback_steps\": " << nc->fallback_steps << ",\n"
        << "  \"newton_fallback_cause\": \"" << nc->fallback_cause << "\",\n";
  }
  // The stretch of the run that ran slowest against real time
  // (pace_profile.hpp); null when run() did not step.
  const PaceStretch& slow = sim.slowestStretch();
  out << "  \"slowest_stretch\": ";
  if (slow.valid) {
    const double steps = std::max<long>(1, slow.steps);
    out << "{\"start_s\": " << num(slow.start_s) << ", \"end_s\": " << num(slow.end_s)
        << ", \"real_time_factor\": " << num(slow.realTimeFactor()) << ", \"steps\": " << slow.steps
        << ", \"retried_steps\": " << slow.rejected
        << ", \"mean_step_s\": " << num((slow.end_s - slow.start_s) / steps)
        << ", \"newton_iterations_per_step\": " << num(slow.iterations / steps)
        << ", \"newton_factorizations_per_step\": " << num(slow.factorizations / steps) << "},\n";
  } else {
    out << "null,\n";
  }
  out << "  \"nodes\": " << sim.model().wirePoints() << ",\n"
      << "  \"segment_length_m\": " << num(sim.model().constants().segment_length) << ",\n"
      << "  \"max_constraint_residual\": " << num(sim.maxConstraintResidual()) << ",\n"
      << "  \"kinetic_energy_J\": " << num(e.kinetic) << ",\n"
      << "  \"elastic_energy_J\": " << num(e.elastic) << ",\n"
      << "  \"dissipated_energy_J\": " << num(e.dissipated()) << ",\n"
      << "  \"plastic_work_J\": " << num(e.plastic) << ",\n"
      << "  \"viscous_dissipation_J\": " << num(e.viscous) << ",\n"
      << "  \"work_done_J\": " << num(e.work_done) << ",\n"
      << "  \"energy_imbalance_J\": " << num(e.imbalance()) << ",\n";
  // A numerically dissipative method's lost energy, as its own term
  // (IntegratorInfo::numerically_dissipative); null for the others.
  const IntegratorInfo* info = findIntegrator(sim.scene().solver.integrator);
  out << "  \"numerical_dissipation_J\": "
      << (info && info->numerically_dissipative ? num(-e.imbalance()) : std::string("null"))
      << ",\n"
      << "  \"max_axial_force_N\": " << num(sim.maxAxialForce()) << ",\n";
  const WireModel& m = sim.model();
  const double radius = m.constants().radius;
  // Accepted steps per turn of the core (null before it turned): how
  // finely a method resolves the process at its speed.
  const double turns = std::abs(sim.coreTurns());
  out << "  \"core_turns\": " << num(sim.coreTurns()) << ",\n"
      << "  \"steps_per_core_revolution\": "
      << (turns > 0.0 ? num(sim.stepper().counts().accepted / turns) : std::string("null")) << ",\n"
      << "  \"fed_length_m\": " << num(m.fedLength()) << ",\n"
      << "  \"supply_tension_N\": " << (m.supply() ? num(m.portAxialForce()) : std::string("null"))
      << ",\n"
      << "  \"max_penetration_ratio\": "
      << (m.contact() ? num(sim.maxPenetration() / radius) : std::string("null")) << ",\n"
      << "  \"carried_points\": " << m.retiredPoints() + m.carriedPoints() << ",\n"
      << "  \"retired_points\": " << m.retiredPoints() << ",\n";
  if (estimate) {
    out << "  \"error_estimate\": {\"refinement\": \"" << estimate->refinement << "\", "
        << "\"scale\": " << num(estimate->scale) << ", "
        << "\"shape_error_rel_diameter\": " << num(estimate->shape_error_rel_diameter) << ", "
        << "\"bulging_error_rel\": "
        << (estimate->bulging_valid ? num(estimate->bulging_error_rel) : std::string("null"))
        << ", \"wall_time_s\": " << num(estimate->wall_s)
        << ", \"refined_wall_time_s\": " << num(estimate->refined_wall_s) << "},\n";
  }
  // Bulging (headlineBulging): null until the scene has a core with contact
  // and wound wire.
  const CoilReport coil = reportCoil(m, sim.scene());
  const BulgeReport b = headlineBulging(m, sim.scene(), &coil);
  if (b.valid) {
    out << "  \"bulging_height_m\": " << num(b.height_m) << ",\n"
        << "  \"build_up_height_m\": " << num(b.build_up_m) << ",\n"
        << "  \"bulging_index\": " << b.index << ",\n"
        << "  \"bulging_arc_length_m\": " << num(b.arc_length_m) << ",\n"
        << "  \"bulging_position_core_m\": [" << num(b.p_core.x()) << ", " << num(b.p_core.y())
        << ", " << num(b.p_core.z()) << "],\n"
        << "  \"wound_points\": " << b.wound_points << ",\n";
  } else {
    out << "  \"bulging_height_m\": null,\n"
        << "  \"build_up_height_m\": null,\n"
        << "  \"bulging_index\": null,\n"
        << "  \"bulging_arc_length_m\": null,\n"
        << "  \"bulging_position_core_m\": null,\n"
        << "  \"wound_points\": 0,\n";
  }
  // The wire's stretch and bend against the enamel's limits, and the
  // window's fill (quality_report.hpp).
  const QualityReport q = reportQuality(m, sim.scene(), coil);
  out << "  \"quality\": {\"plastic_elongation\": " << num(q.plastic_elongation)
      << ", \"plastic_elongation_segment\": " << q.plastic_elongation_segment
      << ", \"cross_section_lost\": " << num(q.cross_section_lost)
      << ", \"bending_strain\": " << num(q.bending_strain)
      << ", \"bending_strain_point\": " << q.bending_strain_point
      << ", \"bending_limit\": " << num(q.bending_limit)
      << ", \"elongation_limit\": " << num(q.elongation_limit) << ", \"turns_past_limits\": [";
  for (std::size_t i = 0; i < q.turns_past_limits.size(); ++i) {
    out << (i ? ", " : "") << q.turns_past_limits[i];
  }
  out << "], \"crossover_per_layer_rad\": [";
  for (std::size_t i = 0; i < q.crossover_per_layer_rad.size(); ++i) {
    const double a = q.crossover_per_layer_rad[i];
    out << (i ? ", " : "") << (std::isnan(a) ? std::string("null") : num(a));
  }
  const auto orNull = [&](double v) { return std::isnan(v) ? std::string("null") : num(v); };
  out << "], \"fill_factor\": " << orNull(q.fill_factor)
      << ", \"tension_peak_N\": " << orNull(q.tension_peak_N)
      << ", \"tension_low_N\": " << orNull(q.tension_low_N)
      << ", \"tension_ripple_max_N\": " << orNull(q.tension_ripple_max_N)
      << ", \"tension_ripple_mean_N\": " << orNull(q.tension_ripple_mean_N)
      << ", \"tension_ripple_per_turn_N\": [";
  for (std::size_t i = 0; i < q.tension_ripple_per_turn_N.size(); ++i) {
    out << (i ? ", " : "") << num(q.tension_ripple_per_turn_N[i]);
  }
  out << "]},\n";
  // Turns, layers, gaps and overlaps (coil_report.hpp): null without a
  // wound coil.
  out << "  \"coil\": ";
  writeCoilJson(coil, out);
  out << "\n}\n";
}

void writeCoilJson(const CoilReport& r, std::ostream& out) {
  if (!r.valid) {
    out << "null";
    return;
  }
  auto list = [&](const std::vector<double>& v) {
    std::string s = "[";
    for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + num(v[i]);
    return s + "]";
  };
  // (turns: the wound wire's turns to a whole one; per_turn lists each,
  // the last one the turn being laid.)
  out << "{\n    \"turns\": " << r.wound_turns() << ",\n"
      << "    \"turns_wound\": " << num(r.turns_wound) << ",\n"
      << "    \"layers\": " << r.layers << ",\n"
      << "    \"gaps\": " << r.gaps << ",\n"
      << "    \"largest_gap_m\": " << num(r.largest_gap_m) << ",\n"
      << "    \"first_gap_turn\": " << r.first_gap_turn << ",\n"
      << "    \"overlaps\": " << r.overlaps << ",\n"
      << "    \"first_overlap_turn\": " << r.first_overlap_turn << ",\n"
      << "    \"bulging_m\": " << num(r.bulging_m) << ",\n"
      << "    \"bulging_per_layer_m\": " << list(r.bulging_per_layer_m) << ",\n"
      << "    \"per_turn\": [";
  for (std::size_t i = 0; i < r.turns.size(); ++i) {
    const TurnReport& t = r.turns[i];
    out << (i ? "," : "") << "\n      {\"turn\": " << t.turn << ", \"layer\": " << t.layer
        << ", \"planned_layers\": [" << t.planned_min << ", " << t.planned_max << "]"
        << ", \"first_point\": " << t.first_point << ", \"points\": " << t.points
        << ", \"axial_m\": " << num(t.axial_m) << ", \"stand_off_m\": " << num(t.stand_off_m)
        << ", \"spacing_m\": " << (std::isnan(t.spacing_m) ? std::string("null") : num(t.spacing_m))
        << ", \"gap_m\": " << num(t.gap_m) << ", \"overlap\": " << (t.overlap ? "true" : "false")
        << "}";
  }
  out << "\n    ]\n  }";
}

void writeWireCsv(const Simulation& sim, std::ostream& out) {
  out << "index,x,y,z,axial_force_N,curvature_1pm,plastic_curvature_1pm,twist_rad_per_m,"
         "in_contact,stick,turn,layer\n";
  out << std::setprecision(12);
  // Turn and layer of the wound wire (0 beyond it, or without a coil).
  const CoilReport coil = reportCoil(sim.model(), sim.scene());
  for (int i = 0; i < sim.model().wirePoints(); ++i) {
    const PointReport r = wirePoint(sim.model(), i);
    const bool wound = i < static_cast<int>(coil.point_turn.size());
    out << i << ',' << r.p_world.x() << ',' << r.p_world.y() << ',' << r.p_world.z() << ','
        << r.axial_force_N << ',' << r.curvature_1pm << ',' << r.plastic_curvature_1pm << ','
        << r.twist_rad_per_m << ',' << int(r.in_contact) << ',' << int(r.stick) << ','
        << (wound ? coil.point_turn[i] : 0) << ',' << (wound ? coil.point_layer[i] : 0) << '\n';
  }
}

void writeShapeCsv(const Simulation& sim, std::ostream& out) {
  const WireModel& m = sim.model();
  out << "index,x_core,y_core,z_core,stand_off_m,in_contact,stick\n" << std::setprecision(12);
  for (int i = 0; i < m.wirePoints(); ++i) {
    const Eigen::Vector3d p = wirePointCore(m, i);
    const PointReport r = wirePoint(m, i);
    out << i << ',' << p.x() << ',' << p.y() << ',' << p.z() << ',' << standOff(m, i) << ','
        << int(r.in_contact) << ',' << int(r.stick) << '\n';
  }
}

void checkOutputDir(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create output directory '" + dir + "': " + ec.message());
  const fs::path probe = fs::path(dir) / ".write_test";
  {
    std::ofstream f(probe);
    if (!f) throw std::runtime_error("output directory '" + dir + "' is not writable");
  }
  fs::remove(probe, ec);
}

void writeOutputs(const Simulation& sim, const std::string& dir, const ErrorEstimate* estimate,
                  const RunStop* stop) {
  checkOutputDir(dir);
  std::ostringstream summary, csv;
  writeSummaryJson(sim, summary, estimate, stop);
  writeWireCsv(sim, csv);
  writeFileAtomically((fs::path(dir) / "wire.csv").string(), csv.str());
  if (sim.model().core() && !sim.scene().core.cylinders.empty()) {
    std::ostringstream shape;
    writeShapeCsv(sim, shape);
    writeFileAtomically((fs::path(dir) / "shape_core.csv").string(), shape.str());
  }
  writeFileAtomically((fs::path(dir) / "summary.json").string(), summary.str());
}

}  // namespace cws
