// Contact with the flanges and with the wound wire the core carries,
// against the penalty law's closed form: the force k h along the normal,
// h the penetration from the geometry (a plane, a capsule of the wire's
// radius), one contact per surface a point touches (a corner, a groove).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "coil_winding_sim/core/assembly/spatial_assembly.hpp"
#include "coil_winding_sim/core/external_forces/contact.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

#ifdef CWS_SOURCE_DIR
namespace {

const std::string k3d = std::string(CWS_SOURCE_DIR) + "/config/scenes/paper_case_3d.yaml";

// A wire of n points at rest, all forces zero.
struct Bench {
  cws::WireConstants c;
  cws::WireKinematics k;
  cws::WireForces f;
  Bench(const cws::Scene& s, int n, int first) {
    c.n = n;
    c.first = first;
    c.capacity = n;
    c.radius = 0.5 * s.wire.diameter;
    c.point_mass = 1e-6;
    c.segment_length = s.wire.segment_length;
    k.resize(n);
    k.p_world.setZero();
    k.v_world.setZero();
    k.q.setZero();
    k.qd.setZero();
    f.resize(n);
  }
  void evaluate(const cws::Contact& contact) {
    f.f_world.setZero();
    f.f_q.setZero();
    cws::ExplicitSink sink(0.0, c, k, f);
    contact.addForces(sink);
  }
};

// The 3-D scene with flanges `width` [m] apart, without friction.
cws::Scene flangeScene(double width) {
  return cws::loadScene(k3d, {"process.winding_width=" + std::to_string(width),
                              "physics.flanges=true", "physics.friction=false"});
}

// The first flange's position along the core axis [m]: half a wire
// diameter behind the port's start (the second lies the winding width
// further on, the pitch being positive).
double firstFlangeAt(const cws::Scene& s) {
  const Eigen::Vector3d axis = s.core.axis_world.normalized();
  return (s.supply.port_position_world - s.core.position_world).dot(axis) - 0.5 * s.wire.diameter;
}

// The core's swept radius [m]: the flanges reach core.flange_height beyond.
double sweptRadius(const cws::Scene& s) {
  double swept = 0.0;
  for (const cws::CylinderParams& cyl : s.core.cylinders) {
    swept = std::max(swept, cyl.center_core.norm() + cyl.radius);
  }
  return swept;
}

// A Newton solve's state of six points: point 1 at p1_world, points 2..5
// far from everything (point 0 is the prescribed one).
cws::SpatialState solveState(const Eigen::Vector3d& p1_world) {
  cws::SpatialState st;
  st.first = 1;
  st.n = 6;
  st.alpha = 1e4;
  st.p.setZero(3, 6);
  for (int i = 2; i < 6; ++i) st.p.col(i) = Eigen::Vector3d(0.0, -50e-3, i * 1e-3);
  st.p.col(1) = p1_world;
  st.v.setZero(3, 6);
  st.q.setZero(4, 6);
  st.qd.setZero(4, 6);
  st.mu.setZero(3, 6);
  return st;
}

// The force [N] contact puts on point 1 with the flags the solve froze.
Eigen::Vector3d frozenForce(const cws::Contact& contact, const cws::SpatialState& st,
                            cws::SpatialAssembly& a) {
  a.begin(st.first, st.n, false, false, st.alpha);
  cws::SpatialSink sink(st, a);
  contact.addForces(sink);
  return a.forces().segment<3>(a.pRow(1));
}

}  // namespace

