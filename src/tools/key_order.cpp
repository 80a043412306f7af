#include "key_order.hpp"

namespace cws_tools {

Eigen::VectorXd keepKeyOrder(const std::vector<std::string>& keys, const cws::Scene& base,
                             Eigen::VectorXd x) {
  // The lower key, the upper key, and their values in a scene.
  struct Ordered {
    const char *lower, *upper;
    double base_lower, base_upper;
  };
  const Ordered pairs[] = {{"contact.kinetic_friction", "contact.static_friction",
                            base.contact.kinetic_friction, base.contact.static_friction}};
  auto indexOf = [&](const char* key) {
    for (std::size_t k = 0; k < keys.size(); ++k)
      if (keys[k] == key) return static_cast<int>(k);
    return -1;
  };
  for (const Ordered& p : pairs) {
    const int lo = indexOf(p.lower), up = indexOf(p.upper);
    if (lo < 0 && up < 0) continue;
    const double lower = lo >= 0 ? x[lo] : p.base_lower;
    const double upper = up >= 0 ? x[up] : p.base_upper;
    if (lower <= upper) continue;
    if (lo >= 0) {
      x[lo] = upper;
    } else {
      x[up] = lower;
    }
  }
  return x;
}

}  // namespace cws_tools
