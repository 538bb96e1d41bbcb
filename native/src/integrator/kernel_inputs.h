// What every stage of a kernel reads (kernel.h, and the concepts it calls: lights.h,
// shadow.h, mis.h, glossy.h, wave.h): the scene, the settings, the camera, its queries
// (whitted.cpp) and the effects the analysis chose (EffectBits).
#pragma once

#include <cstdint>

#include "integrator/analysis.h"
#include "integrator/settings.h"
#include "integrator/whitted.h"
#include "scene/mesh_light.h"
#include "scene/scene.h"

namespace whitted {

// kEffects of a kernel that reads the effects at run time.
inline constexpr uint32_t kRuntimeEffects = ~0u;

// The effects are read with has(): constants in the kernels compiled per set of effects
// (kEffects, for renders without passes: measured faster, docs/EFFECTS.md), run-time
// flags in the others (kRuntimeEffects) and for the bits above kAllEffects. The code is
// the same either way.
template <uint32_t kEffects, class Queries>
struct KernelInputs {
  explicit KernelInputs(const WhittedIntegrator& w)
      : scene(w.scene()),
        settings(w.settings()),
        camera(w.camera()),
        queries(w),
        effects(w.effects().bits),
        emitters((effects & kEmitterEffect) != 0 && !scene.mesh_lights->empty()),
        world((effects & kWorldLightEffect) != 0 ? scene.world_light.get() : nullptr) {}

  bool has(uint32_t bit) const {
    if constexpr (kEffects == kRuntimeEffects) {
      return (effects & bit) != 0;
    } else {
      // The bits above kAllEffects are read at run time in every kernel (EffectBits).
      return bit > kAllEffects ? (effects & bit) != 0 : (kEffects & bit) != 0;
    }
  }

  // What a shader program may ask of a ray at `state` besides the ray.
  RayContext context(const NodeState& state) const { return {&camera, state.depth}; }

  const CompiledScene& scene;
  const Settings& settings;
  const Camera& camera;
  Queries queries;
  uint32_t effects;         // EffectBits
  bool emitters;            // feelers go to emissive meshes (kEmitterEffect, and there are some)
  const WorldLight* world;  // feelers go to the world (kWorldLightEffect); null: none
  // Whether a hit at `depth` sends feelers to the world (its Max Bounces).
  bool lit_by_world(int depth) const {
    return world != nullptr && depth <= world->params().max_bounces;
  }
};

}  // namespace whitted
