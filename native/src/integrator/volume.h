// Homogeneous participating media (issue 48; Kajiya and Von Herzen 1984, single
// scattering as Cycles renders it with Volume Bounces 0): a material's constant volume
// coefficients (Material::volume_*) fill the meshes it covers. A ray's segment inside one,
// from its origin to the next hit (or the world), lets exp(-sigma_t d) of what lies beyond
// through, and adds what the medium scatters towards it from each lamp, emissive mesh and
// the world light (a distance drawn along the segment, a feeler to the light weighed by the
// Henyey-Greenstein phase) and what it emits. The medium of a segment is the MediumStack's current
// one (medium.h): the bounds of a medium without a surface are entered and left in the kernel's
// trace() (kernel.h), glass with a volume by the refraction's crossing. Shadow feelers carry the
// transmittance of the media they cross (media_transmittance). Only in scenes the
// analysis finds media in (kVolumeEffect); the others never reach this file.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include "core/limits.h"
#include "core/math.h"
#include "core/ray.h"
#include "integrator/glow.h"
#include "integrator/kernel_inputs.h"
#include "integrator/ray_tree.h"
#include "integrator/shadow.h"
#include "integrator/strata.h"
#include "integrator/transmittance.h"
#include "scene/light.h"
#include "scene/mesh_light.h"
#include "scene/world_light.h"

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

// What of the light arriving at x = r(drawn.t) from direction wi the medium sends back
// towards r's origin, per unit of that light, before its feeler: T(t) sigma_s phase / pdf(t).
inline Color scattered_share(const Medium& m, const Ray& r, const DrawnDistance& drawn,
                             const Vec3& wi) {
  const float phase = henyey_greenstein(glm::dot(wi, r.direction), m.anisotropy);
  return transmittance(m.extinction(), drawn.t) * m.scattering * (phase / drawn.pdf);
}

// What a feeler from a point in the medium lets through to its light (shadow.h), counted.
template <uint32_t kEffects, class Queries>
Color volume_feeler(const KernelInputs<kEffects, Queries>& in, const Ray& feeler,
                    uint64_t shadow_sets, int depth, RayCounts* counts) {
  Blockers storage;
  const Blockers* linked = blockers(in.scene, shadow_sets, &storage);
  counts->volume_feelers += 1;
  return shadow_transmittance(in, feeler, in.queries.occluded(first_query(in, feeler), linked),
                              linked, depth, counts);
}

// The feeler from x, a point in a medium, to a lamp's sample `ls`: short of the lamp by
// kShadowRayShortening, to infinity for the sun.
inline Ray lamp_feeler(const Vec3& x, const LightSample& ls, float time) {
  const float t_max =
      std::isinf(ls.distance) ? kInfinity : ls.distance * (1.0f - limits::kShadowRayShortening);
  return {x, ls.wi, 0.0f, t_max, kShadowRay, time};
}

// A segment [0, length] of a ray inside a medium of constant coefficients, as the loops
// that scatter light along it ask of it (heterogeneous.h's MarchedSegment answers the same
// for a marched one): how far it reaches, a distance drawn by its transmittance (the
// channels' mean extinction), and what of the light arriving at a drawn distance from
// direction wi it sends back towards the ray's origin (scattered_share).
struct ConstantSegment {
  const Medium& m;
  float length;
  float sigma;

  ConstantSegment(const Medium& medium, float l)
      : m(medium),
        length(l),
        sigma((medium.extinction().x + medium.extinction().y + medium.extinction().z) / 3.0f) {}
  float reach() const { return length; }
  DrawnDistance drawn(float u) const { return by_transmittance(length, sigma, u); }
  Color share(const Ray& r, const DrawnDistance& at, const Vec3& wi) const {
    return scattered_share(m, r, at, wi);
  }
};

// The draws of a light sampled from points along a segment (the emitters', the world's):
// n x n points of the light (`light`, Emitter Samples a side), each seen from its own point
// of the segment, drawn by transmittance (the first number of `along`'s point, the
// segment's drawn(); its second is free for the light's use).
struct SegmentDraws {
  Strata light;
  Strata along;

