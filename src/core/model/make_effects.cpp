#include "coil_winding_sim/core/model/make_effects.hpp"

#include "coil_winding_sim/core/external_forces/air_drag.hpp"
#include "coil_winding_sim/core/external_forces/contact.hpp"
#include "coil_winding_sim/core/external_forces/damping.hpp"
#include "coil_winding_sim/core/external_forces/end_load.hpp"
#include "coil_winding_sim/core/external_forces/free_wire_contact.hpp"
#include "coil_winding_sim/core/external_forces/gravity.hpp"
#include "coil_winding_sim/core/external_forces/supply.hpp"
#include "coil_winding_sim/core/inner_forces/bending.hpp"
#include "coil_winding_sim/core/inner_forces/stretching.hpp"
#include "coil_winding_sim/core/inner_forces/twisting.hpp"

namespace cws {

EffectSet makeEffects(const Scene& s, const EffectContext& ctx) {
  const WireConstants& c = ctx.constants;
  const bool plastic = s.physics.plasticity;
  const PhysicsSwitches& on = s.physics;
  EffectSet e;
  // The springs of the wire (section II), then the loads on it, in the
  // order their forces are summed.
  e.add(std::make_unique<Stretching>(c, s.wire.stretch, plastic));
  Bending* bending = e.add(std::make_unique<Bending>(c, s.wire.bend, plastic));
  if (on.torsion) {
    // Bending and torsion share one pass over the joints' rotations.
    bending->sharePass(*e.add(std::make_unique<Twisting>(c, s.wire.torsion, plastic)));
  }
  if (on.gravity) e.add(std::make_unique<Gravity>(c, s.gravity.acceleration_world));
  if (on.damping) e.add(std::make_unique<Damping>(c, s.damping));
  if (on.air_drag) e.add(std::make_unique<AirDrag>(c, s.air_drag));
  if (on.contact) {
    Contact* contact = e.add(std::make_unique<Contact>(c, s, *ctx.core));
    if (on.wire_contact) {
      contact->attachCarriedWire(*ctx.carried_p_core);
      e.add(std::make_unique<FreeWireContact>(c, *contact));
    }
  }
  if (on.supply) e.add(std::make_unique<Supply>(c, s, ctx.core));
  e.add(std::make_unique<EndLoad>(c, s.end.load));
  return e;
}

}  // namespace cws
