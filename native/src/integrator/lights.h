// The local term: the surface's emission, its ambient term, and the light it receives
// from each lamp, emissive mesh (emitter), the world and glowing medium through their
// samples, each a Phong sum (local.h) gated by its shadow feeler (shadow.h). Where a
// feeler goes is the kernel's policy (kernel.h): traced now in the recursion, queued in a
// wave (wave.h).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "core/limits.h"
#include "core/math.h"
#include "core/ray.h"
#include "integrator/glow.h"
#include "integrator/kernel_inputs.h"
#include "integrator/local.h"
#include "integrator/mis.h"
#include "integrator/shading_point.h"
#include "integrator/shadow.h"
#include "integrator/strata.h"
#include "scene/light.h"
#include "scene/mesh_light.h"
#include "scene/world_light.h"

namespace whitted {

// A light sample's feeler as the kernel sends it: whether its light casts shadows, how
// many samples share the light (pruning judges the whole light), and, for the
// inspector, the lamp (CompiledScene::lights) or emitter (instances) it goes to.
struct Feeler {
  bool cast_shadows;
  int samples;
  int32_t light;
  int32_t emitter;
  bool diffuse = true;  // its light's ray visibility (Light::diffuse, Light::glossy)
  bool glossy = true;
  uint64_t shadow_sets = kAllLightSets;  // the shadow sets that block it (light.h)
};

// One sample of a light: its feeler, what arrives, and the MIS weight of its glossy share.
struct Drawing {
  Feeler feeler;
  LightSample sample;
  LobeWeights mis;
};

// A light sample between its Phong terms and its shadow feeler's answer.
struct PreparedSample {
  LightTerms t;
  Color irradiance;
  Color unshadowed;      // its share of the local term if all of it arrives
  Ray feeler;            // the shadow ray, when `sends_feeler` (else all of it arrives)
  uint64_t shadow_sets;  // the shadow sets that may block it (Feeler::shadow_sets)
  bool dark;             // pruned: it adds nothing
  bool sends_feeler;
};

// The local term of one kernel (kernel.h), made for each surface it shades: the
// kernel's inputs, its recorder (told each sample's terms) and its policy.
template <uint32_t kEffects, class Recorder, class Queries, class Policy>
class Lights {
 public:
  using Inputs = KernelInputs<kEffects, Queries>;
  Lights(const Inputs& in, Recorder& recorder, const Policy& policy)
      : in_(in), recorder_(recorder), policy_(policy) {}

  // The local term: the surface's emission and its Phong shading, over the light samples i
  // (E_i the irradiance of sample i, S_i what its shadow ray lets through),
  //   (1 - coat) * [Ia*ka*kd + sum_i S_i * (kd/pi + ks*(f+2)/(2pi)*(v.r)^f) * E_i * (l.n)]
  //   + sum_i S_i * coat_highlight_i * E_i.
  // The recorder is told each sample's terms as its light arrives, then the surface's
  // emission, ambient term and sum.
  // The emissive meshes are lights too (emitters); `seen` is what of the surface's own
  // emission this ray counts (emission_weight), `rays` the glossy rays it will send.
  Color local(const ShadingPoint& p, const GlossyRays& rays, float seen, const NodeState& state,
              RayCounts* counts) const {
    const CompiledScene& scene = in_.scene;
    const SurfaceParams& surface = p.surface;
    const Color emission = surface.emission * seen;
    const Color ambient = p.base * p.it.material->ambient * scene.ambient * surface.diffuse;
    Color phong = ambient;
    const uint32_t receiver = scene.instances[p.it.instance].links.light_set;
    for (const Light& light : scene.lights) {
      if (state.depth > light.max_bounces) continue;       // past its Max Bounces
      if (!in_sets(light.light_sets, receiver)) continue;  // not linked to this surface
      const int samples = light.sample_count();
      const Feeler feeler{light.cast_shadows,
                          samples,
                          static_cast<int32_t>(&light - scene.lights.data()),
                          -1,
                          light.diffuse,
                          light.glossy,
                          light.shadow_sets};
      // Where a sized lamp's n x n feelers go (sample_light): at its strata's centres, the
      // same for every camera sample (the seed's lattice), unless the camera samples are
      // Monte Carlo ones (jittered_samples, settings.h); then at the chain's points of this
      // lamp (ChainPoints, strata.h), so that many camera samples of one feeler each
      // integrate the lamp (Cook 1984), stratified across the pixel's samples.
      const bool sobol = jittered_samples(in_.settings);
      const ChainPoints points(state, 0x6c616d00u + static_cast<uint32_t>(feeler.light), samples);
      // Where the glossy rays see its shape, their lobe's share of each feeler is weighed
      // against them (MIS: lamp_weight).
      const bool weighed =
          rays.drawn > 0.0f && (light.visibility & kReflectionRay) != 0 && light.has_shape();
      const auto draw = [&](int s) {
        glm::vec2 at;
        if (sobol) at = points.point(s);
        Drawing out{feeler, sample_light(light, p.it.position, s, sobol ? &at : nullptr), {}};
        if (weighed) {
          out.mis = lobe_weights(rays, rays.drawn, static_cast<float>(samples) * out.sample.density,
                                 p.wo, out.sample.wi);
        }
        return out;
      };
      feelers(p, samples, draw, state, counts, &phong);
    }
    if (in_.emitters) emitters(p, rays, state, counts, &phong);
    if (in_.lit_by_world(state.depth)) world(p, rays, state, counts, &phong);
    if (in_.has(kVolumeEffect) && !scene.glowing.empty()) glow(p, state, counts, &phong);
    const Color radiance = emission + phong;
    recorder_.local(p, state.depth, emission, ambient, radiance);
    return radiance;
  }

