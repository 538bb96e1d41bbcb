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
// shares against them: the lobes they are drawn from (the coat's; the base's, which the
// specular layer beneath the coat shares) and how many each lobe sends per feeler.
// count 0: none will be sent (no glossy lobe, the depth, the cutoff), and the feelers
// count whole.
struct GlossyRays {
  GgxLobe coat{Vec3(0.0f, 0.0f, 1.0f), 0.0f};
  CoatModel coat_model = CoatModel::kGgx;  // the coat lobe's distribution
  GgxLobe base{Vec3(0.0f, 0.0f, 1.0f), 0.0f};
  // Which lobes send rays: a lobe that sends none leaves its share whole to the feelers.
  bool coat_rays = false;
  bool layer_rays = false;
  bool base_rays = false;
  float count = 0.0f;  // per lobe that sends rays
  float drawn = 0.0f;  // how many each (n x n), as the lamps' feelers weigh theirs against them
};

// A feeler's MIS weights on the glossy lobes' shares, `density` its own (per solid angle,
// times its technique's count) and `rays` each lobe's rays per feeler (GlossyRays::count,
// or ::drawn against a lamp's n x n feelers).
//
// Why per lobe: the reflected term is a sum of integrals, one per lobe j (the coat, the
// specular layer, the base), I_j = int f_j(wi) L(wi) dwi. Lobe j's rays are drawn from
// p_j and carry f_j alone (glossy.h: their weight is that lobe's sigma), so each I_j has
// exactly two techniques that estimate it: the feelers (density p_F, n_F of them) and
// lobe j's rays (p_j, n_j). Veach's multi-sample MIS over those two gives the feeler's
// share of f_j the weight w_F,j = h(n_F p_F, n_j p_j) and lobe j's ray the weight
// w_j = h(n_j p_j, n_F p_F) (its NodeState::mis, world_weight, lamp_density), with h the
// power heuristic: w_F,j + w_j = 1 for every direction, so each I_j, and their sum, is
// estimated without bias. A lobe's rays never weigh against another lobe's: they do not
// evaluate its f_k, which no other technique than its own rays and the feelers estimates.
// The layer and the base draw from the same GGX lobe (ShadingPoint::ggx), one density.
inline LobeWeights lobe_weights(const GlossyRays& rays, float count, float density, const Vec3& wo,
                                const Vec3& wi) {
  LobeWeights w;
  if (rays.coat_rays) {
    w.coat =
        power_heuristic(density, count * lobe_reflection_pdf(rays.coat_model, rays.coat, wo, wi));
  }
  if (rays.layer_rays || rays.base_rays) {
    const float base = power_heuristic(density, count * ggx_reflection_pdf(rays.base, wo, wi));
    if (rays.layer_rays) w.layer = base;
    if (rays.base_rays) w.base = base;
  }
  return w;
}

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
  if (state.depth + 1 > in.settings.max_depth) return rays;
  // Each glossy lobe above the cutoff (branch's, on a lobe's whole weight) sends rays.
  for (const Lobe& lobe : reflection_lobes(p, split, true)) {
    if (!(lobe.ggx.alpha() > 0.0f) ||
        max_component(state.weight * lobe.sigma * lobe.energy) < in.settings.cutoff) {
      continue;
    }
    if (lobe.coat == &p.coat) {
      rays.coat = lobe.ggx;
      rays.coat_model = lobe.model();
      rays.coat_rays = true;
    } else {
      rays.base = lobe.ggx;
      (lobe.coat == &p.layer ? rays.layer_rays : rays.base_rays) = true;
    }
  }
  if (!(rays.coat_rays || rays.layer_rays || rays.base_rays)) return rays;
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
