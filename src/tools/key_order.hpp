// Scene keys whose values must keep an order (kinetic friction at most
// static friction), for searches over boxes of keys (calibrate): a point
// that breaks the order is moved onto it.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws_tools {

// The point x (the values of `keys`, in their order) moved onto the keys'
// order where it breaks it: the key of a pair among `keys` takes the
// other's value (the lower one's where both are); `base` gives the value
// of a key of a pair that is not among them. A search over a box that
// runs through this stays within the order: a corner that breaks it is
// its edge.
Eigen::VectorXd keepKeyOrder(const std::vector<std::string>& keys, const cws::Scene& base,
                             Eigen::VectorXd x);

}  // namespace cws_tools