 private:
  // Adds the shares of `samples` light samples, draw(s) for s in order, to *phong one by
  // one, as light_sample's are; in a wave (Policy::kQueues), queues their feelers. A
  // single feeler, or those of different lights, trace faster one at a time
  // (docs/notes/performance_reading.md), and the inspector records each alone; the
  // feelers of a sized light leave one point for one small region of space: they go to
  // Embree as packets of up to kFeelerBatch (the same sum to the bit).
  template <class Draw>
  void feelers(const ShadingPoint& p, int samples, const Draw& draw, const NodeState& state,
               RayCounts* counts, Color* phong) const {
    if constexpr (Policy::kQueues) {
      for (int s = 0; s < samples; ++s) queue_sample(p, draw(s), state, counts, phong);
    } else if (!Recorder::kBatchesFeelers || samples == 1) {
      for (int s = 0; s < samples; ++s) *phong += light_sample(p, draw(s), state, counts);
    } else {
      std::array<PreparedSample, kFeelerBatch> batch;
      for (int first = 0; first < samples; first += kFeelerBatch) {
        const int n = std::min(kFeelerBatch, samples - first);
        for (int k = 0; k < n; ++k) {
          // No node: a recorder that lets feelers batch keeps none of them.
          prepare_sample(p, draw(first + k), state, counts, typename Recorder::Node{},
                         &batch[static_cast<size_t>(k)]);
        }
        sum_batch(p, batch.data(), n, state, counts, phong);
      }
    }
  }

  // The feelers to the emissive meshes: n x n samples of their power table (drawn as
  // glossy rays are: Strata), each a point on a triangle lighting p as a patch
  // of an area light, E = L cos_e / (d^2 density) / n^2. The glossy share of each is
  // weighed against the glossy rays that may meet the same point (MIS; emission_weight).
  // Out of line, and light_sample and prepare_sample always inlined: as GCC chose, the
  // lamps' feelers went through calls that cost a scene without emitters 6% more of
  // Whitted's own instructions (85.2 M before emitters, 90.5 M; now 88.3 M: callgrind,
  // python -m whitted_tools.builds --small).
  [[gnu::noinline]] void emitters(const ShadingPoint& p, const GlossyRays& rays,
                                  const NodeState& state, RayCounts* counts, Color* phong) const {
    const CompiledScene& scene = in_.scene;
    const MeshLights& lights = *scene.mesh_lights;
    const Strata strata(state, in_.settings.emitter_samples, 0x656du,
                        jittered_samples(in_.settings));
    const uint32_t receiver = scene.instances[p.it.instance].links.light_set;
    const auto draw = [&](int k) {
      const glm::vec2 u = strata.point(k);
      // Where the emitter is at the shading point's time (a moving one's place then).
      const MeshLights::Sample s = lights.sample(scene, u.x, u.y, p.it.time);
      const EmissiveTriangle& triangle = s.triangle;
      const InstanceLinks& links = scene.instances[triangle.instance].links;
      Drawing out{{true, strata.count(), -1, static_cast<int32_t>(triangle.instance), true, true,
                   links.shadow_sets},
                  {Vec3(0.0f, 0.0f, 1.0f), 0.0f, Color(0.0f)},
                  {}};
      if (!in_sets(links.light_sets, receiver)) return out;  // not linked to this surface
      // From where the feeler leaves (on a smooth mesh lifted off the facet, towards
      // the curved surface): measured from the facet, the feeler would reach past the
      // sample and the emitter would block its own light.
      const Vec3 d = s.point - p.it.shadow_origin;
      const float dist2 = glm::dot(d, d);
      const float dist = std::sqrt(dist2);
      if (!(dist > 0.0f)) return out;
      out.sample.wi = d / dist;
      out.sample.distance = dist;
      if (!triangle.lights(-out.sample.wi)) return out;  // a side it does not light
      // Behind the surface it adds nothing: its emission (a program's, perhaps) unread.
      if (glm::dot(p.ns, out.sample.wi) <= 0.0f) return out;
      const float cos_e = std::fabs(glm::dot(out.sample.wi, triangle.normal));
      const Ray towards{p.it.shadow_origin, out.sample.wi, 0.0f, dist, 0u, p.it.time};
      const Color radiance = emitted(scene, triangle, s.barycentric, towards, in_.context(state));
      out.sample.irradiance = radiance * (cos_e * strata.share / (dist2 * s.density));
      if (rays.count > 0.0f) {
        out.mis = lobe_weights(rays, rays.count, s.density * dist2 / cos_e, p.wo, out.sample.wi);
      }
      return out;
    };
    feelers(p, strata.count(), draw, state, counts, phong);
  }

