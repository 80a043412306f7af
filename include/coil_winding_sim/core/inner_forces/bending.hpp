// Bending springs, eqs. (10)-(12), on the two curvature components.
#pragma once

#include "coil_winding_sim/core/inner_forces/rotational_spring.hpp"

namespace cws {

// Bending: two curvature components in the material frame, each with its own
// hysteresis (the paper's scalar bending angle generalized to 3-D).
class Bending : public RotationalSpring {
 public:
  Bending(const WireConstants& c, const HysteresisParams& p, bool plastic)
      : RotationalSpring("bending", c, p, plastic, 0, 2) {}
};

}  // namespace cws
