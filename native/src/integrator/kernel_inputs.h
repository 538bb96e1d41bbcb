// What every stage of a kernel reads (kernel.h, and the concepts it calls: lights.h,
// shadow.h, mis.h, glossy.h, wave.h): the scene, the settings, the camera, its queries
// (whitted.cpp) and the effects the analysis chose (EffectBits).
#pragma once

#include <cstdint>

#include "integrator/analysis.h"
#include "integrator/settings.h"
#include "integrator/strata.h"
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

  // What a shader program may ask of a ray at `state` besides the ray; `rays` where it
  // may trace from the hit (ProgramRays).
  RayContext context(const NodeState& state, const TracedRays* rays = nullptr) const {
    return {&camera, state.depth, rays};
  }

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

// The rays a program traces from a surface that a ray at `state` met (TracedRays): the
// kernel's queries, counted in `counts` and told to `recorder` under the ray's `node`
// (the inspector's), and the points of the state's chain (strata.h) in a dimension of
// their own.
template <uint32_t kEffects, class Queries, class Recorder>
class ProgramRays final : public TracedRays {
 public:
  static constexpr uint32_t kSalt = 0x414f5253u;
  ProgramRays(const KernelInputs<kEffects, Queries>& in, const NodeState& state, RayCounts* counts,
              Recorder& recorder, typename Recorder::Node node)
      : in_(in), state_(state), counts_(counts), recorder_(recorder), node_(node) {}
  bool occluded(const Ray& ray, const uint32_t* instance) const override {
    counts_->ambient_occlusion += 1;
    Blockers only;
    if (instance != nullptr) only.instance = *instance;
    const bool blocked = in_.queries.occluded(ray, instance != nullptr ? &only : nullptr);
    recorder_.program_ray(node_, ray, state_.depth, TreeRayKind::kAmbientOcclusion, blocked);
    return blocked;
  }
  bool intersect(const Ray& ray, Hit* hit) const override {
    counts_->bevel += 1;
    const bool found = in_.queries.intersect(ray, hit);
    Ray drawn = ray;
    if (found) drawn.t_max = hit->t;
    recorder_.program_ray(node_, drawn, state_.depth, TreeRayKind::kBevel, found);
    return found;
  }
  glm::vec2 point(int k, int count) const override {
    return ChainPoints(state_, kSalt, count).point(k);
  }

 private:
  const KernelInputs<kEffects, Queries>& in_;
  const NodeState& state_;
  RayCounts* counts_;
  Recorder& recorder_;
  typename Recorder::Node node_;
};

}  // namespace whitted
