// Distributed ray tracing's glossy terms (Cook et al. 1984): the reflected and the
// refracted term of a rough surface as the mean of n x n rays drawn from its lobe
// (microfacet.h: GGX's, or GTR1's for Blender 3.x's Clearcoat), one per stratum (strata.h). Each
// ray is handed to `branch`, the kernel's (kernel.h: traced now, or queued in a wave), as
// branch(ray, weight, media, drawn), which returns the radiance it brings back.
#pragma once

#include <algorithm>
#include <cstdint>

#include "core/math.h"
#include "core/ray.h"
#include "integrator/kernel_inputs.h"
#include "integrator/lobes.h"
#include "integrator/medium.h"
#include "integrator/mis.h"
#include "integrator/shading_point.h"
#include "integrator/split.h"
#include "integrator/strata.h"
#include "scene/microfacet.h"

namespace whitted {

// Glossy reflection: n x n rays drawn from the lobe, each weighing its sigma * f cos / pdf
// / n^2 (the lobe over its density: GGX's G2/G1). Their points (Strata) depend only on the pixel
// and the camera sample (a Sobol sequence's, or a hash of the sample's seed), so every render of a
// scene draws the same rays, whatever its scale, and neighbouring samples different ones. A ray the
// lobe sends below the surface is lost, as light the single-scattering lobe does not return.
// Returns the mean of what they bring, per unit of the lobe's sigma.
template <uint32_t kEffects, class Queries, class Branch>
Color glossy_reflection(const KernelInputs<kEffects, Queries>& in, const ShadingPoint& p,
                        const Lobe& lobe_of, const NodeState& state, const Branch& branch) {
  const Strata strata(state, in.settings.glossy_samples, 0x6c6fu, jittered_samples(in.settings));
  // The world light the rays' glossy share is weighed against (null: none), and rays per
  // emitter or world feeler, for each ray's MIS density (0: no emitters to weigh).
  const WorldLight* world =
      in.lit_by_world(state.depth) && in.world->params().glossy ? in.world : nullptr;
  const float per_feeler =
      in.emitters || world != nullptr ? rays_per_feeler(in.settings, state) : 0.0f;
  const bool lamps = lamps_seen_by_glossy(in.scene);
  Color mean(0.0f);  // sum over the rays of (weight / sigma) * radiance
  for (int k = 0; k < strata.count(); ++k) {
    const glm::vec2 u = strata.point(k);
    Vec3 wi;
    float lobe = 0.0f;  // f cos / pdf (GGX's G2 / G1)
    if (!lobe_sample_reflection(lobe_of.model(), lobe_of.ggx, p.wo, u.x, u.y, &wi, &lobe,
                                p.it.material->masking)) {
      continue;
    }
    if (glm::dot(wi, p.ng) <= 0.0f) continue;  // below the surface itself
    if (lobe_of.coat != nullptr) {
      lobe *= lobe_of.coat->facet_scale(p.wo, glm::normalize(p.wo + wi));
    }
    const Color weight = lobe_of.sigma * lobe_of.energy * lobe;
    // Its density, for the MIS weight of the emission it may meet (emission_weight) and
    // of the lamps' shapes (lamp_weight).
    const float pdf = per_feeler > 0.0f || lamps
                          ? lobe_reflection_pdf(lobe_of.model(), lobe_of.ggx, p.wo, wi)
                          : 0.0f;
    const float density = per_feeler * pdf;
    const float mis = in.emitters ? density : 0.0f;
    // Its weight on the world where it escapes, against the world's feelers.
    const float world_weight =
        world != nullptr ? power_heuristic(density, world->pdf(wi, p.ns)) : 1.0f;
    const float lamp_density = lamps ? static_cast<float>(strata.count()) * pdf : 0.0f;
    const uint32_t seed = hash3(state.seed, static_cast<uint32_t>(k), 0x676cu);
    const Drawn drawn{strata.share, seed, strata.index(k), mis, world_weight, lamp_density};
    const Color brought = branch(spawn_ray(p.it.position, p.it.position_error,
                                           p.it.geometric_normal, p.it.time, wi, kReflectionRay),
                                 weight, state.media, drawn);
    mean += (lobe * strata.share) * lobe_of.energy * brought;
  }
  return mean;
}

// Frosted glass: the refracted term from n x n visible normals of the GGX lobe (as
// glossy_reflection's), the view refracted through each (Walter et al. 2007), weighing
// sigma_t * G2/G1 times its facet's Fresnel transmittance over the one sigma_t holds.
// Where a facet totally reflects the view (inside the glass, past its critical angle),
// its ray reflects about it and stays in the medium. Returns the mean per unit sigma_t.
template <uint32_t kEffects, class Queries, class Branch>
Color rough_transmission(const KernelInputs<kEffects, Queries>& in, const ShadingPoint& p,
                         const Color& sigma_t, const Crossing& beyond, const NodeState& state,
                         const Branch& branch) {
  const Strata strata(state, in.settings.glossy_samples, 0x7472u, jittered_samples(in.settings));
  const float cos_o = glm::dot(p.ns, p.wo);
  const bool fresnel = in.settings.fresnel != Fresnel::kOff;
  const float kept = fresnel ? 1.0f - fresnel_exact(cos_o, beyond.eta) : 1.0f;
  Color mean(0.0f);
  for (int k = 0; k < strata.count(); ++k) {
    Vec3 m;
    const glm::vec2 u = strata.point(k);
    if (!ggx_sample_normal(p.ns, p.wo, p.alpha, u.x, u.y, &m)) {
      continue;
    }
    Vec3 t;
    const bool through = refract(-p.wo, m, beyond.eta, &t) && glm::dot(t, p.ng) < 0.0f;
    if (!through) {
      t = reflect(-p.wo, m);  // total internal reflection at this facet
      if (glm::dot(t, p.ng) <= 0.0f) continue;
    }
    float lobe = ggx_transmission_weight(cos_o, glm::dot(p.ns, t), p.alpha, p.it.material->masking);
    if (through && fresnel && kept > 0.0f) {
      lobe *= (1.0f - fresnel_exact(std::max(0.0f, glm::dot(p.wo, m)), beyond.eta)) / kept;
    }
    // No feeler reaches an emitter through glass: what these rays meet counts whole.
    const Drawn drawn{strata.share, hash3(state.seed, static_cast<uint32_t>(k), 0x7463u),
                      strata.index(k), 0.0f};
    const Color brought =
        branch(spawn_ray(p.it.position, p.it.position_error, p.it.geometric_normal, p.it.time, t,
                         through ? kRefractionRay : kReflectionRay),
               sigma_t * lobe, through ? beyond.media : state.media, drawn);
    mean += (lobe * strata.share) * brought;
  }
  return mean;
}

}  // namespace whitted