  SegmentDraws(const NodeState& state, int samples, uint32_t salt, bool sobol)
      : light(state, samples, salt, sobol), along(state, samples, salt ^ 0x9e3779b9u, sobol) {}
};

// The single scattering of the emissive meshes' light along a segment (the surfaces'
// emitter feelers, lights.h, from points in the medium): Emitter Samples x Emitter Samples
// points drawn from the emitters' power table, each seen from its own distance along the
// segment, drawn by transmittance, with a feeler each. Out of line: only scenes with media
// and emitters call it.
template <uint32_t kEffects, class Queries, class Recorder, class Segment>
[[gnu::noinline]] Color scattered_emitters(const KernelInputs<kEffects, Queries>& in,
                                           Recorder& recorder, const Ray& r, const Segment& segment,
                                           const NodeState& state, int layer, RayCounts* counts) {
  const CompiledScene& scene = in.scene;
  const SegmentDraws draws(state, in.settings.emitter_samples,
                           0x766d6500u ^ static_cast<uint32_t>(layer),
                           jittered_samples(in.settings));
  Color radiance(0.0f);
  for (int k = 0; k < draws.light.count(); ++k) {
    const DrawnDistance drawn = segment.drawn(draws.along.point(k).x);
    if (!(drawn.pdf > 0.0f)) continue;
    const Vec3 x = r.origin + drawn.t * r.direction;
    const glm::vec2 u = draws.light.point(k);
    const MeshLights::Sample s = scene.mesh_lights->sample(scene, u.x, u.y, r.time);
    const Vec3 d = s.point - x;
    const float dist2 = glm::dot(d, d);
    const float dist = std::sqrt(dist2);
    if (!(dist > 0.0f)) continue;
    const Vec3 wi = d / dist;
    const Ray feeler{x, wi, 0.0f, dist * (1.0f - limits::kShadowRayShortening), kShadowRay, r.time};
    const auto emitter = static_cast<int32_t>(s.triangle.instance);
    if (!s.triangle.lights(-wi)) {  // a side it does not light
      recorder.unsent(recorder.scatter(feeler, Color(0.0f), -1, emitter, state.depth),
                      TreeCut::kBackfacing);
      continue;
    }
    // An emitter's patch lights x as an area light's: L cos_e / (d^2 density) / n^2.
    const float cos_e = std::fabs(glm::dot(wi, s.triangle.normal));
    const Ray towards{x, wi, 0.0f, dist, 0u, r.time};
    const Color emitted_radiance =
        emitted(scene, s.triangle, s.barycentric, towards, in.context(state));
    Color arriving = segment.share(r, drawn, wi) * emitted_radiance *
                     (cos_e * draws.light.share / (dist2 * s.density));
    const auto node = recorder.scatter(feeler, arriving, -1, emitter, state.depth);
    if (is_black(arriving)) {
      recorder.unsent(node, TreeCut::kUnlit);
      continue;
    }
    const Color through = volume_feeler(
        in, feeler, scene.instances[s.triangle.instance].links.shadow_sets, state.depth, counts);
    recorder.shadow(node, feeler, through);
    arriving *= through;
    radiance += arriving;
  }
  return radiance;
}