  // The feelers to the world as a light (scene/world_light.h): n x n directions drawn by
  // its importance map, and as many over a sky's sun disc (n = Emitter Samples at the
  // first glossy hit and before, as the emitter feelers'), each bringing the world's
  // radiance there over the techniques' summed density, E = L / (pdf n^2), for the Phong sum to
  // weigh by (l.n) as any light's irradiance. A shadow feeler to infinity decides what arrives. The
  // glossy share is weighed against the glossy rays that escape the same way (MIS; their
  // NodeState::world_weight).
  [[gnu::noinline]] void world(const ShadingPoint& p, const GlossyRays& rays,
                               const NodeState& state, RayCounts* counts, Color* phong) const {
    const WorldLight& light = *in_.world;
    const WorldLightParams& params = light.params();
    const Strata strata(state, in_.settings.emitter_samples, 0x776cu,
                        jittered_samples(in_.settings));
    // Each stratum's point gives one direction per technique (the map, a sun disc).
    const int count = strata.count() * light.techniques();
    const auto draw = [&](int k) {
      const WorldLight::Sample s =
          light.sample(strata.point(k % strata.count()), p.ns, k / strata.count());
      Drawing out{{true, count, -1, -1, params.diffuse, params.glossy, kAllLightSets},
                  {s.wi, kInfinity, Color(0.0f)},
                  {}};
      counts->world_feelers += 1;
      // Behind the surface it adds nothing: the world's program unread.
      if (!(s.pdf > 0.0f) || glm::dot(p.ns, s.wi) <= 0.0f) return out;
      const Color radiance = in_.scene.world_light_radiance(s.wi, state.depth + 1);
      out.sample.irradiance = radiance * (strata.share / s.pdf);
      if (rays.count > 0.0f && params.glossy) {
        out.mis = lobe_weights(rays, rays.count, s.pdf, p.wo, s.wi);
      }
      return out;
    };
    feelers(p, count, draw, state, counts, phong);
  }

  // The feelers to glowing media (CompiledScene::glowing): a medium's emission lights
  // surfaces, as Cycles' diffuse rays gather it even with no bounce. For each glowing
  // object n x n directions (n = Emitter Samples, as the emitter feelers') uniform in the
  // cone of its sphere, each bringing what glow_along finds (its march is its shadow
  // feeler). The GGX lobe's share is left to the glossy rays, which meet the same glow
  // (mis 0).
  [[gnu::noinline]] void glow(const ShadingPoint& p, const NodeState& state, RayCounts* counts,
                              Color* phong) const {
    const std::vector<CompiledScene::Glow>& glowing = in_.scene.glowing;
    const Strata strata(state, in_.settings.emitter_samples, 0x676cu,
                        jittered_samples(in_.settings));
    const int count = strata.count() * static_cast<int>(glowing.size());
    const Vec3& origin = p.it.shadow_origin;
    const auto draw = [&](int k) {
      const CompiledScene::Glow& g = glowing[static_cast<size_t>(k / strata.count())];
      Drawing out{{false, count, -1, static_cast<int32_t>(g.instance), true, true, kAllLightSets},
                  {Vec3(0.0f, 0.0f, 1.0f), 0.0f, Color(0.0f)},
                  {0.0f, 0.0f, 0.0f}};
      const Vec3 wi = GlowCone(g, origin).draw(strata.point(k % strata.count()));
      out.sample.wi = wi;
      // Behind the surface it adds nothing: no march.
      if (glm::dot(p.ns, wi) <= 0.0f) return out;
      const Ray feeler = spawn_ray(origin, p.it.position_error, p.ng, p.it.time, wi, kShadowRay);
      const GlowArriving glow = glow_along(in_, feeler, state.depth + 1, counts);
      out.sample.distance = glow.distance;
      out.sample.irradiance = glow.radiance * strata.share;
      return out;
    };
    feelers(p, count, draw, state, counts, phong);
  }

