#include "coil_winding_sim/core/wire_model.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "coil_winding_sim/core/external_forces/damping.hpp"
#include "coil_winding_sim/core/external_forces/end_load.hpp"
#include "coil_winding_sim/core/external_forces/gravity.hpp"

namespace cws {

namespace {
WireConstants constantsOf(const Scene& s) {
  WireConstants c;
  const int segments = s.segmentCount();
  c.n = segments + 1;
  c.segment_length = s.naturalSegmentLength();
  c.line_density = s.wire.line_density;
  c.radius = 0.5 * s.wire.diameter;
  // Eq. (1): M = rho L / n.
  c.point_mass = s.wire.line_density * s.wire.length / c.n;
  c.point_inertia = 0.4 * c.point_mass * c.radius * c.radius;
  c.point_length = c.point_mass / c.line_density;
  return c;
}
}  // namespace

WireModel::WireModel(const Scene& s)
    : c_(constantsOf(s)),
      clamp_in_core_(s.start.frame == "core"),
      constraints_(c_, s.solver.baumgarte_nu) {
  // The core exists only for scenes that touch it or hold the wire on it.
  if (s.physics.contact || clamp_in_core_) {
    const double omega_cmd = s.process.core_speed_rpm * 2.0 * M_PI / 60.0;
    core_ =
        std::make_unique<RotatingCore>(s.core, s.core.start_at_speed ? omega_cmd : 0.0, omega_cmd);
  }
  const bool plastic = s.physics.plasticity;
  stretching_ = std::make_unique<Stretching>(c_, s.wire.stretch, plastic);
  bending_ = std::make_unique<Bending>(c_, s.wire.bend, plastic);
  all_ = {stretching_.get(), bending_.get()};
  if (s.physics.torsion) {
    twisting_ = std::make_unique<Twisting>(c_, s.wire.torsion, plastic);
    all_.push_back(twisting_.get());
  }
  if (s.physics.gravity) {
    external_.push_back(std::make_unique<Gravity>(c_, s.gravity.acceleration_world));
  }
  if (s.physics.damping) external_.push_back(std::make_unique<Damping>(c_, s.damping));
  if (s.physics.contact) {
    auto contact = std::make_unique<Contact>(c_, s, *core_);
    contact_ = contact.get();
    external_.push_back(std::move(contact));
  }
  external_.push_back(std::make_unique<EndLoad>(c_, s.end.load));
  for (auto& e : external_) all_.push_back(e.get());

  // Straight wire along the clamp direction, all frames equal to the clamp's,
  // at rest (a clamp on a turning core starts the wire with its motion).
  const int m = c_.n - 1;
  p0_ = s.start.position;
  q0_ = quat::fromZetaDirection(s.start.direction);
  Eigen::Vector3d p0_world, v0_world, a0_world;
  Eigen::Vector4d q0_world;
  clamp(0.0, p0_world, v0_world, a0_world, q0_world);
  const Eigen::Vector3d dir = quat::zeta(q0_world);
  y0_.setZero(14 * m + 2);
  for (int i = 1; i < c_.n; ++i) {
    y0_.segment<3>(3 * (i - 1)) = p0_world + i * c_.segment_length * dir;
    y0_.segment<4>(3 * m + 4 * (i - 1)) = q0_world;
  }

  // Tolerances: positions atol [m]; quaternions atol / l (the same
  // displacement over one segment); rates those divided by max_step (the
  // error that would move a point by atol within the largest step).
  const double inf = std::numeric_limits<double>::infinity();
  atol_.resize(y0_.size());
  atol_.segment(0, 3 * m).setConstant(s.solver.atol);
  atol_.segment(3 * m, 4 * m).setConstant(s.solver.atol / c_.segment_length);
  atol_.segment(7 * m, 3 * m).setConstant(s.solver.atol / s.solver.max_step);
  atol_.segment(10 * m, 4 * m).setConstant(s.solver.atol / c_.segment_length / s.solver.max_step);
  atol_.tail(2).setConstant(inf);
  // rtol scales everything but positions, whose size depends on the origin.
  rweight_.setOnes(y0_.size());
  rweight_.segment(0, 3 * m).setZero();

  kin_.resize(c_.n);
  committed_.resize(c_.n);
  forces_.resize(c_.n);
  acc_.resize(3, c_.n);
  qdd_.resize(4, c_.n);
  unpack(0.0, y0_, committed_);
}

void WireModel::clamp(double t, Eigen::Vector3d& p0_world, Eigen::Vector3d& v0_world,
                      Eigen::Vector3d& a0_world, Eigen::Vector4d& q0) const {
  if (!clamp_in_core_) {
    p0_world = p0_;
    v0_world.setZero();
    a0_world.setZero();
    q0 = q0_;
    return;
  }
  // Held on the turning core: the clamp moves with the core material.
  p0_world = core_->pointWorld(t, p0_);
  v0_world = core_->velocityWorld(t, p0_world);
  a0_world = core_->accelerationWorld(t, p0_world);
  const Eigen::Quaterniond qc(q0_[0], q0_[1], q0_[2], q0_[3]);
  const Eigen::Quaterniond qw = core_->quaternionWorldCore(t) * qc;
  q0 = {qw.w(), qw.x(), qw.y(), qw.z()};
}

Eigen::Vector3d WireModel::unpack(double t, const Eigen::VectorXd& y, WireKinematics& k) const {
  const int m = c_.n - 1;
  Eigen::Vector3d p0, v0, a0;
  Eigen::Vector4d q0;
  clamp(t, p0, v0, a0, q0);
  k.p_world.col(0) = p0;
  k.v_world.col(0) = v0;
  k.q.col(0) = q0;
  k.qd.col(0).setZero();  // frame 0 enters only the joint-0 spring, by position
  k.p_world.rightCols(m) = Eigen::Map<const Eigen::Matrix3Xd>(y.data(), 3, m);
  k.q.rightCols(m) = Eigen::Map<const Eigen::Matrix4Xd>(y.data() + 3 * m, 4, m);
  k.v_world.rightCols(m) = Eigen::Map<const Eigen::Matrix3Xd>(y.data() + 7 * m, 3, m);
  k.qd.rightCols(m) = Eigen::Map<const Eigen::Matrix4Xd>(y.data() + 10 * m, 4, m);
  return a0;
}

void WireModel::derivative(double t, const Eigen::VectorXd& y, Eigen::VectorXd& dydt) {
  const int m = c_.n - 1;
  const Eigen::Vector3d a0_world = unpack(t, y, kin_);
  forces_.setZero();
  for (const ForceEffect* e : all_) e->addForces(t, kin_, forces_);
  constraints_.accelerations(kin_, forces_, a0_world, Eigen::Vector4d::Zero(), acc_, qdd_);
  dydt.segment(0, 7 * m) = y.segment(7 * m, 7 * m);
  Eigen::Map<Eigen::Matrix3Xd>(dydt.data() + 7 * m, 3, m) = acc_.rightCols(m);
  Eigen::Map<Eigen::Matrix4Xd>(dydt.data() + 10 * m, 4, m) = qdd_.rightCols(m);
  dydt[14 * m] = forces_.power_external;
  dydt[14 * m + 1] = forces_.power_dissipated;
}

void WireModel::acceptStep(double t, const Eigen::VectorXd& y) {
  unpack(t, y, committed_);
  for (ForceEffect* e : all_) e->commit(t, committed_);
  if (core_) core_->commit(t);
}

EnergyReport WireModel::energy(const Eigen::VectorXd& y) const {
  const int m = c_.n - 1;
  EnergyReport r;
  const WireKinematics& k = committed_;
  for (int i = 1; i < c_.n; ++i) {
    r.kinetic += 0.5 * c_.point_mass * k.v_world.col(i).squaredNorm() +
                 2.0 * c_.point_inertia * k.qd.col(i).squaredNorm();
  }
  for (const ForceEffect* e : all_) {
    r.elastic += e->elasticEnergy(k);
    r.plastic += e->plasticWork(k);
  }
  r.work_done = y[14 * m];
  r.viscous = y[14 * m + 1];
  return r;
}

double WireModel::axialForce(int j) const { return stretching_->axialForce(committed_, j); }

PointReport WireModel::point(int i) const {
  PointReport r;
  const WireKinematics& k = committed_;
  r.p_world = k.p_world.col(i);
  r.axial_force_N = axialForce(i == 0 ? 0 : i - 1);
  if (contact_) {
    r.in_contact = contact_->inContact(i);
    r.stick = contact_->stuck(i);
  }
  if (i + 1 < c_.n) {
    const Eigen::Vector3d omega = bending_->darboux(k, i);
    r.curvature_1pm = omega.head<2>().norm();
    r.plastic_curvature_1pm =
        Eigen::Vector2d(bending_->plasticValue(i, 0), bending_->plasticValue(i, 1)).norm();
    r.twist_rad_per_m = omega[2];
  }
  return r;
}

std::vector<double> WireModel::history() const {
  std::vector<double> h;
  for (const ForceEffect* e : all_) e->appendHistory(h);
  return h;
}

std::vector<const ForceEffect*> WireModel::effects() const {
  return std::vector<const ForceEffect*>(all_.begin(), all_.end());
}

}  // namespace cws