// The flanges: k h along the normal into the winding, where h = r - the
// distance from the flange, and nothing beyond a wire diameter on the other
// side, between the flanges or beyond their reach from the axis.
TEST(Flanges, PushIntoTheWindingByThePenaltyLaw) {
  const double width = 4e-3;  // [m]
  const cws::Scene s = flangeScene(width);
  const cws::RotatingCore core(s.core, 0.0);
  Bench b(s, 6, 1);
  cws::Contact contact(b.c, s, core);
  const Eigen::Vector3d axis = s.core.axis_world.normalized();
  const double r = b.c.radius;
  const double at0 = firstFlangeAt(s), at1 = at0 + width;
  // Outside the core's cylinders, within the flanges' reach (1 mm beyond
  // the core's swept radius): only the flanges can touch.
  const double swept = sweptRadius(s);
  ASSERT_GT(s.core.flange_height, 1e-3);
  const Eigen::Vector3d far = s.core.position_world + Eigen::Vector3d(swept + 1e-3, 0.0, 0.0);
  auto at = [&](double axial) { return Eigen::Vector3d(far + (axial - far.dot(axis)) * axis); };
  const double h1 = 1e-5, h2 = 2e-5;  // penetrations [m]
  b.k.p_world.col(0) = at(0.5 * (at0 + at1));
  b.k.p_world.col(1) = at(at0 + r - h1);       // into the first flange
  b.k.p_world.col(2) = at(0.5 * (at0 + at1));  // between them
  b.k.p_world.col(3) = at(at1 - r + h2);       // into the second
  b.k.p_world.col(4) = at(at1 + 3.0 * r);      // beyond the second
  b.k.p_world.col(5) = at(at0 - 3.0 * r);      // beyond the first
  b.evaluate(contact);
  const double k = s.contact.stiffness;
  EXPECT_LT((b.f.f_world.col(1) - k * h1 * axis).norm(), 1e-9 * k * h1);
  EXPECT_LT((b.f.f_world.col(3) + k * h2 * axis).norm(), 1e-9 * k * h2);
  EXPECT_EQ(b.f.f_world.col(2).norm(), 0.0);
  EXPECT_EQ(b.f.f_world.col(4).norm(), 0.0);
  EXPECT_EQ(b.f.f_world.col(5).norm(), 0.0);
  // Beyond the flanges' reach from the axis the same depth touches nothing.
  b.k.p_world.col(1) += s.core.flange_height * Eigen::Vector3d::UnitX();
  b.evaluate(contact);
  EXPECT_EQ(b.f.f_world.col(1).norm(), 0.0);
}

