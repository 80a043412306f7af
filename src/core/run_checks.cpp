#include "coil_winding_sim/core/run_checks.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "coil_winding_sim/core/time_steppers/integrators.hpp"

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

}  // namespace cws
