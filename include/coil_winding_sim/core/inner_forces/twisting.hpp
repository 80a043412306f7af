// Torsional springs, eqs. (13)-(15), on the twist rate.
#pragma once

#include "coil_winding_sim/core/inner_forces/rotational_spring.hpp"

namespace cws {

// Torsion about the wire axis zeta.
class Twisting : public RotationalSpring {
 public:
  Twisting(const WireConstants& c, const HysteresisParams& p, bool plastic)
      : RotationalSpring("twisting", c, p, plastic, 2, 1) {}
};

}  // namespace cws
