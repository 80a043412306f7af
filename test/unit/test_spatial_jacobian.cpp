// Each effect's analytic Jacobian in the 3-D implicit formulation, and the
// frame constraints', against central finite differences of its own forces,
// on states of the paper's 3-D case wound part of the way: elastic and
// yielded springs (stretch, bend, torsion), points sticking, slipping and
// just touching the core, the supply port's constraint. Every unknown is
// perturbed: positions, the frames' rotations (the quaternion moved along
// its tangent basis dq/dtheta, held at the unperturbed state's as the
// assembly holds it within an evaluation) and the multipliers.
#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "coil_winding_sim/core/constraints/frame_constraints.hpp"
#include "coil_winding_sim/core/external_forces/contact.hpp"
#include "coil_winding_sim/core/implicit/spatial_formulation.hpp"
#include "coil_winding_sim/core/run/simulation.hpp"

#ifdef CWS_SOURCE_DIR
namespace {

const std::string k3d = std::string(CWS_SOURCE_DIR) + "/config/scenes/paper_case_3d.yaml";

// What is checked: one effect, or the constraints (effect null): the
// frames', and the port's at port_motion where given.
// frames_q: the quaternions the frames' tangent bases are taken at.
void assembleOne(const cws::ForceEffect* effect, cws::SpatialState& s, cws::SpatialAssembly& a,
                 bool port, bool jacobian, const Eigen::Matrix4Xd& frames_q,
                 const cws::PortMotion* port_motion) {
  a.setFrames(frames_q, s.first, s.n);
  a.begin(s.first, s.n, port, jacobian, s.alpha);
  if (effect) {
    cws::SpatialSink sink(s, a);
    effect->addForces(sink);
  } else {
    if (port_motion) cws::addSpatialPortConstraint(s, *port_motion, 7.0, a);
    cws::addSpatialFrameConstraints(s, 7.0, a);
  }
  a.finish();
}

// The Newton matrix (d r / d u, r = -F on force rows and F on constraint
// rows) against central differences, column by column.
void checkOne(cws::SpatialState& s, const cws::ForceEffect* effect, int capacity, bool port,
              const char* name, double& worst, const cws::PortMotion* port_motion = nullptr) {
  cws::SpatialAssembly a, ap, am;
  a.resize(capacity);
  ap.resize(capacity);
  am.resize(capacity);
  const Eigen::Matrix4Xd frames_q = s.q;
  assembleOne(effect, s, a, port, true, frames_q, port_motion);
  const int unknowns = a.unknowns();
  Eigen::MatrixXd analytic = Eigen::MatrixXd::Zero(unknowns, unknowns);
  for (int r = 0; r < unknowns; ++r) {
    for (int c = 0; c < unknowns; ++c) {
      if (a.matrix().inBand(r, c)) analytic(r, c) = a.matrix().at(r, c);
    }
  }
  // The block LU relies on it: a point's block couples to its neighbours'
  // only through its first kCoupled unknowns (no multiplier acts on the
  // next point).
  using A = cws::SpatialAssembly;
  for (int r = 0; r < unknowns; ++r) {
    for (int c = 0; c < unknowns; ++c) {
      const int br = r / A::kPerPoint, bc = c / A::kPerPoint;
      const bool coupled =
          br == bc || (br < bc ? r % A::kPerPoint : c % A::kPerPoint) < A::kCoupled;
      if (!coupled) {
        EXPECT_EQ(analytic(r, c), 0.0) << name << " couples row " << r << " col " << c;
      }
    }
  }
  const double global = analytic.cwiseAbs().maxCoeff();
  if (global == 0.0) return;
  // The central difference's round-off, about 2 eps_machine |F| / eps:
  // below it (times 1e4, the tolerance's inverse) a column's entries are
  // not resolved (a follower force alone, whose derivative in p is zero).
  const double forces = a.forces().head(unknowns).cwiseAbs().maxCoeff();
  // Which rows are constraint rows.
  std::vector<bool> constraint(unknowns, false);
  for (int i = s.first; i < s.n; ++i) {
    for (int k = 0; k < A::kMultipliers; ++k) constraint[a.muRow(i) + k] = true;
  }
  if (port) constraint[unknowns - 2] = constraint[unknowns - 1] = true;
  for (int c = 0; c < unknowns; ++c) {
    // The unknown behind column c and its perturbation: one coordinate, or
    // (a frame's rotation) the quaternion along a tangent direction.
    double* u = nullptr;
    double* rate = nullptr;
    int frame = -1;
    Eigen::Vector4d dq = Eigen::Vector4d::Zero();
    double eps = 1e-9;
    if (port && c >= unknowns - 2) {
      u = &s.lambda_port[c - (unknowns - 2)];
      eps = 1e-4;
    } else {
      const int i = s.first + c / A::kPerPoint;
      const int k = c % A::kPerPoint;
      if (k >= A::kMu && k < A::kMu + A::kMultipliers) {
        u = &s.mu(1 + k - A::kMu, i);
        eps = 1e-4;
      } else if (k >= A::kP && k < A::kP + 3) {
        u = &s.p(k - A::kP, i);
        rate = &s.v(k - A::kP, i);
      } else {
        frame = i;
        dq = a.frameBasis(i).col(k - A::kQ);
        eps = 1e-7;
      }
    }
    auto move = [&](double step) {
      if (frame >= 0) {
        s.q.col(frame) += step * dq;
        s.qd.col(frame) += s.alpha * step * dq;
        return;
      }
      *u += step;
      if (rate) *rate += s.alpha * step;
    };
    auto eval = [&](double sign, cws::SpatialAssembly& out) {
      move(sign * eps);
      assembleOne(effect, s, out, port, false, frames_q, port_motion);
      move(-sign * eps);
    };
    eval(1.0, ap);
    eval(-1.0, am);
    Eigen::VectorXd fd(unknowns);
    for (int r = 0; r < unknowns; ++r) {
      const double d = (ap.forces()[r] - am.forces()[r]) / (2.0 * eps);
      fd[r] = constraint[r] ? d : -d;
    }
    const double round_off = 2.0 * std::numeric_limits<double>::epsilon() * forces / eps;
    const double scale = std::max({analytic.col(c).cwiseAbs().maxCoeff(), fd.cwiseAbs().maxCoeff(),
                                   1e-9 * global, 1e4 * round_off});
    for (int r = 0; r < unknowns; ++r) {
      const double err = std::abs(fd[r] - analytic(r, c)) / scale;
      worst = std::max(worst, err);
      EXPECT_LT(err, 1e-4) << name << " row " << r << " col " << c << ": fd " << fd[r]
                           << " analytic " << analytic(r, c);
    }
  }
}

// Points touching the core, stuck among them, and yielded segments and
// joints at the committed state.
struct Coverage {
  int touching = 0, stuck = 0, yielded_segments = 0, yielded_joints = 0;
  int on_wire = 0, on_flange = 0;  // slots beyond the core body
};

// Makes every other stuck point slip: moved 50 um along the core's turning
// direction, its stick spring exceeds mu_s N and the recheck lets it slip
// in that direction; then it is put back.
void slipEveryOther(cws::SpatialState& s, cws::Contact& contact, const cws::RotatingCore& core) {
  Eigen::Matrix3Xd saved = s.p;
  int k = 0;
  for (int i = s.first; i < s.n; ++i) {
    if (contact.trialSurface(i) < 0 || !contact.trialStuck(i) || k++ % 2 != 0) continue;
    const Eigen::Vector3d r = s.p.col(i) - core.originWorld();
    s.p.col(i) += 50e-6 * core.axisWorld().cross(r).normalized();
  }
  contact.recheck(cws::NewtonView(s));
  s.p = saved;
}

Coverage checkAllAt(double t_s, unsigned seed, const std::vector<std::string>& extra = {}) {
  std::vector<std::string> overrides = {"solver.carry_stuck_wire=false", "physics.damping=true",
                                        "damping.translational=0.5", "damping.rotational=1e-6",
                                        "process.duration=" + std::to_string(t_s)};
  overrides.insert(overrides.end(), extra.begin(), extra.end());
  const cws::Scene scene = cws::loadScene(k3d, overrides);
  cws::Simulation sim(scene);
  sim.run();
  cws::WireModel& model = sim.model();
  cws::SpatialFormulation form(model, scene.solver);
  form.load(sim.time());
  cws::SpatialState& s = form.trialState();
  s.alpha = 1.0 / 1e-4;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  s.lambda_port = Eigen::Vector2d(3.0, -2.0);  // [N]
  for (int i = s.first; i < s.n; ++i) {
    s.p.col(i) += 1e-6 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    s.v.col(i) += 1e-2 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    s.q.col(i) += 1e-4 * Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng));
    s.qd.col(i) += 1.0 * Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng));
    s.mu.col(i) = Eigen::Vector3d(u(rng), u(rng), u(rng));
  }
  for (cws::EffectHistory* h : model.historyList()) h->beginStep(cws::NewtonView(s));
  for (cws::ForceEffect* e : model.effectList()) {
    if (auto* contact = dynamic_cast<cws::Contact*>(e)) slipEveryOther(s, *contact, *model.core());
  }
  Coverage cover;
  for (int i = s.first; i < s.n; ++i) {
    if (model.contact() && model.contact()->trialSurface(i) >= 0) {
      ++cover.touching;
      cover.stuck += model.contact()->trialStuck(i);
    }
    for (int slot = 1; model.contact() && slot < model.contact()->slots(); ++slot) {
      const int surface = model.contact()->trialSurface(i, slot);
      if (surface < 0) continue;
      ++(surface >= model.contact()->wireSurface() ? cover.on_wire : cover.on_flange);
    }
    if (i + 1 < s.n && model.stretching().plasticStrain(i) != 0.0) ++cover.yielded_segments;
    if (i + 1 < s.n &&
        (model.bending().plasticValue(i, 0) != 0.0 || model.bending().plasticValue(i, 1) != 0.0)) {
      ++cover.yielded_joints;
    }
  }
  const int capacity = model.constants().capacity;
  const bool port = scene.physics.supply;
  for (cws::ForceEffect* e : model.effectList()) {
    double worst = 0.0;
    checkOne(s, e, capacity, port, e->name(), worst);
    ::testing::Test::RecordProperty(std::string(e->name()) + "_worst_relative",
                                    std::to_string(worst));
  }
  double worst = 0.0;
  const cws::PortMotion port_motion = model.portMotion(s.t);
  checkOne(s, nullptr, capacity, port, "frame and port constraints", worst,
           port ? &port_motion : nullptr);
  ::testing::Test::RecordProperty("frame_constraints_worst_relative", std::to_string(worst));
  return cover;
}

}  // namespace

