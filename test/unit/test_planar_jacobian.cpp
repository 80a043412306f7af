// Each effect's analytic Jacobian in the planar implicit formulation against
// central finite differences of its own forces, on states of the paper's
// case wound part of the way: elastic and yielded springs, points sticking,
// slipping and just touching the core, the supply port's constraint.
#include <gtest/gtest.h>

#include <functional>
#include <random>

#include "coil_winding_sim/core/constraints/frame_constraints.hpp"
#include "coil_winding_sim/core/implicit/planar_formulation.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"

#ifdef CWS_SOURCE_DIR
namespace {

const std::string kDefault = std::string(CWS_SOURCE_DIR) + "/config/scenes/default.yaml";

// The Newton matrix entries of one effect (or of the port constraint),
// -(dF/dx + alpha dF/dv), against -(F(x + e) - F(x - e)) / 2e with v =
// alpha (x - x_hat) moving along. `assemble` adds its forces.
void checkEffect(cws::PlanarFormulation& form, const std::string& name,
                 const std::function<void(cws::PlanarAssembly&)>& assemble, int capacity,
                 double& worst_relative) {
  cws::PlanarState& s = form.trialState();
  const int first = s.first, n = s.n;
  cws::PlanarAssembly a, ap, am;
  a.resize(capacity);
  ap.resize(capacity);
  am.resize(capacity);
  a.begin(first, n, true, true, s.alpha);
  assemble(a);
  const int unknowns = 2 * (n - first) + 1;
  Eigen::MatrixXd analytic = Eigen::MatrixXd::Zero(unknowns, unknowns);
  for (int r = 0; r < unknowns; ++r) {
    for (int c = 0; c < unknowns; ++c) {
      if (a.matrix().inBand(r, c)) analytic(r, c) = a.matrix().at(r, c);
    }
  }
  // (Over the points' rows and columns, those compared: a constraint's
  // scaled row would dwarf them.)
  const int points = 2 * (n - first);
  double scale = analytic.topLeftCorner(points, points).cwiseAbs().maxCoeff();
  if (scale == 0.0) return;
  const double eps = 1e-9;  // [m]
  for (int c = 0; c < 2 * (n - first); ++c) {
    const int i = first + c / 2, k = c % 2;
    auto eval = [&](double sign, cws::PlanarAssembly& out) {
      s.x(k, i) += sign * eps;
      s.v(k, i) += sign * s.alpha * eps;
      out.begin(first, n, true, false, s.alpha);
      assemble(out);
      s.x(k, i) -= sign * eps;
      s.v(k, i) -= sign * s.alpha * eps;
    };
    eval(1.0, ap);
    eval(-1.0, am);
    for (int r = 0; r < 2 * (n - first); ++r) {
      const double fd = -(ap.forces()[r] - am.forces()[r]) / (2.0 * eps);
      const double err = std::abs(fd - analytic(r, c)) / scale;
      worst_relative = std::max(worst_relative, err);
      EXPECT_LT(err, 1e-4) << name << " row " << r << " col " << c << ": fd " << fd << " analytic "
                           << analytic(r, c);
    }
  }
}

// A state of the default scene at 1200 rpm after t_s, with the trial
// positions moved by up to `jitter` [m] at random.
void checkAllAt(double t_s, double jitter, unsigned seed,
                const std::vector<std::string>& extra = {}) {
  std::vector<std::string> overrides = {
      "process.core_speed_rpm=1200", "solver.carry_stuck_wire=false",
      "physics.damping=true",        "damping.translational=0.5",
      "damping.rotational=1e-6",     "process.duration=" + std::to_string(t_s)};
  overrides.insert(overrides.end(), extra.begin(), extra.end());
  cws::Scene scene = cws::loadScene(kDefault, overrides);
  cws::Simulation sim(scene);
  sim.run();
  cws::WireModel& model = sim.model();
  cws::PlanarFormulation form(model, scene.solver);
  form.load(sim.time());
  cws::PlanarState& s = form.trialState();
  s.alpha = 1.0 / 1e-4;
  s.lambda_port = 3.0;  // [N]
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  for (int i = s.first; i < s.n; ++i) {
    s.x.col(i) += Eigen::Vector2d(u(rng), u(rng));
    s.v.col(i) += Eigen::Vector2d(u(rng), u(rng)) / 1e-4;
  }
  const int capacity = model.constants().capacity;
  for (cws::ForceEffect* e : model.effectList()) {
    double worst = 0.0;
    if (auto* h = dynamic_cast<cws::EffectHistory*>(e)) h->beginStep(cws::NewtonView(s));
    auto assemble = [&](cws::PlanarAssembly& a) {
      cws::PlanarSink sink(s, a);
      e->addForces(sink);
    };
    checkEffect(form, e->name(), assemble, capacity, worst);
    ::testing::Test::RecordProperty(std::string(e->name()) + "_worst_relative",
                                    std::to_string(worst));
  }
  // The supply's port constraint, lambda_port above.
  double worst = 0.0;
  const double scale = scene.wire.stretch.elastic_rigidity / scene.wire.segment_length;
  auto port = [&](cws::PlanarAssembly& a) {
    cws::addPlanarPortConstraint(s, model.portMotion(s.t), scale, a);
  };
  checkEffect(form, "port constraint", port, capacity, worst);
  ::testing::Test::RecordProperty("port_constraint_worst_relative", std::to_string(worst));
}

}  // namespace

TEST(PlanarJacobian, EveryEffectMatchesFiniteDifferencesWhileWinding) { checkAllAt(0.02, 1e-6, 1); }

TEST(PlanarJacobian, EveryEffectMatchesFiniteDifferencesAtStart) { checkAllAt(1e-4, 1e-6, 2); }

// The contact's dashpots (contact.damping_ratio) add velocity terms to the
// normal force, the stick spring and the kinetic friction's normal force.
TEST(PlanarJacobian, ContactDashpotsMatchFiniteDifferences) {
  checkAllAt(0.02, 1e-6, 3, {"contact.damping_ratio=1.0"});
}

// Elastic slip (contact.friction_law) with the dashpots: slip where the
// jitter carries the stick spring's trial force out of the cone (2e6 N/m),
// stick where it stays inside (2e4 N/m).
TEST(PlanarJacobian, ElasticSlipMatchesFiniteDifferences) {
  for (const char* k_t : {"2.0e6", "2.0e4"}) {
    checkAllAt(0.02, 1e-6, 3,
               {"contact.damping_ratio=1.0", "contact.friction_law=elastic_slip",
                std::string("contact.stick_stiffness=") + k_t});
  }
}
#endif