// The single scattering of the world's light along a segment (the surfaces' world feelers,
// lights.h, from points in the medium): Emitter Samples x Emitter Samples directions drawn
// by the world's importance map (and its sun disc), each seen from its own distance along
// the segment, drawn by transmittance, with a feeler to infinity each. A point in a medium
// has no surface to face: a world drawn by the cosine (one colour) is drawn about the ray's
// direction or its opposite, one of the two by a coin, over the whole sphere.
template <uint32_t kEffects, class Queries, class Recorder, class Segment>
[[gnu::noinline]] Color scattered_world(const KernelInputs<kEffects, Queries>& in,
                                        Recorder& recorder, const Ray& r, const Segment& segment,
                                        const NodeState& state, int layer, RayCounts* counts) {
  const WorldLight& light = *in.world;
  const SegmentDraws draws(state, in.settings.emitter_samples,
                           0x76776c00u ^ static_cast<uint32_t>(layer),
                           jittered_samples(in.settings));
  Color radiance(0.0f);
  for (int k = 0; k < draws.light.count(); ++k) {
    const DrawnDistance drawn = segment.drawn(draws.along.point(k).x);
    if (!(drawn.pdf > 0.0f)) continue;
    const Vec3 x = r.origin + drawn.t * r.direction;
    const Vec3 n = draws.along.point(k).y < 0.5f ? r.direction : -r.direction;
    for (int technique = 0; technique < light.techniques(); ++technique) {
      const WorldLight::Sample s = light.sample(draws.light.point(k), n, technique);
      counts->world_feelers += 1;
      if (!(s.pdf > 0.0f)) continue;
      const float pdf = 0.5f * (light.pdf(s.wi, n) + light.pdf(s.wi, -n));
      const Color world_radiance = in.scene.world_light_radiance(s.wi, state.depth + 1);
      Color arriving = segment.share(r, drawn, s.wi) * world_radiance * (draws.light.share / pdf);
      const Ray feeler{x, s.wi, 0.0f, kInfinity, kShadowRay, r.time};
      const auto node = recorder.scatter(feeler, arriving, -1, -1, state.depth);
      if (is_black(arriving)) {
        recorder.unsent(node, TreeCut::kUnlit);
        continue;
      }
      const Color through = volume_feeler(in, feeler, kAllLightSets, state.depth, counts);
      recorder.shadow(node, feeler, through);
      arriving *= through;
      radiance += arriving;
    }
  }
  return radiance;
}

// The single scattering of the glowing media's light along a segment (the surfaces' glow
// feelers, lights.h, from points in the medium; glow.h): for each glowing object
// Emitter Samples x Emitter Samples directions in the cone of its sphere, each seen from
// its own distance along the segment, drawn by transmittance, and marched (glow_along).
// A fire's smoke scatters its own flames' light so. Out of line: only scenes with glowing
// media call it.
template <uint32_t kEffects, class Queries, class Recorder, class Segment>
[[gnu::noinline]] Color scattered_glow(const KernelInputs<kEffects, Queries>& in,
                                       Recorder& recorder, const Ray& r, const Segment& segment,
                                       const NodeState& state, int layer, RayCounts* counts) {
  const std::vector<CompiledScene::Glow>& glowing = in.scene.glowing;
  Color radiance(0.0f);
  for (size_t object = 0; object < glowing.size(); ++object) {
    const CompiledScene::Glow& g = glowing[object];
    const SegmentDraws draws(
        state, in.settings.emitter_samples,
        0x76676c00u ^ (static_cast<uint32_t>(object) << 8) ^ static_cast<uint32_t>(layer),
        jittered_samples(in.settings));
    for (int k = 0; k < draws.light.count(); ++k) {
      const DrawnDistance drawn = segment.drawn(draws.along.point(k).x);
      if (!(drawn.pdf > 0.0f)) continue;
      const Vec3 x = r.origin + drawn.t * r.direction;
      const Vec3 wi = GlowCone(g, x).draw(draws.light.point(k));
      const Color share = segment.share(r, drawn, wi);
      if (is_black(share)) continue;  // a marched step that scatters nothing
      const Ray feeler{x, wi, 0.0f, kInfinity, kShadowRay, r.time};
      const GlowArriving glow = glow_along(in, feeler, state.depth + 1, counts);
      const Color arriving = share * glow.radiance * draws.light.share;
      recorder.scatter(Ray{x, wi, 0.0f, glow.distance, kShadowRay, r.time}, arriving, -1,
                       static_cast<int32_t>(g.instance), state.depth);
      radiance += arriving;
    }
  }
  return radiance;
}

