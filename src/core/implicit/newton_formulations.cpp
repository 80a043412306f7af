#include "coil_winding_sim/core/implicit/newton_formulations.hpp"

#include "coil_winding_sim/core/implicit/planar_formulation.hpp"
#include "coil_winding_sim/core/implicit/spatial_formulation.hpp"

namespace cws {

std::unique_ptr<NewtonFormulation> makeNewtonFormulation(NewtonModelView& model,
                                                         const SolverParams& solver) {
  if (model.newtonSetup().planar) return std::make_unique<PlanarFormulation>(model, solver);
  return std::make_unique<SpatialFormulation>(model, solver);
}

}  // namespace cws