// A flange is a thin disc with a rim: beyond its radius R a point is
// pushed off the rim's circle, k (r - |d|) along d / |d| with d from the
// circle's nearest point (in the plane through the axis and the point), so
// the force turns over the edge; within R, off the face it lies on, from
// either side. The normal's derivative against central differences.
TEST(Flanges, PushOffTheRimAndOffEitherFace) {
  const double width = 4e-3;  // [m]
  const cws::Scene s = flangeScene(width);
  const cws::RotatingCore core(s.core, 0.0);
  Bench b(s, 2, 1);
  const cws::Contact contact(b.c, s, core);
  const cws::ContactGeometry& g = contact.geometry();
  g.place(0.0);
  const Eigen::Vector3d axis = s.core.axis_world.normalized();
  const double r = b.c.radius, at0 = firstFlangeAt(s);
  const double rim = sweptRadius(s) + s.core.flange_height;
  // A direction from the axis, at right angles to it.
  const Eigen::Vector3d u =
      (Eigen::Vector3d(1.0, 0.3, 0.0) - Eigen::Vector3d(1.0, 0.3, 0.0).dot(axis) * axis)
          .normalized();
  auto at = [&](double radial, double axial) {
    return Eigen::Vector3d(s.core.position_world + radial * u + axial * axis);
  };
  const int first_flange = g.wireBase() - 2;  // surfaces: cylinders, faces, then the flanges
  double depth;
  Eigen::Vector3d n;
  Eigen::Matrix3d dn;
  // Above the rim by 0.2 mm and 0.1 mm into the winding side: from the
  // circle, |d| = sqrt(0.2^2 + 0.1^2) mm.
  const Eigen::Vector3d p = at(rim + 0.2e-3, at0 + 0.1e-3);
  ASSERT_TRUE(g.spatialSurface(1, first_flange, p, n, depth, &dn));
  const double dist = std::hypot(0.2e-3, 0.1e-3);
  EXPECT_NEAR(depth, r - dist, 1e-12);
  EXPECT_LT((n - (0.2e-3 * u + 0.1e-3 * axis) / dist).norm(), 1e-9);
  // d normal / dp against central differences.
  const double e = 1e-8;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d np, nm;
    double hp, hm;
    ASSERT_TRUE(
        g.spatialSurface(1, first_flange, p + e * Eigen::Vector3d::Unit(k), np, hp, nullptr));
    ASSERT_TRUE(
        g.spatialSurface(1, first_flange, p - e * Eigen::Vector3d::Unit(k), nm, hm, nullptr));
    EXPECT_LT(((np - nm) / (2.0 * e) - dn.col(k)).norm(), 1e-5 * dn.norm()) << "column " << k;
  }
  // touchAll finds the same.
  cws::ContactGeometry::Touch touches[cws::ContactGeometry::kMaxSlots];
  ASSERT_TRUE(g.touchAll(1, p, nullptr, touches));
  EXPECT_EQ(touches[g.flangeSlot()].surface, first_flange);
  EXPECT_NEAR(touches[g.flangeSlot()].h, r - dist, 1e-12);
  // Within the radius, outside the winding 0.2 mm from the face: pushed
  // outwards, r - 0.2 mm deep.
  ASSERT_TRUE(g.spatialSurface(1, first_flange, at(rim - 1e-3, at0 - 0.2e-3), n, depth, &dn));
  EXPECT_NEAR(depth, r - 0.2e-3, 1e-12);
  EXPECT_LT((n + axis).norm(), 1e-12);
  EXPECT_EQ(dn.norm(), 0.0);
  // More than a wire radius beyond the rim: nothing.
  EXPECT_FALSE(g.spatialSurface(1, first_flange, at(rim + 1.01 * r, at0), n, depth, &dn));
}

// How far wire lies outside the winding, beyond a flange's face: the axial
// distance past the nearer face, and its distance from the axis against
// the flanges' reach (swept radius + core.flange_height).
TEST(Flanges, TellHowFarAPointLiesOutsideTheWinding) {
  const double width = 4e-3;  // [m]
  const cws::Scene s = flangeScene(width);
  const cws::RotatingCore core(s.core, 0.0);
  Bench b(s, 2, 1);
  const cws::Contact contact(b.c, s, core);
  const cws::ContactGeometry& g = contact.geometry();
  const Eigen::Vector3d axis = s.core.axis_world.normalized();
  const double at0 = firstFlangeAt(s), at1 = at0 + width;
  const double swept = sweptRadius(s);
  const Eigen::Vector3d far = s.core.position_world + Eigen::Vector3d(swept + 2e-3, 0.0, 0.0);
  auto at = [&](double axial) { return Eigen::Vector3d(far + (axial - far.dot(axis)) * axis); };
  cws::ContactGeometry::FlangeSide side = g.flangeSide(at(at0 - 1.5e-3));
  EXPECT_EQ(side.flange, 0);
  EXPECT_NEAR(side.outside_m, 1.5e-3, 1e-12);
  EXPECT_NEAR(side.from_axis_m, swept + 2e-3, 1e-12);
  EXPECT_NEAR(side.reach_m, swept + s.core.flange_height, 1e-12);
  side = g.flangeSide(at(at1 + 0.7e-3));
  EXPECT_EQ(side.flange, 1);
  EXPECT_NEAR(side.outside_m, 0.7e-3, 1e-12);
  // Between the faces: minus the distance to the nearer one.
  side = g.flangeSide(at(at0 + 1e-3));
  EXPECT_EQ(side.flange, 0);
  EXPECT_NEAR(side.outside_m, -1e-3, 1e-12);
  // Without flanges there is no side.
  const cws::Scene none = cws::loadScene(k3d, {});
  Bench bn(none, 2, 1);
  const cws::Contact plain(bn.c, none, core);
  EXPECT_EQ(plain.geometry().flangeSide(at(at0 - 1.5e-3)).flange, -1);
}

