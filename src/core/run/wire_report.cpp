// Reports of the whole wire at the last accepted step (wire_report.hpp).
#include "coil_winding_sim/core/run/wire_report.hpp"

#include <algorithm>

#include "coil_winding_sim/core/external_forces/contact.hpp"
#include "coil_winding_sim/core/machine/rotating_core.hpp"

namespace cws {

PointReport wirePoint(const WireModel& m, int w) {
  const int retired = m.retiredPoints();
  if (w >= retired) return m.livePoint(w - retired);
  const RetiredPoint& q = m.retiredWire()[w];
  PointReport r;
  static_cast<PointFigures&>(r) = q;
  r.p_world = m.core()->pointWorld(m.committedTime(), q.p_core);
  return r;
}

Eigen::Vector3d wirePointCore(const WireModel& m, int w) {
  const int retired = m.retiredPoints();
  if (w < retired) return m.retiredWire()[w].p_core;
  return m.core()->pointCore(m.committedTime(), m.committed().p_world.col(w - retired));
}

double standOff(const WireModel& m, int w) {
  const int retired = m.retiredPoints();
  return w < retired ? m.retiredWire()[w].stand_off_m : m.liveStandOff(w - retired);
}

int lastInContact(const WireModel& m) {
  const Contact* contact = m.contact();
  if (!contact) return -1;
  const int retired = m.retiredPoints(), n = m.constants().n;
  int last = -1;
  for (int i = 1; i < n; ++i) {
    if (contact->inContact(i)) last = i;
  }
  if (last >= 0) return retired + last;
  for (int w = retired - 1; w >= 1; --w) {
    if (m.retiredWire()[w].in_contact) return w;
  }
  return -1;
}

BulgeReport bulging(const WireModel& m) {
  BulgeReport b;
  if (!m.contact() || !m.section()) return b;
  const int last_contact = lastInContact(m);
  if (last_contact < 0) return b;
  b.valid = true;
  b.wound_points = last_contact + 1;
  b.height_m = 0.0;
  // Retired wire: its largest stand-off was found as it retired.
  const RetiredWire& retired = m.retiredWire();
  int w = 0;
  if (m.retiredPoints() > 0 && last_contact >= m.retiredPoints()) {
    b.height_m = retired.max_stand_off_m;
    b.index = retired.max_stand_off_point;
    w = m.retiredPoints();
  }
  for (; w <= last_contact; ++w) {
    const double h = standOff(m, w);
    if (h > b.height_m || b.index < 0) {
      b.height_m = std::max(0.0, h);
      b.index = w;
    }
  }
  b.build_up_m = b.height_m;
  b.arc_length_m = b.index * m.constants().segment_length;
  b.p_core = wirePointCore(m, b.index);
  return b;
}

}  // namespace cws
