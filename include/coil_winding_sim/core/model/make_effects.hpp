// The one place where a scene's effects are made: each effect a scene
// switches on, in evaluation order. A scene that switches an effect off
// never builds it. Adding an effect is its file, its scene keys and one
// line in makeEffects (src/core/model/make_effects.cpp).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <type_traits>
#include <vector>

#include "coil_winding_sim/core/assembly/force_effect.hpp"
#include "coil_winding_sim/core/scene/scene.hpp"

namespace cws {

class RotatingCore;

// What the effects are made with besides the scene: the model's constants
// (n grows with a supply), its core (null when the scene needs none) and
// the poses of the wire the core carries (core frame).
struct EffectContext {
  const WireConstants& constants;
  const RotatingCore* core = nullptr;
  const std::vector<Eigen::Vector3d>* carried_p_core = nullptr;
};

// The effects of a scene, in evaluation order.
class EffectSet {
 public:
  // The first effect of type E, or null.
  template <class E>
  E* find() const {
    for (const auto& e : owned_) {
      if (auto* p = dynamic_cast<E*>(e.get())) return p;
    }
    return nullptr;
  }
  // All, in evaluation order.
  std::vector<ForceEffect*> list() const {
    std::vector<ForceEffect*> out;
    for (const auto& e : owned_) out.push_back(e.get());
    return out;
  }
  // Those that keep a history, in the same order (snapshots store theirs
  // in it).
  const std::vector<EffectHistory*>& histories() const { return histories_; }
  // Adds an effect (makeEffects); returns it.
  template <class E>
  E* add(std::unique_ptr<E> e) {
    E* p = e.get();
    if constexpr (std::is_base_of_v<EffectHistory, E>) histories_.push_back(p);
    owned_.push_back(std::move(e));
    return p;
  }

 private:
  std::vector<std::unique_ptr<ForceEffect>> owned_;
  std::vector<EffectHistory*> histories_;
};

// The effects `s` (validated) switches on, made with `ctx`.
EffectSet makeEffects(const Scene& s, const EffectContext& ctx);

}  // namespace cws