// In a Newton solve the flange a recheck found stays frozen: it pushes k h
// along the axis while the point lies within the flange's reach, and not
// at all once the point is beyond it, where the explicit steps find no
// flange either (a frozen flange pushing as its whole plane moved a point
// beyond the rim, where the recheck then found none, and the flag turned
// at every recheck).
TEST(Flanges, AFrozenFlangeEndsWhereTheFlangeEnds) {
  const cws::Scene s = flangeScene(4e-3);
  const cws::RotatingCore core(s.core, 0.0);
  Bench b(s, 6, 1);
  cws::Contact contact(b.c, s, core);
  const Eigen::Vector3d axis = s.core.axis_world.normalized();
  const double r = b.c.radius, h1 = 1e-5, k = s.contact.stiffness;
  const double at0 = firstFlangeAt(s), swept = sweptRadius(s);
  // Point 1 h1 into the first flange, 1 mm inside its reach; the others
  // far from everything.
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  auto place = [&](double radial) {
    Eigen::Vector3d p = s.core.position_world + radial * x;
    return Eigen::Vector3d(p + (at0 + r - h1 - p.dot(axis)) * axis);
  };
  cws::SpatialState st = solveState(place(swept + s.core.flange_height - 1e-3));
  contact.beginStep(cws::NewtonView(st));
  ASSERT_TRUE(contact.recheck(cws::NewtonView(st)));  // the flange is found
  cws::SpatialAssembly a;
  a.resize(6);
  auto force = [&] { return frozenForce(contact, st, a); };
  EXPECT_LT((force() - k * h1 * axis).norm(), 1e-9 * k * h1);
  // The same depth 1 mm beyond the flange's reach, the flag still frozen.
  st.p.col(1) = place(swept + s.core.flange_height + 1e-3);
  EXPECT_EQ(force().norm(), 0.0);
}

// A point that a Newton solve's recheck finds on a surface, then off it,
// then on it again (grazing a flange: on, its spring pushes the point out;
// off, nothing holds it) keeps the surface for the rest of the step with
// the penalty law clipped, k h where it touches and nothing where it does
// not: a loss is then no change, so the solve ends instead of turning the
// flag at every round down to steps of 1e-8 s (issue 57). A new step
// counts afresh, and the commit takes what the geometry finds.
TEST(Flanges, AGrazingPointKeepsItsSurfaceClippedAfterTwoChangesInAStep) {
  const cws::Scene s = flangeScene(4e-3);
  const cws::RotatingCore core(s.core, 0.0);
  Bench b(s, 6, 1);
  cws::Contact contact(b.c, s, core);
  const Eigen::Vector3d axis = s.core.axis_world.normalized();
  const double r = b.c.radius, h1 = 1e-5;
  const double at0 = firstFlangeAt(s), swept = sweptRadius(s);
  // Point 1 `depth` [m] into the first flange, 1 mm inside its reach.
  auto place = [&](double depth) {
    Eigen::Vector3d p = s.core.position_world + (swept + 1e-3) * Eigen::Vector3d::UnitX();
    return Eigen::Vector3d(p + (at0 + r - depth - p.dot(axis)) * axis);
  };
  cws::SpatialState st = solveState(place(-h1));  // the step starts off the flange
  contact.beginStep(cws::NewtonView(st));
  st.p.col(1) = place(h1);
  EXPECT_TRUE(contact.recheck(cws::NewtonView(st)));  // found
  st.p.col(1) = place(-h1);
  EXPECT_TRUE(contact.recheck(cws::NewtonView(st)));  // lost
  st.p.col(1) = place(h1);
  EXPECT_TRUE(contact.recheck(cws::NewtonView(st)));  // found again: clipped from now on
  st.p.col(1) = place(-h1);
  EXPECT_FALSE(contact.recheck(cws::NewtonView(st)));  // lost: no change
  // The clipped law: k h1 into the flange, nothing off it.
  cws::SpatialAssembly a;
  a.resize(6);
  auto force = [&] { return frozenForce(contact, st, a); };
  EXPECT_EQ(force().norm(), 0.0);
  st.p.col(1) = place(h1);
  EXPECT_LT((force() - s.contact.stiffness * h1 * axis).norm(), 1e-9 * s.contact.stiffness * h1);
  // The step's end as the geometry finds it: off the flange.
  st.p.col(1) = place(-h1);
  for (int i = 1; i < 6; ++i) b.k.p_world.col(i) = st.p.col(i);
  contact.commit({0.0, b.k, false});
  EXPECT_LT(contact.surface(1, 1), 0);
  // The next step rechecks afresh: a change is reported again.
  contact.beginStep(cws::NewtonView(st));
  st.p.col(1) = place(h1);
  EXPECT_TRUE(contact.recheck(cws::NewtonView(st)));
}

