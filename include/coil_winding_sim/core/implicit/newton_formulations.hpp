// The Newton formulation an implicit stepper solves, built for the model
// it integrates: the planar wire's reduced coordinates, or the 3-D wire
// with its frame constraints.
#pragma once

#include <memory>

#include "coil_winding_sim/core/implicit/newton_formulation.hpp"
#include "coil_winding_sim/core/model/newton_model_view.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

std::unique_ptr<NewtonFormulation> makeNewtonFormulation(NewtonModelView& model,
                                                         const SolverParams& solver);

}  // namespace cws