  // A light sample in a wave: its share added now if no feeler is sent, else its feeler
  // queued (Policy::feeler), which adds its share once the feeler's answer is known, with
  // what the recorder needs then (Recorder::queued).
  [[gnu::flatten]] void queue_sample(const ShadingPoint& p, const Drawing& drawing,
                                     const NodeState& state, RayCounts* counts,
                                     Color* phong) const {
    PreparedSample prepared;
    prepare_sample(p, drawing, state, counts, typename Recorder::Node{}, &prepared);
    if (prepared.dark) return;
    if (!prepared.sends_feeler) {
      *phong += arrived(p, prepared, Color(1.0f));
      return;
    }
    policy_.feeler(first_query(in_, prepared.feeler), prepared.unshadowed, prepared.shadow_sets,
                   drawing.feeler.light, state.depth,
                   recorder_.queued(p, prepared.t, prepared.irradiance, state.depth));
  }

  // One light sample's share of the local term: its Phong terms, unshadowed, times what
  // its shadow ray lets through; nothing when pruning finds it cannot light the point.
  [[gnu::always_inline]] Color light_sample(const ShadingPoint& p, const Drawing& drawing,
                                            const NodeState& state, RayCounts* counts) const {
    const auto node = recorder_.feeler(p.it, drawing.sample, drawing.feeler.light,
                                       drawing.feeler.emitter, state.depth);
    PreparedSample prepared;
    prepare_sample(p, drawing, state, counts, node, &prepared);
    if (prepared.dark) return Color(0.0f);
    Color transmittance(1.0f);
    if (prepared.sends_feeler) {
      const Ray& ray = prepared.feeler;
      Blockers storage;
      const Blockers* linked = blockers(in_.scene, prepared.shadow_sets, &storage);
      transmittance =
          shadow_transmittance(in_, ray, in_.queries.occluded(first_query(in_, ray), linked),
                               linked, state.depth, counts);
      recorder_.shadow(node, ray, transmittance);
    }
    return arrived(p, prepared, transmittance);
  }

  // Everything of a light sample up to its shadow feeler: the pruning decisions, the
  // unshadowed Phong terms, and the feeler, if one is sent.
  [[gnu::always_inline]] void prepare_sample(const ShadingPoint& p, const Drawing& drawing,
                                             const NodeState& state, RayCounts* counts,
                                             typename Recorder::Node node,
                                             PreparedSample* out) const {
    const LightSample& ls = drawing.sample;
    out->shadow_sets = drawing.feeler.shadow_sets;
    // The shading normal decides whether a light is behind the (smooth) surface, not the
    // flat facet: gating on the facet draws stair-steps along the terminator of a coarse
    // smooth mesh.
    const float cos_l = glm::dot(p.ns, ls.wi);
    out->dark = in_.has(kPruningEffect) && dark(cos_l, ls, node, counts);
    out->sends_feeler = false;
    if (out->dark) return;
    out->t = light_terms(p, ls.wi, cos_l);
    if (drawing.mis.weighs()) weigh_glossy(p, ls.wi, drawing.mis, &out->t);
    if (!drawing.feeler.diffuse || !drawing.feeler.glossy) {
      unseen(drawing.feeler.diffuse, drawing.feeler.glossy, &out->t);
    }
    out->irradiance = ls.irradiance;
    out->unshadowed = unshadowed(p, out->t, ls.irradiance);
    recorder_.unshadowed(node, p, out->t, ls);
    out->sends_feeler = shadow(p, drawing.feeler, ls, out->unshadowed, state, counts, &out->feeler);
  }

  // The pruning decision (kPruningEffect) before any term is computed: a light sample
  // behind the surface or sending no light here adds nothing and needs no shadow ray.
  bool dark(float cos_l, const LightSample& ls, typename Recorder::Node node,
            RayCounts* counts) const {
    if (cos_l <= 0.0f) {
      counts->shadow_rays_skipped.backfacing += 1;
      recorder_.unsent(node, TreeCut::kBackfacing);
      return true;
    }
    if (is_black(ls.irradiance)) {
      counts->shadow_rays_skipped.unlit += 1;  // outside a spot's cone, behind an area light
      recorder_.unsent(node, TreeCut::kUnlit);
      return true;
    }
    return false;
  }