// A point in the corner of a cylinder and a flange feels both: the sum of
// the two penalty forces, each along its own normal.
TEST(Flanges, ACornerPointFeelsTheCoreAndTheFlange) {
  const cws::Scene s = flangeScene(4e-3);
  const cws::RotatingCore core(s.core, 0.0);
  Bench b(s, 2, 1);
  cws::Contact contact(b.c, s, core);
  const double r = b.c.radius;
  const Eigen::Vector3d axis = s.core.axis_world.normalized();
  const double at0 = firstFlangeAt(s);
  // Over the first cylinder's outermost line (+x), h_c into the cylinder
  // and h_f into the flange.
  const cws::CylinderParams& cyl = s.core.cylinders[0];
  const Eigen::Vector3d out(1.0, 0.0, 0.0);
  const double h_c = 3e-6, h_f = 7e-6;
  const Eigen::Vector3d radial =
      Eigen::Vector3d(cyl.center_core.x(), cyl.center_core.y(), 0.0) + (cyl.radius + r - h_c) * out;
  b.k.p_world.col(1) = radial + (at0 + r - h_f) * axis;
  b.evaluate(contact);
  const double k = s.contact.stiffness;
  const Eigen::Vector3d expected = k * h_c * out + k * h_f * axis;
  EXPECT_LT((b.f.f_world.col(1) - expected).norm(), 1e-9 * expected.norm());
  // Both are held at a commit, each in its own slot.
  contact.commit({0.0, b.k, false});
  EXPECT_EQ(contact.surface(1, 0), 0);
  EXPECT_GE(contact.surface(1, 1), 0);
  EXPECT_NEAR(contact.penetration(1, 0), h_c, 1e-15);
  EXPECT_NEAR(contact.penetration(1, 1), h_f, 1e-15);
}

namespace {

// Carried wire in two runs along x, 30 mm off the core's axis (out of the
// core's reach): points 1..11 at z = 0, then one segment up to z = d, and
// points 12..22 back at z = d. The free wire starts at point 23.
struct TwoRuns {
  cws::Scene s;
  std::vector<Eigen::Vector3d> carried_core;
  double y0 = 30e-3, d = 0.0;
  explicit TwoRuns(const cws::Scene& scene) : s(scene), carried_core(40), d(scene.wire.diameter) {
    for (int j = 1; j <= 11; ++j) carried_core[j] = Eigen::Vector3d((j - 1) * 1e-3, y0, 0.0);
    for (int j = 12; j <= 22; ++j) carried_core[j] = Eigen::Vector3d((22 - j) * 1e-3, y0, d);
  }
};

// The 3-D scene with contact against carried wire (which needs friction),
// under the law whose fresh contact holds no friction force: the forces
// these tests check are the normal law's alone. (Under elastic slip a
// point that touches is tied to where it was at the last commit, and this
// bench has none.)
cws::Scene wireContactScene() {
  return cws::loadScene(k3d, {"physics.wire_contact=true", "contact.friction_law=stick_speed"});
}

}  // namespace

