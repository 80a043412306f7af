#include "coil_winding_sim/core/model/wire_model.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "coil_winding_sim/core/external_forces/damping.hpp"
#include "coil_winding_sim/core/external_forces/free_wire_contact.hpp"

namespace cws {

namespace {
bool needsCore(const Scene& s) {
  return s.physics.contact || s.physics.supply || s.start.frame == "core";
}

double coreSpeedCommand(const Scene& s) { return rpmToRadPerSec(s.process.core_speed_rpm); }

// Clamp position at t = 0 in the world frame.
Eigen::Vector3d clampStartWorld(const Scene& s) {
  if (s.start.frame != "core") return s.start.position;
  const RotatingCore core(s.core, 0.0);
  return core.pointWorld(0.0, s.start.position);
}

// Number of points, segment length, masses and storage of the wire.
WireConstants constantsOf(const Scene& s) {
  WireConstants c;
  c.line_density = s.wire.line_density;
  c.radius = 0.5 * s.wire.diameter;
  // Point counts and storage come from the scene, which validated them.
  c.n = static_cast<int>(s.initialPoints());
  c.capacity = static_cast<int>(s.pointCapacity());
  c.segment_length = s.modelSegmentLength();
  if (!s.physics.supply) {
    // A wire of fixed length: eq. (1), M = rho L / n.
    c.point_mass = s.wire.line_density * s.wire.length / c.n;
  } else {
    // A drawn-in wire: straight from the clamp towards the port, segments of
    // exactly segment_length, the last point within one segment of the port;
    // every point (new ones too) carries rho l, eq. (1) for n -> infinity.
    c.point_mass = s.wire.line_density * c.segment_length;
  }
  c.point_inertia = 0.4 * c.point_mass * c.radius * c.radius;
  c.point_length = c.point_mass / c.line_density;
  return c;
}
}  // namespace

WireModel::WireModel(const Scene& s)
    : c_(constantsOf(s)),
      clamp_in_core_(s.start.frame == "core"),
      constraints_(c_, s.solver.baumgarte_nu,
                   s.physics.planar ? Eigen::Vector3d(s.core.axis_world.normalized())
                                    : Eigen::Vector3d::Zero()),
      // Wire can be carried only where friction holds it on a core that also
      // holds the fixed end; elsewhere the option has no effect.
      carry_(s.carriesWoundWire()),
      carried_(c_.capacity, carry_) {
  // The core exists only for scenes that touch it, draw wire onto it or hold
  // the wire on it.
  if (needsCore(s)) {
    const double omega_cmd = coreSpeedCommand(s);
    core_ = std::make_unique<RotatingCore>(s.core, omega_cmd);
  }
  if (s.physics.planar) planar_normal_world_ = s.core.axis_world.normalized();
  // Carried wire kept live behind the integrated wire: two layers of turns
  // and four more (a new turn lies on the layer below it, and at a flange or
  // a stalled traverse on the turns just wound), at least eight turns.
  const double pitch = std::abs(s.process.traverse_pitch);
  const double turns_per_layer = pitch > 0.0 ? s.process.winding_width / pitch : 0.0;
  keep_turns_ = std::max(8.0, 2.0 * turns_per_layer + 4.0);
  if (core_ && !(s.core.cylinders.empty() && s.core.faces.empty())) {
    section_ = std::make_unique<CoreSection>(s.core);
  }

  // The retired wire's records for the job's whole wire, reserved (only
  // written pages take memory): a job with an end never grows the store
  // within a step; a cell that runs until stopped grows it by doubling.
  if (carry_) {
    retired_reserve_ =
        static_cast<int>(std::clamp(s.wirePointsEstimate() - c_.capacity, 0.0, kMaxWirePoints));
    retired_.reserve(retired_reserve_);
  }
  effects_ = makeEffects(s, EffectContext{c_, core_.get(), &carried_.positionsCore()});
  all_ = effects_.list();
  stretching_ = effects_.find<Stretching>();
  bending_ = effects_.find<Bending>();
  twisting_ = effects_.find<Twisting>();
  damping_ = effects_.find<Damping>();
  contact_ = effects_.find<Contact>();
  free_wire_contact_ = effects_.find<FreeWireContact>();
  supply_ = effects_.find<Supply>();

  // Straight wire, at rest, all frames equal: along the clamp direction, or
  // with a supply from the clamp towards the port.
  p0_ = s.start.position;
  Eigen::Vector3d dir_world = s.start.direction;
  if (supply_) {
    dir_world = s.supply.port_position_world - clampStartWorld(s);
    q0_ = quat::fromZetaDirection(
        clamp_in_core_ ? Eigen::Vector3d(core_->rotationWorldCore(0.0).transpose() * dir_world)
                       : dir_world);
  } else {
    q0_ = quat::fromZetaDirection(s.start.direction);
  }
  p0_start_ = p0_;
  q0_start_ = q0_;
  Eigen::Vector3d p0_world, v0_world, a0_world;
  Eigen::Vector4d q0_world, qd0_world;
  clamp(0.0, p0_world, v0_world, a0_world, q0_world, qd0_world);
  // With a supply the wire starts stretched to the supply tension, in
  // equilibrium with it (segments of the boundary length).
  const Eigen::Vector3d dir = quat::zeta(q0_world);
  const double spacing = supply_ ? supply_->boundaryLength() : c_.segment_length;
  y0_.setZero(capacity());
  for (int i = 1; i < c_.n; ++i) {
    y0_.segment<3>(stateOffset(i)) = p0_world + i * spacing * dir;
    y0_.segment<4>(stateOffset(i) + 3) = q0_world;
  }

  // Tolerances: positions atol [m]; quaternions atol / l (the same
  // displacement over one segment); rates those divided by max_step (the
  // error that would move a point by atol within the largest step). rtol
  // scales everything but positions, whose size depends on the origin.
  const double inf = std::numeric_limits<double>::infinity();
  const double atol = s.solver.atol, l = c_.segment_length, h = s.solver.max_step;
  atol_.resize(capacity());
  rweight_.setOnes(capacity());
  atol_.head(kAuxStates).setConstant(inf);
  for (int i = 1; i < c_.capacity; ++i) {
    const int o = stateOffset(i);
    atol_.segment<3>(o).setConstant(atol);
    atol_.segment<4>(o + 3).setConstant(atol / l);
    atol_.segment<3>(o + 7).setConstant(atol / h);
    atol_.segment<4>(o + 10).setConstant(atol / l / h);
    rweight_.segment<3>(o).setZero();
  }

  kin_.resize(c_.capacity);
  committed_.resize(c_.capacity);
  forces_.resize(c_.capacity);
  acc_.resize(3, c_.capacity);
  qdd_.resize(4, c_.capacity);
  unpack(0.0, y0_, committed_);
  newton_setup_.planar = s.physics.planar;
  newton_setup_.port = s.physics.supply;
  newton_setup_.elastic_rigidity = s.wire.stretch.elastic_rigidity;
  newton_setup_.core_axis_world = s.core.axis_world;
  if (supply_) {
    // The stretched start is work done on the wire before t = 0.
    for (int j = 0; j + 1 < c_.n; ++j) {
      y0_[0] += stretching_->virginWork(stretching_->strain(committed_, j));
    }
    stretching_->preload(committed_);
    port_distance0_ = portDistance(0.0, committed_);
  }
}

void WireModel::clamp(double t, Eigen::Vector3d& p0_world, Eigen::Vector3d& v0_world,
                      Eigen::Vector3d& a0_world, Eigen::Vector4d& q0, Eigen::Vector4d& qd0) const {
  if (!clamp_in_core_) {
    p0_world = p0_;
    v0_world.setZero();
    a0_world.setZero();
    q0 = q0_;
    qd0.setZero();
    return;
  }
  // Held on the turning core: the clamp moves with the core material.
  p0_world = core_->pointWorld(t, p0_);
  v0_world = core_->velocityWorld(t, p0_world);
  a0_world = core_->accelerationWorld(t, p0_world);
  const Eigen::Quaterniond qc(q0_[0], q0_[1], q0_[2], q0_[3]);
  const Eigen::Quaterniond qw = core_->quaternionWorldCore(t) * qc;
  q0 = {qw.w(), qw.x(), qw.y(), qw.z()};
  // qdot = 1/2 (0, omega_world) * q.
  const Eigen::Vector3d w = 0.5 * core_->omega(t) * core_->axisWorld();
  const Eigen::Quaterniond qdw = Eigen::Quaterniond(0.0, w.x(), w.y(), w.z()) * qw;
  qd0 = {qdw.w(), qdw.x(), qdw.y(), qdw.z()};
}

void WireModel::prescribedPose(double t, Eigen::Vector3d& p_world, Eigen::Vector3d& v_world,
                               Eigen::Vector4d& q, Eigen::Vector4d& qd) const {
  const int i = c_.first - 1;
  if (i == 0) {
    Eigen::Vector3d a_world;
    clamp(t, p_world, v_world, a_world, q, qd);
    return;
  }
  // A carried point: its pose in the core frame, turned with the core.
  const Eigen::Vector3d w = core_->omega(t) * core_->axisWorld();
  const Eigen::Vector4d& q_core = carried_.orientationCore(i);
  p_world = core_->pointWorld(t, carried_.positionCore(i));
  v_world = w.cross(p_world - core_->originWorld());
  const Eigen::Quaterniond qc(q_core[0], q_core[1], q_core[2], q_core[3]);
  const Eigen::Quaterniond qw = core_->quaternionWorldCore(t) * qc;
  q = {qw.w(), qw.x(), qw.y(), qw.z()};
  qd = 0.5 * quat::E(q).transpose() * w;
}

Eigen::Vector3d WireModel::unpack(double t, ConstRef y, WireKinematics& k, int from) const {
  Eigen::Vector3d p0, v0, a0;
  Eigen::Vector4d q0, qd0;
  clamp(t, p0, v0, a0, q0, qd0);
  k.p_world.col(0) = p0;
  k.v_world.col(0) = v0;
  k.q.col(0) = q0;
  k.qd.col(0) = qd0;
  for (int i = std::max(from, 1); i < c_.n; ++i) {
    const int o = stateOffset(i);
    k.p_world.col(i) = y.segment<3>(o);
    k.q.col(i) = y.segment<4>(o + 3);
    k.v_world.col(i) = y.segment<3>(o + 7);
    k.qd.col(i) = y.segment<4>(o + 10);
  }
  return a0;
}

void WireModel::derivative(double t, ConstRef y, Ref dydt) {
  const Eigen::Vector3d a0_world = unpack(t, y, kin_);
  // Carried points (1..f-1) turn rigidly with the core: their accelerations
  // and quaternion second derivatives, qdd = 1/2 E(qd)^T w + 1/2 E(q)^T w',
  // and the power the core spends on their motion.
  const int f = c_.first, boundary = f - 1;
  Eigen::Vector3d a_boundary = a0_world;
  Eigen::Vector4d qdd_boundary = Eigen::Vector4d::Zero();
  double carried_power = 0.0;
  if (f > 1) {
    const Eigen::Vector3d w = core_->omega(t) * core_->axisWorld();
    const Eigen::Vector3d w_dot = core_->angularAcceleration(t) * core_->axisWorld();
    for (int i = 1; i < f; ++i) {
      acc_.col(i) = core_->accelerationWorld(t, kin_.p_world.col(i));
      qdd_.col(i) = 0.5 * (quat::E(kin_.qd.col(i)).transpose() * w +
                           quat::E(kin_.q.col(i)).transpose() * w_dot);
      carried_power += c_.point_mass * acc_.col(i).dot(kin_.v_world.col(i)) +
                       4.0 * c_.point_inertia * qdd_.col(i).dot(kin_.qd.col(i));
    }
    a_boundary = acc_.col(boundary);
    qdd_boundary = qdd_.col(boundary);
  }
  // Forces on the integrated points and the prescribed one before them.
  forces_.setZero(boundary, c_.n - boundary);
  ExplicitSink sink(t, c_, kin_, forces_);
  for (const ForceEffect* e : all_) e->addForces(sink);
  PortMotion port;
  if (supply_) port = supply_->port(t);
  constraints_.accelerations(kin_, forces_, a_boundary, qdd_boundary, supply_ ? &port : nullptr,
                             acc_, qdd_);
  // The clamp, or the carried wire, works on the integrated wire through the
  // prescribed point and its frame: minus the power of the wire's forces on
  // them.
  const double clamp_power = -(forces_.f_world.col(boundary) + constraints_.forceOnBoundary())
                                  .dot(kin_.v_world.col(boundary)) -
                             forces_.f_q.col(boundary).dot(kin_.qd.col(boundary)) + carried_power;
  // Planar mode: the constraint solve moves points in the plane only; remove
  // what rounding leaves along the normal.
  const Eigen::Vector3d& nrm = planar_normal_world_;
  dydt[0] =
      forces_.workRate(kin_.v_world, kin_.qd, f, c_.n) + clamp_power + constraints_.portPower();
  dydt[1] = forces_.dissipationRate(kin_.v_world, kin_.qd, f, c_.n);
  for (int i = 1; i < c_.n; ++i) {
    const int o = stateOffset(i);
    dydt.segment<7>(o) = y.segment<7>(o + 7);
    Eigen::Vector3d a = acc_.col(i);
    a -= a.dot(nrm) * nrm;
    dydt.segment<3>(o + 7) = a;
    dydt.segment<4>(o + 10) = qdd_.col(i);
  }
}

bool WireModel::semiImplicitUpdate(double h, ConstRef dydt, Ref y) const {
  // Discrete work-energy law of the method: the kinetic energy changes by
  // exactly h f . (v + v_new) / 2 for the forces f of the step's start. Book
  // the applied loads and the friction and damping forces at that mean
  // velocity, i.e. add h f . dv / 2 with dv = h a to the rates at v; at v
  // or v_new alone the balance drifts by O(h) per unit of friction work
  // (docs/MODEL.md, "Other integrators").
  double dw = 0.0, dd = 0.0;
  for (int i = c_.first; i < c_.n; ++i) {
    const int o = stateOffset(i);
    const auto dv = dydt.segment<3>(o + 7);
    const auto dqd = dydt.segment<4>(o + 10);
    dw += forces_.f_work_world.col(i).dot(dv) + forces_.fq_work.col(i).dot(dqd);
    dd -= forces_.f_dissipative_world.col(i).dot(dv) + forces_.fq_dissipative.col(i).dot(dqd);
  }
  y[0] += h * (dydt[0] + 0.5 * h * dw);
  y[1] += h * (dydt[1] + 0.5 * h * dd);
  for (int i = 1; i < c_.n; ++i) {
    const int o = stateOffset(i);
    y.segment<7>(o + 7) += h * dydt.segment<7>(o + 7);  // v, qdot
    y.segment<7>(o) += h * y.segment<7>(o + 7);         // p, q with the new rates
  }
  return true;
}

double WireModel::portDistance(double t, const WireKinematics& k) const {
  const int last = c_.n - 1;
  const Eigen::Vector3d zeta = quat::zeta(k.q.col(last)).normalized();
  return (supply_->port(t).p_world - k.p_world.col(last)).dot(zeta);
}

double WireModel::fedLength() const {
  if (!supply_) return 0.0;
  const double now = portDistance(committed_time_, committed_);
  return points_added_ * c_.segment_length +
         (now - port_distance0_) / (1.0 + supply_->tensionStrain());
}

void WireModel::appendPoint(double t, Eigen::VectorXd& y) {
  // Full storage: buried wire leaves the live arrays, where there is any.
  if (c_.n >= c_.capacity) retireBuriedWire(y);
  if (c_.n >= c_.capacity) {
    std::ostringstream msg;
    msg << "at t = " << t << " s the wire drawn in needs more than " << c_.capacity
        << " live points: raise supply.max_points";
    if (carry_) {
      msg << " (the wound wire more than " << keep_turns_
          << " turns behind the free span retires from them; less than that lies wound)";
    }
    // A wire that has run away is drawn in too: say so rather than blame
    // the storage (the residual bound of docs/STABILITY.md).
    const double residual = constraints_.maxResidual(committed_);
    if (!(residual <= 1.0e-3)) {
      msg << ", unless the run diverged: a segment is " << residual
          << " rad off its frame's tangent (a sound run stays below 1e-3)";
    }
    throw IntegrationError(msg.str());
  }
  // The outer end of the boundary segment passes the port (eq. 21): it
  // becomes a mass point moving with the last one, on the same line.
  const int last = c_.n - 1;
  const Eigen::Vector3d zeta = quat::zeta(committed_.q.col(last)).normalized();
  // It moves as a rigid extension of the last segment, so that the
  // constraints of the new frame and of the port start at rest.
  const int o = stateOffset(last + 1);
  const Eigen::Vector3d arm = supply_->boundaryLength() * zeta;
  const Eigen::Vector3d omega_world =
      2.0 * quat::E(committed_.q.col(last)) * committed_.qd.col(last);
  const Eigen::Vector3d v = committed_.v_world.col(last) + omega_world.cross(arm);
  const Eigen::Vector4d qd = committed_.qd.col(last);
  y.segment<3>(o) = committed_.p_world.col(last) + arm;
  y.segment<4>(o + 3) = committed_.q.col(last);
  y.segment<3>(o + 7) = v;
  y.segment<4>(o + 10) = qd;
  ++c_.n;
  ++points_added_;
  // (The carried wire's committed poses stay: they need no unpacking.)
  unpack(t, y, committed_, c_.first);
  for (EffectHistory* h : effects_.histories()) h->grow(committed_);
  // The new material brings its kinetic energy and the work that stretched
  // it to the supply tension: both count as work done on the wire.
  y[0] += 0.5 * c_.point_mass * v.squaredNorm() + 2.0 * c_.point_inertia * qd.squaredNorm() +
          stretching_->virginWork(stretching_->strain(committed_, last));
}

void WireModel::removeLastPoint(double t, Eigen::VectorXd& y) {
  const EnergyReport before = energy(y);
  for (EffectHistory* h : effects_.histories()) h->shrink(committed_);
  --c_.n;
  --points_added_;
  unpack(t, y, committed_, c_.first);
  // The wire that leaves takes its kinetic and recoverable energy with it:
  // work done by the wire on the supply (its plastic work stays counted).
  const EnergyReport after = energy(y);
  y[0] -= (before.kinetic - after.kinetic) + (before.elastic - after.elastic);
}

void WireModel::acceptStep(double t, Eigen::VectorXd& y) {
  committed_time_ = t;
  if (carried_deferred_ && c_.first > 1) {
    // The integrated points, and the boundary one on its rigid pose; the
    // rest of the carried wire waits for placeCarriedWire().
    unpack(t, y, committed_, c_.first);
    placeCarried(t, c_.first - 1, y);
    carried_kinematics_placed_ = carried_state_placed_ = c_.first == 2;
  } else {
    unpack(t, y, committed_);
    // Carried points: back onto their exact rigid poses (no drift).
    for (int i = 1; i < c_.first; ++i) placeCarried(t, i, y);
    carried_kinematics_placed_ = carried_state_placed_ = true;
  }
  // The one commit of the effects' history; a Newton step's flags with it.
  const AcceptedStep step{t, committed_, newton_flags_};
  newton_flags_ = false;
  for (EffectHistory* h : effects_.histories()) h->commit(step);
  if (core_) core_->commit(t);
  if (supply_) {
    while (portDistance(t, committed_) > supply_->boundaryLength()) appendPoint(t, y);
    // Wire drawn back out (a tension jump that makes wound wire slip, the
    // core turning backwards): the supply takes it back at its tension, a
    // point at a time as it passes the port. Two integrated points stay.
    while (portDistance(t, committed_) < 0.0 && c_.n - 2 > c_.first) removeLastPoint(t, y);
    // The load cell's reading, and the tensioner on the wire drawn in.
    constexpr double kTwoPi = 6.283185307179586;
    supply_->afterStep(t, fedLength(), portAxialForce(), core_ ? core_->angle(t) / kTwoPi : 0.0);
  }
  if (carry_) updateCarried(t, y);
  committed_.scheme_core = false;  // (the next step sets its own)
}

void WireModel::setCoreSpeed(double omega) {
  if (core_) core_->setCommand(omega);
}

void WireModel::setSupplyTension(double tension) {
  if (supply_) supply_->setTension(tension);
}

void WireModel::setPortCommand(const Eigen::Vector3d& p_world, double t_s) {
  if (!supply_) {
    throw std::invalid_argument(
        "port command: the scene has no supply port (physics.supply false)");
  }
  supply_->commandPort(t_s, p_world, committed_time_);
}

EnergyReport WireModel::energy(const Eigen::VectorXd& y) const {
  placeCarriedWire();
  EnergyReport r;
  const WireKinematics& k = committed_;
  for (int i = 1; i < c_.n; ++i) {
    r.kinetic += 0.5 * c_.point_mass * k.v_world.col(i).squaredNorm() +
                 2.0 * c_.point_inertia * k.qd.col(i).squaredNorm();
  }
  for (const ForceEffect* e : all_) {
    const EffectEnergy held = e->energy(k);
    r.elastic += held.elastic;
    r.plastic += held.plastic;
  }
  // Retired wire: turning rigidly with the core, its deformation fixed.
  if (c_.retired > 0) {
    const double w = core_->omega(committed_time_);
    r.kinetic += 0.5 * carried_.retiredInertia() * w * w;
    r.elastic += retired_.elastic_J;
    r.plastic += retired_.plastic_J;
  }
  r.work_done = y[0];
  r.viscous = y[1];
  // A dancer and the nozzle are part of the machine the balance holds.
  if (supply_) {
    const MachineEnergy m = supply_->machineEnergy();
    r.kinetic += m.kinetic;
    r.elastic += m.elastic;
    r.viscous += m.dissipated;
    r.work_done += m.work_done;
  }
  return r;
}

double WireModel::axialForce(int j) const { return stretching_->axialForce(committed_, j); }

PointReport WireModel::livePoint(int i) const {
  placeCarriedWire();
  PointReport r;
  const WireKinematics& k = committed_;
  r.p_world = k.p_world.col(i);
  // (Point 0 reports segment 0, or where wire retired, the retired segment
  // ending at it.)
  r.axial_force_N = i > 0 ? axialForce(i - 1) : c_.retired > 0 ? clamp_axial_force_ : axialForce(0);
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

PortMotion WireModel::portMotion(double t) const {
  return supply_ ? supply_->port(t) : PortMotion();
}

std::vector<double> WireModel::history() const {
  std::vector<double> h;
  for (const EffectHistory* e : effects_.histories()) e->appendHistory(h);
  return h;
}

std::vector<const ForceEffect*> WireModel::effects() const {
  return std::vector<const ForceEffect*>(all_.begin(), all_.end());
}

void WireModel::setFriction(double mu_static, double mu_kinetic) {
  if (contact_) contact_->setFriction(mu_static, mu_kinetic);
}

void WireModel::setDamping(const DampingParams& d) {
  if (damping_) damping_->setParams(d);
}

}  // namespace cws