  // Whether a light sample's shadow ray is sent, and which (*ray). None is sent, and all
  // of the light arrives, for a light that casts no shadows, or when pruning finds that
  // the light, lit or not, cannot change the pixel by the cutoff.
  // Flattened: with two callers of prepare_sample, GCC stopped inlining spawn_ray here,
  // which cost the one-sample path about 1% (callgrind, whitted_tools.builds --small). Always
  // inlined: with the recorders' hooks, GCC kept it out of the pass kernel, which cost a
  // passes render of the demo scene 1.1% more of whitted_native's instructions (callgrind).
  [[gnu::flatten, gnu::always_inline]] bool shadow(const ShadingPoint& p, const Feeler& feeler,
                                                   const LightSample& ls, const Color& unshadowed,
                                                   const NodeState& state, RayCounts* counts,
                                                   Ray* ray) const {
    if (!in_.has(kShadowEffect) || !feeler.cast_shadows) return false;
    if (in_.has(kPruningEffect)) {
      // The whole light is judged, not this sample's share of it: otherwise more samples
      // would each fall below the cutoff and soft shadows would fade.
      const float whole_light = static_cast<float>(feeler.samples);
      if (max_component(state.weight * unshadowed) * whole_light < in_.settings.cutoff) {
        counts->shadow_rays_skipped.cutoff += 1;
        return false;
      }
    }
    // Stop the shadow ray just short of the light sample.
    const float t_max =
        std::isinf(ls.distance) ? kInfinity : ls.distance * (1.0f - limits::kShadowRayShortening);
    *ray = spawn_ray(p.it.shadow_origin, p.it.position_error, p.ng, p.it.time, ls.wi, kShadowRay,
                     t_max);
    return true;
  }

  // What a prepared sample adds to the local term once `transmittance` of it arrives.
  Color arrived(const ShadingPoint& p, const PreparedSample& prepared,
                const Color& transmittance) const {
    recorder_.arrived(p, prepared.t, prepared.irradiance * transmittance);
    return prepared.unshadowed * transmittance;
  }

  // Traces the feelers of `n` prepared samples, as one packet when there are several, and
  // adds the samples' shares to *phong in their order.
  void sum_batch(const ShadingPoint& p, const PreparedSample* batch, int n, const NodeState& state,
                 RayCounts* counts, Color* phong) const {
    std::array<Ray, kFeelerBatch> rays;
    std::array<bool, kFeelerBatch> blocked;
    int feelers = 0;
    // One packet has one set of blockers: the emitters' feelers of a batch may differ
    // under shadow linking, and then go one by one.
    bool shared = true;
    for (int i = 0; i < n; ++i) {
      if (batch[i].sends_feeler) {
        rays[static_cast<size_t>(feelers++)] = first_query(in_, batch[i].feeler);
        shared = shared && batch[i].shadow_sets == batch[0].shadow_sets;
      }
    }
    Blockers storage;
    const Blockers* linked = blockers(in_.scene, batch[0].shadow_sets, &storage);
    if (feelers == 1 || (feelers > 1 && !shared)) {
      for (int i = 0, f = 0; i < n; ++i) {
        if (!batch[i].sends_feeler) continue;
        Blockers own;
        blocked[static_cast<size_t>(f)] = in_.queries.occluded(
            rays[static_cast<size_t>(f)], blockers(in_.scene, batch[i].shadow_sets, &own));
        ++f;
      }
    }
    if (feelers > 1 && shared) {
      in_.queries.occluded_packet(rays.data(), feelers, blocked.data(), linked);
    }
    int feeler = 0;
    for (int i = 0; i < n; ++i) {
      const PreparedSample& prepared = batch[i];
      if (prepared.dark) {
        *phong += Color(0.0f);  // as light_sample's share: a -0 sum becomes +0
        continue;
      }
      Color transmittance(1.0f);
      if (prepared.sends_feeler) {
        const bool first_blocked = blocked[static_cast<size_t>(feeler++)];
        Blockers own;
        transmittance = shadow_transmittance(in_, prepared.feeler, first_blocked,
                                             blockers(in_.scene, prepared.shadow_sets, &own),
                                             state.depth, counts);
      }
      *phong += arrived(p, prepared, transmittance);
    }
  }

  const Inputs& in_;
  Recorder& recorder_;
  const Policy& policy_;
};

}  // namespace whitted