// Wires crossing at a right angle: a free point pressed onto a carried
// segment feels k h along the line joining the two wire axes, h = d - that
// distance; past a carried wire's end, the end point's sphere; nothing
// from its neighbours along its own wire.
TEST(WireContact, CrossingWiresFollowThePenaltyLaw) {
  const cws::Scene s = wireContactScene();
  const cws::RotatingCore core(s.core, 0.0);
  TwoRuns wire(s);
  Bench b(s, 40, 23);
  cws::Contact contact(b.c, s, core);
  contact.attachCarriedWire(wire.carried_core);
  const double d = wire.d, k = s.contact.stiffness;
  const double h1 = 2e-5, h2 = 1e-5;  // [m]
  // Point 30 crosses the first run (along x at z = 0) from below, along z:
  // over the inside of segment 7.
  b.k.p_world.col(30) = Eigen::Vector3d(7.5e-3, wire.y0 - (d - h1), 0.0);
  // Point 31 beyond the first point of the carried wire, along -x.
  b.k.p_world.col(31) = Eigen::Vector3d(-(d - h2), wire.y0, 0.0);
  // Point 23, the first free point, right beside the last carried one.
  b.k.p_world.col(23) = wire.carried_core[22] + Eigen::Vector3d(0.0, -0.9e-3, 0.0);
  // The others far away.
  for (int i = 24; i < 40; ++i) {
    if (i != 30 && i != 31) b.k.p_world.col(i) = Eigen::Vector3d(0.0, -50e-3, i * 1e-3);
  }
  b.evaluate(contact);
  EXPECT_LT((b.f.f_world.col(30) - Eigen::Vector3d(0.0, -k * h1, 0.0)).norm(), 1e-9 * k * h1);
  // Point 31 also lies under the second run's end (z = d): d away from it,
  // on the edge of touching: only the first run's end pushes.
  EXPECT_LT((b.f.f_world.col(31) - Eigen::Vector3d(-k * h2, 0.0, 0.0)).norm(), 1e-6 * k * h2);
  EXPECT_EQ(b.f.f_world.col(23).norm(), 0.0);
  for (int i = 24; i < 40; ++i) {
    if (i == 30 || i == 31) continue;
    EXPECT_EQ(b.f.f_world.col(i).norm(), 0.0) << i;
  }
}

// A point in the groove between two turns touches both: each pushes k h
// along the line from its axis, h = d - the distance from it.
TEST(WireContact, APointInTheGrooveFeelsBothTurns) {
  const cws::Scene s = wireContactScene();
  const cws::RotatingCore core(s.core, 0.0);
  TwoRuns wire(s);
  Bench b(s, 40, 23);
  cws::Contact contact(b.c, s, core);
  contact.attachCarriedWire(wire.carried_core);
  const double d = wire.d, k = s.contact.stiffness;
  for (int i = 23; i < 40; ++i) b.k.p_world.col(i) = Eigen::Vector3d(0.0, -50e-3, i * 1e-3);
  // Over the groove at x = 4.5 mm, a little below sqrt(3)/2 d, where it
  // would rest on both.
  const double height = 0.5 * std::sqrt(3.0) * d - 3e-5;
  const Eigen::Vector3d p(4.5e-3, wire.y0 + height, 0.5 * d);
  b.k.p_world.col(33) = p;
  b.evaluate(contact);
  Eigen::Vector3d expected = Eigen::Vector3d::Zero();
  for (double z : {0.0, d}) {
    const Eigen::Vector3d from_axis(0.0, height, p.z() - z);
    expected += k * (d - from_axis.norm()) * from_axis.normalized();
  }
  EXPECT_LT((b.f.f_world.col(33) - expected).norm(), 1e-9 * expected.norm());
  EXPECT_NEAR(expected.z(), 0.0, 1e-12 * expected.norm());  // symmetric: up only
  contact.commit({0.0, b.k, false});
  int runs = 0;
  for (int slot = 0; slot < contact.slots(); ++slot) {
    runs += contact.surface(33, slot) >= contact.wireSurface();
  }
  EXPECT_EQ(runs, 2);
}