TEST(SpatialJacobian, EveryEffectMatchesFiniteDifferencesWhileWinding) {
  const Coverage c =
      checkAllAt(0.02, 1, {"process.core_speed_rpm=1200", "contact.friction_law=stick_speed"});
  // The state covers what the laws switch between (stick_speed's stuck
  // points made to slip: slipEveryOther; elastic slip has its own test
  // below).
  EXPECT_GT(c.stuck, 0);
  EXPECT_GT(c.touching - c.stuck, 0) << "no slipping point";
  EXPECT_GT(c.yielded_segments, 0);
  EXPECT_GT(c.yielded_joints, 0);
  std::printf("touching %d, stuck %d, yielded segments %d, joints %d\n", c.touching, c.stuck,
              c.yielded_segments, c.yielded_joints);
}

TEST(SpatialJacobian, EveryEffectMatchesFiniteDifferencesAtStart) { checkAllAt(1e-4, 2); }

// The contact's dashpots (contact.damping_ratio): velocity terms in the
// normal force, stick_speed's stick spring and its kinetic friction.
TEST(SpatialJacobian, ContactDashpotsMatchFiniteDifferences) {
  const Coverage c = checkAllAt(0.03, 4,
                                {"process.core_speed_rpm=1200", "contact.damping_ratio=1.0",
                                 "contact.friction_law=stick_speed"});
  std::printf("touching %d, stuck %d\n", c.touching, c.stuck);
  EXPECT_GT(c.stuck, 0);
  EXPECT_GT(c.touching - c.stuck, 0) << "no slipping point";
}

