// Multiple importance sampling (Veach 1995) between the two techniques that reach an
// emissive mesh, the world or a lamp's shape: the feelers to the emitters, to the world
// and to the lamps (lights.h) and the glossy rays (glossy.h).
// Each weighs what it brings by the power heuristic against the other's density.
#pragma once

#include <cmath>
#include <cstdint>

#include "core/math.h"
#include "core/ray.h"
#include "integrator/kernel_inputs.h"
#include "integrator/shading_point.h"
#include "integrator/split.h"
#include "integrator/strata.h"
#include "scene/mesh_light.h"
#include "scene/microfacet.h"

namespace whitted {

// Veach's power heuristic (exponent 2): the weight of a sample drawn with density `a`
// (per solid angle, times its technique's sample count) against the other technique's
// density `b` for the same direction. The two weights of a direction sum to 1.
inline float power_heuristic(float a, float b) {
  if (!(a > 0.0f)) return 0.0f;
  const float r = b / a;
  if (std::isnan(r)) return 0.5f;  // both infinite
  return 1.0f / (1.0f + r * r);
}

// The glossy rays a hit will send, as the feelers to emissive meshes weigh their glossy
// share against them: the lobe they are drawn from and how many there are per feeler.
// count 0: none will be sent (no glossy lobe, the depth, the cutoff), and the feelers
// count whole.
struct GlossyRays {
  GgxLobe lobe{Vec3(0.0f, 0.0f, 1.0f), 0.0f};
  float count = 0.0f;
  float drawn = 0.0f;  // how many (n x n), as the lamps' feelers weigh theirs against them
};

// Whether glossy rays see some lamp's shape (their MIS weights against its feelers).
inline bool lamps_seen_by_glossy(const CompiledScene& scene) {
  return (scene.lamps_visibility & kReflectionRay) != 0;
}

// What a ray counts of the radiance it meets on the shape of `light` (intersect_light,
// whose `density` is given): a glossy ray (its NodeState::lamp_density) its power
// heuristic against the light's feelers, every other ray all of it.
inline float lamp_weight(float lamp_density, const Light& light, float density) {
  if (!(lamp_density > 0.0f)) return 1.0f;
  return power_heuristic(lamp_density, static_cast<float>(light.sample_count()) * density);
}

// Glossy rays per emitter feeler at a hit: each technique's sample count at `state`.
inline float rays_per_feeler(const Settings& settings, const NodeState& state) {
  const int glossy = Strata::side(state, settings.glossy_samples);
  const int feelers = Strata::side(state, settings.emitter_samples);
  return static_cast<float>(glossy * glossy) / static_cast<float>(feelers * feelers);
}

// The glossy rays the reflected term will send from this hit, for the emitter and world
// feelers' MIS weights: none without emitters or a world light, a glossy lobe, depth left
// or a weight above the cutoff.
// Always inlined into the step, as split_weights (split.h says why).
template <uint32_t kEffects, class Queries>
[[gnu::always_inline]] inline GlossyRays glossy_rays(const KernelInputs<kEffects, Queries>& in,
                                                     const ShadingPoint& p, const Split& split,
                                                     const NodeState& state) {
  GlossyRays rays;
  if (!(in.emitters || in.lit_by_world(state.depth) || lamps_seen_by_glossy(in.scene)) ||
      (in.effects & kGlossyEffect) == 0 || !in.has(kReflectionEffect)) {
    return rays;
  }
  if (split.total_internal_reflection || is_black(split.sigma_r)) return rays;
  const bool coat = split.about_coat && p.coat.alpha > 0.0f;
  if (!coat && (split.about_coat || !(p.alpha > 0.0f))) return rays;
  if (state.depth + 1 > in.settings.max_depth) return rays;
  const Color energy = coat ? Color(1.0f) : p.energy;
  if (max_component(state.weight * split.sigma_r * energy) < in.settings.cutoff) return rays;
  rays.lobe = coat ? GgxLobe(p.coat.normal, p.coat.alpha) : p.ggx;
  rays.count = rays_per_feeler(in.settings, state);
  const int side = Strata::side(state, in.settings.glossy_samples);
  rays.drawn = static_cast<float>(side * side);
  return rays;
}

// What a glossy ray counts of the emission it meets: its MIS weight against the
// feelers that sample this side of this triangle (1 where none do, and for every other
// ray; 0 where light linking keeps the emitter from the surface the ray left). The
// distance is from the ray's origin (behind a cut-out: from the cut-out).
// Always inlined into the step, as split_weights (split.h says why).
template <uint32_t kEffects, class Queries>
[[gnu::always_inline]] inline float emission_weight(const KernelInputs<kEffects, Queries>& in,
                                                    const Ray& ray, const ShadingPoint& p,
                                                    const NodeState& state) {
  if (is_black(p.surface.emission)) return 1.0f;
  const CompiledScene& scene = in.scene;
  // Light linking: a bounce sees an emitter only if it lights the surface it left
  // (camera rays see every one, as in Cycles).
  if (scene.light_linking && state.receiver >= 0 &&
      !in_sets(scene.instances[p.it.instance].links.light_sets,
               static_cast<uint32_t>(state.receiver))) {
    return 0.0f;
  }
  if (!(state.mis > 0.0f) || !in.emitters) return 1.0f;
  const MeshLights& lights = *scene.mesh_lights;
  const int32_t index = lights.find(p.it.instance, p.it.primitive);
  if (index < 0) return 1.0f;
  const auto found = static_cast<uint32_t>(index);
  const EmissiveTriangle triangle = lights.at(scene, found, p.it.time);
  if (!triangle.lights(-ray.direction)) return 1.0f;
  const Vec3 d = p.it.position - ray.origin;
  const float cos_e = std::fabs(glm::dot(ray.direction, triangle.normal));
  const float density = lights.density(found, triangle) * glm::dot(d, d) / cos_e;
  return power_heuristic(state.mis, density);
}

}  // namespace whitted