// A point nested among four carried wires (a disordered coil) feels all
// four: k h_i from each wire's axis, h_i = d - the distance from it.
TEST(WireContact, APointAmongFourWiresFeelsAllFour) {
  const cws::Scene s = wireContactScene();
  const cws::RotatingCore core(s.core, 0.0);
  const double d = s.wire.diameter, y0 = 30e-3, k = s.contact.stiffness;
  // Four runs of 11 points along x around the line (y0, 0), each h_i
  // deeper than touching; the segments joining them lie at x = 10 mm.
  const double h[4] = {1e-5, 2e-5, 3e-5, 4e-5};  // [m]
  const Eigen::Vector3d dir[4] = {Eigen::Vector3d::UnitY(), -Eigen::Vector3d::UnitY(),
                                  Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitZ()};
  std::vector<Eigen::Vector3d> carried(60, Eigen::Vector3d::Zero());
  for (int run = 0; run < 4; ++run) {
    for (int j = 0; j < 11; ++j) {
      const double along = (run % 2 == 0 ? j : 10 - j) * 1e-3;
      carried[1 + 11 * run + j] = Eigen::Vector3d(along, y0, 0.0) + (d - h[run]) * dir[run];
    }
  }
  Bench b(s, 60, 45);
  cws::Contact contact(b.c, s, core);
  contact.attachCarriedWire(carried);
  for (int i = 45; i < 60; ++i) b.k.p_world.col(i) = Eigen::Vector3d(0.0, -50e-3, i * 1e-3);
  b.k.p_world.col(52) = Eigen::Vector3d(4.5e-3, y0, 0.0);
  b.evaluate(contact);
  Eigen::Vector3d expected = Eigen::Vector3d::Zero();
  for (int run = 0; run < 4; ++run) expected -= k * h[run] * dir[run];
  EXPECT_LT((b.f.f_world.col(52) - expected).norm(), 1e-9 * expected.norm());
  contact.commit({0.0, b.k, false});
  int runs = 0;
  for (int slot = 0; slot < contact.slots(); ++slot) {
    runs += contact.surface(52, slot) >= contact.wireSurface();
  }
  EXPECT_EQ(runs, 4);
}

TEST(WireContact, RefusedWhereThereIsNoCarriedWire) {
  auto refusal = [&](const std::vector<std::string>& overrides) {
    try {
      cws::loadScene(k3d, overrides);
    } catch (const cws::SceneError& e) {
      return e.key() + ": " + e.what();
    }
    return std::string("accepted");
  };
  EXPECT_NE(refusal({"physics.wire_contact=true", "solver.carry_stuck_wire=false"})
                .find("solver.carry_stuck_wire"),
            std::string::npos);
  EXPECT_NE(refusal({"physics.wire_contact=true", "physics.planar=true", "process.traverse_pitch=0",
                     "physics.torsion=false"})
                .find("physics.wire_contact"),
            std::string::npos);
  EXPECT_EQ(refusal({"physics.wire_contact=true"}), "accepted");
}

TEST(Flanges, NeedContactA3dSceneAndAWidth) {
  auto refusal = [&](const std::vector<std::string>& overrides) {
    try {
      cws::loadScene(k3d, overrides);
    } catch (const cws::SceneError& e) {
      return e.key() + ": " + e.what();
    }
    return std::string("accepted");
  };
  EXPECT_NE(refusal({"physics.flanges=true"}).find("process.winding_width, which is 0"),
            std::string::npos);
  EXPECT_NE(refusal({"physics.flanges=true", "process.winding_width=4e-3", "physics.friction=false",
                     "physics.contact=false"})
                .find("flanges need physics.contact"),
            std::string::npos);
  EXPECT_EQ(refusal({"physics.flanges=true", "process.winding_width=4e-3"}), "accepted");
}
#endif