// The light of every lamp, emissive mesh, the world and glowing medium that `segment` of ray r (its
// medium's coefficients, ConstantSegment or a MarchedSegment) scatters once towards r's
// origin: integral of T(t) sigma_s phase E(x(t)) S(x(t)) dt (E a light's irradiance at
// x(t), S what its feeler lets through; each feeler told to the recorder), estimated from
// one distance per light sample (a sized lamp's n x n, each with its own): equiangular
// towards a lamp with a place, by transmittance towards the sun, the emitters and the
// world. The distances are the camera sample's draws (Strata: a chain of the pixel's Sobol
// points, or a stratum placed by the sample's seed), `layer` telling a ray's segments
// apart, so threads and tiles change nothing.
template <uint32_t kEffects, class Queries, class Recorder, class Segment>
Color scattered_lights(const KernelInputs<kEffects, Queries>& in, Recorder& recorder, const Ray& r,
                       const Segment& segment, const NodeState& state, int layer,
                       RayCounts* counts) {
  const CompiledScene& scene = in.scene;
  Color scattered(0.0f);
  for (const Light& light : scene.lights) {
    if (state.depth > light.max_bounces) continue;  // past its Max Bounces
    const auto index = static_cast<uint32_t>(&light - scene.lights.data());
    const Strata strata(state, light.sized() ? light.samples : 1,
                        0x766f6c00u ^ (index << 8) ^ static_cast<uint32_t>(layer),
                        jittered_samples(in.settings));
    for (int k = 0; k < strata.count(); ++k) {
      const float u = strata.point(k).x;
      const DrawnDistance drawn = light.type == LightType::kSun
                                      ? segment.drawn(u)
                                      : equiangular(r, segment.reach(), light.position, u);
      if (!(drawn.pdf > 0.0f)) continue;
      const Vec3 x = r.origin + drawn.t * r.direction;
      const LightSample ls = sample_light(light, x, k);
      const Ray feeler = lamp_feeler(x, ls, r.time);
      const auto lamp = static_cast<int32_t>(index);
      if (is_black(ls.irradiance)) {  // outside a spot's cone, behind an area light
        recorder.unsent(recorder.scatter(feeler, Color(0.0f), lamp, -1, state.depth),
                        TreeCut::kUnlit);
        continue;
      }
      const Color share = segment.share(r, drawn, ls.wi);
      if (is_black(share)) continue;  // a marched step that scatters nothing
      Color arriving = share * ls.irradiance;
      const auto node = recorder.scatter(feeler, arriving, lamp, -1, state.depth);
      if (light.cast_shadows) {
        const Color through = volume_feeler(in, feeler, light.shadow_sets, state.depth, counts);
        recorder.shadow(node, feeler, through);
        arriving *= through;
      }
      scattered += arriving;
    }
  }
  if (in.emitters) scattered += scattered_emitters(in, recorder, r, segment, state, layer, counts);
  if (in.lit_by_world(state.depth)) {
    scattered += scattered_world(in, recorder, r, segment, state, layer, counts);
  }
  if (!scene.glowing.empty()) {
    scattered += scattered_glow(in, recorder, r, segment, state, layer, counts);
  }
  return scattered;
}

// What the medium `m` sends back along a segment [0, length] of ray r (length may be
// infinite), seen from r's origin, and lets through, exp(-sigma_t length): its emission,
// integral of T(t) e dt = e (1 - T(length)) / sigma_t, and the light it scatters once
// (scattered_lights). Out of line: only scenes with media call it.
template <uint32_t kEffects, class Queries, class Recorder>
[[gnu::noinline]] SegmentLight segment_radiance(const KernelInputs<kEffects, Queries>& in,
                                                Recorder& recorder, const Ray& r, float length,
                                                const Medium& m, const NodeState& state, int layer,
                                                RayCounts* counts) {
  const Color sigma_t = m.extinction();
  SegmentLight out;
  out.emitted = medium_emission(m.emission, sigma_t, length);
  out.transmittance = transmittance(sigma_t, length);
  if (is_black(m.scattering)) return out;
  out.scattered =
      scattered_lights(in, recorder, r, ConstantSegment(m, length), state, layer, counts);
  return out;
}

}  // namespace whitted