// Elastic slip (contact.friction_law): the return map's consistent tangent,
// with the dashpots. The states' 1 um jitter puts the stick spring's trial
// force (2e6 N/m) far outside the cone of most points (slip); with a stick
// spring of 2e4 N/m it stays inside (stick).
TEST(SpatialJacobian, ElasticSlipMatchesFiniteDifferences) {
  for (const char* k_t : {"2.0e6", "2.0e4"}) {
    const Coverage c = checkAllAt(
        0.03, 4,
        {"process.core_speed_rpm=1200", "contact.damping_ratio=1.0",
         "contact.friction_law=elastic_slip", std::string("contact.stick_stiffness=") + k_t});
    EXPECT_GT(c.touching, 0);
  }
}

// Flanges and wound wire (physics.flanges, physics.wire_contact): a coil
// whose second turn lies beside the first and whose first layer ends at a
// flange.
TEST(SpatialJacobian, FlangeAndWireContactMatchFiniteDifferences) {
  const Coverage c = checkAllAt(
      0.1, 5,
      {"process.core_speed_rpm=1200", "solver.carry_stuck_wire=true", "solver.integrator=bdf2",
       "process.winding_width=2.2e-3", "physics.flanges=true", "physics.wire_contact=true"});
  std::printf("touching %d, stuck %d, on wound wire %d, on a flange %d\n", c.touching, c.stuck,
              c.on_wire, c.on_flange);
  EXPECT_GT(c.on_wire, 0);
  EXPECT_GT(c.on_flange, 0);
}

TEST(SpatialJacobian, EndLoadWithAMoment) {
  // A wire without supply whose tip carries a force and a moment.
  checkAllAt(1e-3, 3,
             {"physics.supply=false", "physics.contact=false", "physics.friction=false",
              "end.load=[{time: 0.0, force: [0.1, 0.2, 0.3], moment: [1e-3, -2e-3, 3e-3]}]"});
}
#endif
