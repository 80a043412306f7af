#include "coil_winding_sim/core/run/run_checks.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "coil_winding_sim/core/scene/integrators.hpp"

namespace cws {

RunMeasures measureRun(const Simulation& sim) {
  RunMeasures m;
  const EnergyReport e = sim.energy();
  const int n = sim.model().size();
  m.finite = std::isfinite(sim.state().head(n).sum()) && std::isfinite(e.kinetic) &&
             std::isfinite(e.elastic) && std::isfinite(e.dissipated()) &&
             std::isfinite(e.work_done);
  m.energy_scale_J = std::max(std::abs(e.work_done), e.kinetic + e.elastic + e.dissipated());
  m.energy_signed_rel = m.energy_scale_J > 0.0 ? e.imbalance() / m.energy_scale_J : 0.0;
  m.energy_rel = std::abs(m.energy_signed_rel);
  const IntegratorInfo* info = findIntegrator(sim.scene().solver.integrator);
  m.dissipative_method = info && info->numerically_dissipative;
  m.residual = sim.maxConstraintResidual();
  m.penetration_ratio =
      sim.model().contact() ? sim.maxPenetration() / sim.model().constants().radius : 0.0;
  m.steps = sim.stepper().counts().accepted;
  m.rejected = sim.stepper().counts().rejected;
  m.mean_step_s = m.steps > 0 ? sim.time() / static_cast<double>(m.steps) : 0.0;
  return m;
}

std::vector<std::string> stabilityViolations(const RunMeasures& m, const StabilityCriteria& c) {
  std::vector<std::string> out;
  auto add = [&](const char* what, double value, double bound) {
    std::ostringstream s;
    s << what << ' ' << value << " above its bound " << bound;
    out.push_back(s.str());
  };
  if (!m.finite) out.push_back("a non-finite number in the state or the energy");
  // NaN fails each "<=" below and is reported as well.
  if (m.dissipative_method) {
    // Energy lost is the method's numerical dissipation; energy gained is not.
    if (!(m.energy_signed_rel <= c.energy_rel))
      add("energy created by the method (relative)", m.energy_signed_rel, c.energy_rel);
  } else if (!(m.energy_rel <= c.energy_rel)) {
    add("energy imbalance (relative)", m.energy_rel, c.energy_rel);
  }
  if (!(m.residual <= c.residual)) add("constraint residual", m.residual, c.residual);
  if (!(m.penetration_ratio <= c.penetration_ratio)) {
    add("penetration / wire radius", m.penetration_ratio, c.penetration_ratio);
  }
  return out;
}

namespace remedy {

std::string diverged(const Scene& s, double t, double residual, const std::string& method,
                     double step_s) {
  std::ostringstream msg;
  msg << "at t = " << t << " s the wire diverged: a segment is " << residual
      << " rad off its frame's tangent (a sound run stays below 1e-3): " << method
      << " is unstable on this scene at its step of " << step_s << " s (";
  const IntegratorInfo* info = findIntegrator(s.solver.integrator);
  if (info && info->explicit_fixed_step) {
    msg << "validation checks only l / c; a stiffer contact or load needs a smaller step): "
           "lower solver.fixed_step, or use rkf45, which tells an unstable step from a "
           "motion that itself diverges";
  } else if (info && info->newton_steps) {
    // The Newton-step methods hold the frames on their segments exactly:
    // what diverged are the positions.
    msg << "solver.implicit_step = " << s.solver.implicit_step
        << " s): lower solver.implicit_step, or use rkf45";
  } else {
    msg << "solver.rtol = " << s.solver.rtol
        << "): lower solver.rtol, or use another "
           "integrator";
  }
  return msg.str();
}

std::string wireThroughWire(const Scene& s, double t, const char* what, int point,
                            double depth_radii, int segment, const std::string& method) {
  const IntegratorInfo* info = findIntegrator(s.solver.integrator);
  const bool newton = info && info->newton_steps;
  std::ostringstream msg;
  msg << "at t = " << t << " s wire passed into " << what << ": point " << point << " lies "
      << depth_radii << " wire radii deep in segment " << segment
      << " (a sound coil: below 0.1): the step carried it past the contact's penalty "
         "spring with "
      << method << "; " << (newton ? "lower solver.implicit_step" : "use bdf2, or a smaller step");
  return msg.str();
}

std::string overFlange(const Scene& s, double t, int point, int flange, double outside_m,
                       double from_axis_m, double reach_m) {
  const double d = s.wire.diameter;
  const int layers = s.bobbinLayers();
  std::ostringstream msg;
  msg << "at t = " << t << " s wire went over the " << (flange == 0 ? "first" : "second")
      << " flange: point " << point << " lies " << 1e3 * outside_m
      << " mm beyond its face, outside the winding, " << 1e3 * from_axis_m
      << " mm from the core axis (the flanges reach " << 1e3 * reach_m
      << " mm: core.flange_height = " << s.core.flange_height << " m, which holds " << layers
      << (layers == 1 ? " layer" : " layers") << " packed as closely as wire packs)";
  // What laid it there, where the scene shows it.
  const bool narrow =
      s.core.flange_spacing > 0.0 && s.core.flange_spacing < s.process.winding_width;
  const bool close = std::abs(s.process.traverse_pitch) < d;
  if (narrow) {
    msg << "; the traverse's stroke, process.winding_width = " << s.process.winding_width
        << " m, runs past flanges core.flange_spacing = " << s.core.flange_spacing << " m apart";
  }
  if (close) {
    msg << "; process.traverse_pitch = " << s.process.traverse_pitch
        << " m, below the wire diameter " << d << " m, lays each turn partly onto the one before";
  }
  msg << ": raise core.flange_height or wind fewer turns";
  if (narrow) msg << ", set core.flange_spacing to at least process.winding_width";
  if (close) msg << ", or lay turns a wire diameter apart";
  return msg.str();
}

std::string collapsed(const Scene& s, const std::string& method, long steps, double below_s,
                      double ratio, double since_s, double t, double h) {
  std::ostringstream msg;
  msg << method << ": the step size collapsed: " << steps << " steps in a row below " << below_s
      << " s (";
  if (ratio == 1.0) {
    msg << "the explicit stability limit l / c";
  } else {
    msg << ratio << " x the explicit stability limit l / c";
  }
  msg << ") from t = " << since_s << " s to " << t << " s, last " << h
      << " s: the scene is too stiff for " << method << " at solver.rtol = " << s.solver.rtol
      << " (contact or stick/slip switching holds its step); use symplectic_euler";
  return msg.str();
}

// A method that fails inside a core speed ramp shorter than the time a wave
// crosses a segment (an instant speed change: core.start_at_speed's start,
// or core.max_angular_acceleration raised far above a machine's) fails on
// that ramp, whatever its own message says: name it and the remedy.
std::string withinRamp(const Scene& s, const std::string& what, const std::string& method,
                       double t_fail_s, double ramp_end_s, double ramp_acceleration) {
  if (!(ramp_end_s > t_fail_s) || ramp_end_s - t_fail_s >= explicitStepLimit(s)) return what;
  std::ostringstream msg;
  msg << what << ". It began to fail within a core speed ramp of " << ramp_acceleration
      << " rad/s^2 that ends at t = " << ramp_end_s
      << " s, a speed change faster than a wave crosses a segment (core.start_at_speed starts "
         "the core in "
      << RotatingCore::kInstantRamp_s
      << " s; core.max_angular_acceleration sets other ramps): " << method
      << " cannot follow it; use "
      << (method == "rkf45" ? "symplectic_euler" : "symplectic_euler or rkf45")
      << ", or lower core.max_angular_acceleration and set core.start_at_speed: false";
  return msg.str();
}

}  // namespace remedy

}  // namespace cws
