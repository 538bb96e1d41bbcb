// What a shadow feeler lets through: its first query, an any-hit test, and behind
// surfaces that let light through, the walk that multiplies their transmittance. The
// recursion (lights.h) and the wave's feeler stage (wave.h) both finish a feeler here.
#pragma once

#include <cstdint>

#include "accel/embree.h"
#include "core/limits.h"
#include "core/ray.h"
#include "integrator/kernel_inputs.h"
#include "integrator/transmittance.h"
#include "scene/light.h"

namespace whitted {

// Feelers traced together (a sized light's samples at one hit, or one lamp's feelers of a
// wave) fill at most one packet.
inline constexpr int kFeelerBatch = SceneAccel::kPacketSize;

// Shadow linking: the instances that may block a feeler of an emitter whose shadows
// the shadow sets `sets` cast (null: every instance), held in *storage.
inline const Blockers* blockers(const CompiledScene& scene, uint64_t sets, Blockers* storage) {
  if (sets == kAllLightSets) return nullptr;
  *storage = Blockers{scene.shadow_sets.data(), sets};
  return storage;
}

// A shadow ray's first query, an any-hit test: against everything, or where anything
// lets light through, against the opaque instances only (anything opaque in the way
// blocks all of the light, whatever lies in front: ray.h).
template <uint32_t kEffects, class Queries>
Ray first_query(const KernelInputs<kEffects, Queries>& in, Ray ray) {
  if (in.has(kTranslucencyEffect)) ray.kind = kOpaqueShadowRay;
  return ray;
}

// What the surfaces on a shadow ray let through (shadow_transmittance, below).
template <uint32_t kEffects, class Queries>
Color surfaces_transmittance(const KernelInputs<kEffects, Queries>& in, Ray ray, bool blocked,
                             const Blockers* linked, int depth, RayCounts* counts) {
  if (blocked) return Color(0.0f);
  if (!in.has(kTranslucencyEffect)) return Color(1.0f);
  ray.kind = kTranslucentShadowRay;
  counts->shadow += 1;
  Color transmittance(1.0f);
  for (int i = 0; i < limits::kMaxTransparentLayers; ++i) {
    Hit hit;
    if (!in.queries.intersect(ray, &hit)) return transmittance;
    const Interaction it = in.scene.interaction(ray, hit);
    // Under shadow linking, a surface that casts none of this light's shadows is passed.
    if (linked == nullptr || in_sets(linked->sets, in.scene.shadow_sets[hit.instance])) {
      const SurfaceParams surface = in.scene.surface(it, ray, RayContext{&in.camera, depth});
      const float a = surface.alpha;
      const bool tinted = in.settings.glass_shadows == GlassShadows::kTinted;
      transmittance *= (1.0f - a) + a * (tinted ? surface.transmissivity : Color(0.0f));
    }
    if (is_black(transmittance)) return transmittance;
    const float remaining = ray.t_max - glm::length(it.position - ray.origin);
    if (!(remaining > 0.0f)) return transmittance;
    ray = spawn_ray(it.position, it.position_error, it.geometric_normal, it.time, ray.direction,
                    kTranslucentShadowRay, remaining);
    counts->shadow += 1;
  }
  return Color(0.0f);
}

// Fraction of light that reaches the end of a shadow ray whose first query answered
// `blocked` (both among `linked`, null: every instance): 0 behind anything opaque; through a
// surface of coverage a, 1 - a passes (cut-outs), and of its covered part a*T with glass_shadows
// tinted (coloured shadows behind glass, transmissivity T), else none (settings.h); in a
// scene with media (kVolumeEffect), times what the media it crosses let through.
template <uint32_t kEffects, class Queries>
Color shadow_transmittance(const KernelInputs<kEffects, Queries>& in, const Ray& ray, bool blocked,
                           const Blockers* linked, int depth, RayCounts* counts) {
  counts->shadow += 1;
  Color through = surfaces_transmittance(in, ray, blocked, linked, depth, counts);
  if (in.has(kVolumeEffect) && !is_black(through))
    through *= media_transmittance(in, ray, depth, counts);
  return through;
}

}  // namespace whitted
