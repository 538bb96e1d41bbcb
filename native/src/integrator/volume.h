// Homogeneous participating media (issue 48; Kajiya and Von Herzen 1984, single
// scattering as Cycles renders it with Volume Bounces 0): a material's constant volume
// coefficients (Material::volume_*) fill the meshes it covers. A ray's segment inside one,
// from its origin to the next hit (or the world), lets exp(-sigma_t d) of what lies beyond
// through, and adds what the medium scatters towards it from each lamp (a distance drawn
// along the segment, a feeler to the lamp weighed by the Henyey-Greenstein phase) and what
// it emits. The medium of a segment is the MediumStack's current one (medium.h): the
// bounds of a medium without a surface are entered and left in the kernel's trace()
// (kernel.h), glass with a volume by the refraction's crossing. Shadow feelers carry the
// transmittance of the media they cross (media_transmittance). Only in scenes the
// analysis finds media in (kVolumeEffect); the others never reach this file.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include "core/limits.h"
#include "core/math.h"
#include "core/ray.h"
#include "integrator/kernel_inputs.h"
#include "integrator/shadow.h"
#include "integrator/strata.h"
#include "integrator/transmittance.h"
#include "scene/light.h"

namespace whitted {

// The Henyey-Greenstein phase function (per steradian) for light arriving from direction
// wi scattered on along `d`, the ray's direction (towards its origin), cos = wi . d: g > 0
// scatters forwards, light keeping its way (looking into a lamp through fog, cos = 1).
inline float henyey_greenstein(float cos_theta, float g) {
  const float denominator = 1.0f + g * g - 2.0f * g * cos_theta;
  return (1.0f - g * g) / (4.0f * kPi * denominator * std::sqrt(denominator));
}

// A distance drawn along a segment [0, length] of a ray and its density per unit length
// (0: none drawn).
struct DrawnDistance {
  float t = 0.0f;
  float pdf = 0.0f;
};

// Equiangular sampling towards point c (Kulla and Fajardo 2012, "Importance Sampling
// Techniques for Path Tracing in Participating Media"): t with density proportional to
// 1 / |x(t) - c|^2, the falloff of a lamp at c, whose noise stays bounded near the lamp
// where a transmittance draw's does not. `length` may be infinite.
inline DrawnDistance equiangular(const Ray& r, float length, const Vec3& c, float u) {
  const Vec3 to_c = c - r.origin;
  const float delta = glm::dot(to_c, r.direction);  // where the ray passes closest to c
  const float d = std::sqrt(std::max(glm::dot(to_c, to_c) - delta * delta, 0.0f));
  if (!(d > 0.0f)) return {};  // a ray through c itself: the lamp is a point on it
  const float theta_a = std::atan2(-delta, d);
  const float theta_b = std::isinf(length) ? 0.5f * kPi : std::atan2(length - delta, d);
  if (!(theta_b > theta_a)) return {};
  const float t = std::clamp(delta + d * std::tan(theta_a + u * (theta_b - theta_a)), 0.0f, length);
  const float h = t - delta;
  return {t, d / ((theta_b - theta_a) * (d * d + h * h))};
}

// A distance drawn by transmittance (a scalar extinction `sigma`, the mean of the
// channels'), truncated to the segment; uniform where the segment is optically thin.
inline DrawnDistance by_transmittance(float length, float sigma, float u) {
  const float depth = sigma * length;
  if (!(depth > 1e-4f)) {
    if (std::isinf(length) || !(length > 0.0f)) return {};
    return {u * length, 1.0f / length};
  }
  const float kept = -std::expm1(-depth);  // 1 - exp(-sigma length), exactly for thin media
  const float t = std::min(-std::log1p(-u * kept) / sigma, length);
  return {t, sigma * std::exp(-sigma * t) / kept};
}

// What the medium `m` sends back along a segment [0, length] of ray r (length may be
// infinite), seen from r's origin: its emission, integral of T(t) e dt = e (1 - T(length)) /
// sigma_t, and the light of every lamp it scatters once, integral of T(t) sigma_s
// phase E(x(t)) S(x(t)) dt (E a lamp's irradiance at x(t), S what its feeler lets through),
// estimated from one distance per light sample (a sized lamp's n x n, each with its own):
// equiangular towards a lamp with a place, by transmittance towards the sun. The distances
// are the camera sample's draws (Strata: a chain of the pixel's Sobol points, or a
// stratum placed by the sample's seed), `layer` telling a ray's segments apart, so
// threads and tiles change nothing. Out of line: only scenes with media call it.
template <uint32_t kEffects, class Queries>
[[gnu::noinline]] Color segment_radiance(const KernelInputs<kEffects, Queries>& in, const Ray& r,
                                         float length, const Material& m, const NodeState& state,
                                         int layer, RayCounts* counts) {
  const Color sigma_t = extinction(m);
  Color radiance(0.0f);
  for (int i = 0; i < 3; ++i) {
    if (!(m.volume_emission[i] > 0.0f)) continue;
    if (sigma_t[i] > 0.0f) {
      radiance[i] += m.volume_emission[i] * -std::expm1(-sigma_t[i] * length) / sigma_t[i];
    } else if (std::isfinite(length)) {
      radiance[i] += m.volume_emission[i] * length;
    }
  }
  if (is_black(m.volume_scattering)) return radiance;
  const CompiledScene& scene = in.scene;
  const float sigma = (sigma_t.x + sigma_t.y + sigma_t.z) / 3.0f;
  for (const Light& light : scene.lights) {
    if (state.depth > light.max_bounces) continue;  // past its Max Bounces
    const auto index = static_cast<uint32_t>(&light - scene.lights.data());
    const Strata strata(state, light.sized() ? light.samples : 1,
                        0x766f6c00u ^ (index << 8) ^ static_cast<uint32_t>(layer),
                        jittered_samples(in.settings));
    Blockers storage;
    const Blockers* linked = blockers(scene, light.shadow_sets, &storage);
    for (int k = 0; k < strata.count(); ++k) {
      const float u = strata.point(k).x;
      const DrawnDistance drawn = light.type == LightType::kSun
                                      ? by_transmittance(length, sigma, u)
                                      : equiangular(r, length, light.position, u);
      if (!(drawn.pdf > 0.0f)) continue;
      const Vec3 x = r.origin + drawn.t * r.direction;
      const LightSample ls = sample_light(light, x, k);
      if (is_black(ls.irradiance)) continue;  // outside a spot's cone, behind an area light
      const float phase = henyey_greenstein(glm::dot(ls.wi, r.direction), m.volume_anisotropy);
      Color arriving = transmittance(sigma_t, drawn.t) * m.volume_scattering * (phase / drawn.pdf) *
                       ls.irradiance;
      if (light.cast_shadows) {
        const float t_max = std::isinf(ls.distance)
                                ? kInfinity
                                : ls.distance * (1.0f - limits::kShadowRayShortening);
        const Ray feeler{x, ls.wi, 0.0f, t_max, kShadowRay, r.time};
        counts->volume_feelers += 1;
        arriving *=
            shadow_transmittance(in, feeler, in.queries.occluded(first_query(in, feeler), linked),
                                 linked, state.depth, counts);
      }
      radiance += arriving;
    }
  }
  return radiance;
}

}  // namespace whitted
