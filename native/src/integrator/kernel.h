// The Whitted step (Whitted 1980, the lecture's RayTrace): along a ray through cut-outs
// (trace), the radiance a surface sends back, I = local + sigma_r * reflected +
// sigma_t * refracted (shade), and the one place the ray tree branches (branch). Each
// concept it calls is its own file: the media crossing (medium.h), the split of weights
// (split.h), the local term and its light samples (lights.h, local.h), MIS (mis.h), the
// glossy strata (glossy.h), the shadow feelers (shadow.h), the wave (wave.h).
//
// Chosen at compile time: the Recorder (kernel_recorder.h), told hook by hook what is
// traced and what each node adds (NoRecorder, whose empty hooks compile away, for renders
// without passes; PassRecorder, passes.h, with passes; TreeRecorder, tree_recorder.h, for
// the inspector); the Queries to Embree (whitted.cpp); the effects (kernel_inputs.h); and
// the Policy for what the step would trace next, a child ray or a feeler: Recurse traces
// it now, depth-first; wave.h's Enqueue appends it to a wave. whitted.cpp picks the
// kernel a render runs.
#pragma once

#include <cstdint>
#include <type_traits>

#include "core/limits.h"
#include "core/math.h"
#include "core/ray.h"
#include "integrator/catcher.h"
#include "integrator/glossy.h"
#include "integrator/heterogeneous.h"
#include "integrator/kernel_inputs.h"
#include "integrator/lights.h"
#include "integrator/medium.h"
#include "integrator/mis.h"
#include "integrator/ray_tree.h"
#include "integrator/shading_point.h"
#include "integrator/split.h"
#include "integrator/strata.h"
#include "integrator/volume.h"
#include "integrator/whitted.h"

namespace whitted {

// The recursion's policy: a child ray or a feeler is traced where the step meets it.
struct Recurse {
  static constexpr bool kQueues = false;
};

template <uint32_t kEffects, class Recorder, class Queries, class Policy>
class Kernel {
 public:
  using Inputs = KernelInputs<kEffects, Queries>;
  // Whether the feelers it queues in a wave carry passes (Recorder::Queued).
  static constexpr bool kQueuesPasses = !std::is_empty_v<typename Recorder::Queued>;
  Kernel(const WhittedIntegrator& w, SampleRecord* record, Policy policy = {})
      : in_(w), recorder_(w, record), policy_(policy) {}

  // WhittedIntegrator::TraceFn.
  static Color run(const WhittedIntegrator& w, const Ray& ray, const NodeState& state,
                   RayCounts* counts, float* alpha, const Hit* first, SampleRecord* record) {
    return Kernel(w, record).trace(ray, state, counts, alpha, first);
  }

  const Inputs& inputs() const { return in_; }

  // A ray a wave queued (wave.h), traced as trace() traces it, the recorder resumed where
  // the recursion would have had it: the sample's record, the ray's factor on the
  // sample, what it carries on the passes.
  Color resume(const Ray& ray, const NodeState& state, const Color& factor, const PassPath& path,
               SampleRecord* record, RayCounts* counts) const {
    recorder_.resume(record, factor, path);
    return trace(ray, state, counts, nullptr);
  }

  // Along a ray, through cut-outs: each surface adds its share, the rest goes on behind.
  // `first`, when given, is the ray's first hit, already found. In a scene with media
  // (kVolumeEffect, volume.h) the ray also meets the bounds of media without a surface,
  // entered and left as it crosses them, and each segment inside a medium adds what it
  // scatters and emits and dims what lies beyond it.
  Color trace(const Ray& ray, const NodeState& state, RayCounts* counts, float* alpha,
              const Hit* first = nullptr) const {
    Color radiance(0.0f);
    float coverage = 0.0f;
    float behind = 1.0f;     // the share of the ray not yet covered by a surface
    Color through(1.0f);     // what the media in front let through (kVolumeEffect)
    NodeState here = state;  // its media change where it crosses a volume's bounds
    Ray r = ray;
    typename Recorder::Node in_front{};  // the recorder's node of the layer in front
    for (int layer = 0; behind > 0.0f; ++layer) {
      Hit hit;
      bool found = false;
      if (layer == 0 && first != nullptr && !in_.has(kVolumeEffect)) {
        hit = *first;
        found = hit.t < kInfinity;
      } else {
        found = in_.queries.intersect(query(r), &hit);
      }
      const auto node = recorder_.ray(r, here.depth, in_front, behind, through);
      if (in_.has(kVolumeEffect)) {
        // The segment inside the media the ray is in: from where the ray starts to count (a
        // camera ray's clip start) to its hit, or as far as it may go; marched where a
        // program drives one of them.
        const float length = (found ? hit.t : r.t_max) - r.t_min;
        const Ray segment{
            r.origin + r.t_min * r.direction, r.direction, 0.0f, length, RayKind(r.kind), r.time};
        const bool marched = heterogeneous(in_.scene, here.media);
        const Medium m = marched ? Medium{} : medium_at(in_.scene, here.media);
        if (marched || !m.empty()) {
          [[maybe_unused]] const auto scope =
              recorder_.segment(node, segment, length, behind, through);
          const SegmentLight light =
              marched ? heterogeneous_segment(in_, recorder_, segment, length, here.media, here,
                                              layer, counts)
                      : segment_radiance(in_, recorder_, segment, length, m, here, layer, counts);
          recorder_.segment_light(here.depth, light);
          radiance += (behind * through) * light.radiance();
          through *= light.transmittance;
        }
        if (is_black(through)) break;
      }
      if ((r.kind & in_.scene.lamps_visibility) != 0) {
        // The lamps the ray passes before what it meets let it go on, as in Cycles.
        const Color seen = lamps(r, found ? hit.t : r.t_max, here);
        recorder_.lamps(here.depth, behind, through, seen);
        radiance += (behind * through) * seen;
      }
      if (!found) {
        radiance +=
            through * escape(r, ray.kind == kCameraRay, here, node, behind, through, &coverage);
        break;
      }
      Interaction it = in_.scene.interaction(r, hit);
      if (in_.has(kVolumeEffect) && !it.material->surface &&
          surface_in_bound(it, counts, &r, &hit)) {
        it = in_.scene.interaction(r, hit);  // the surface, met before the bound is crossed
      } else if (in_.has(kVolumeEffect) && !it.material->surface) {
        // A volume's bound: the ray goes on into (or out of) its medium.
        recorder_.crossed(node, it);
        in_front = node;  // the ray goes on behind it, as behind a cut-out
        if (glm::dot(r.direction, it.geometric_normal) < 0.0f) {
          here.media.enter_bound(it.material_index, it.instance);
        } else {
          here.media.leave(it.material_index);
        }
        const float left = r.t_max - glm::length(it.position - r.origin);
        if (!(left > 0.0f) || layer >= limits::kMaxMediaCrossings) break;
        r = spawn_ray(it.position, it.position_error, it.geometric_normal, it.time, r.direction,
                      RayKind(r.kind), left);
        counts->volume_bounds += 1;
        continue;
      }
      recorder_.hit(node, it);
      if (it.holdout) break;  // a holdout shows nothing and covers nothing
      const ProgramRays<kEffects, Queries, Recorder> rays(in_, here, counts, recorder_, node);
      const SurfaceParams surface = in_.scene.surface(it, r, in_.context(here, &rays));
      float a = 1.0f;
      if (in_.has(kTranslucencyEffect)) {
        a = layer == limits::kMaxTransparentLayers ? 1.0f : surface.alpha;
      }
      if (a > 0.0f) {
        if constexpr (Policy::kQueues) policy_.shading((behind * a) * through);
        [[maybe_unused]] const auto covered = recorder_.cover(node, behind, a, through);
        recorder_.surface(here.depth, r, it, surface);
        if (in_.has(kCatcherEffect) && r.kind == kCameraRay &&
            in_.scene.instances[it.instance].shadow_catcher) {
          const Caught caught = catch_shadows(r, it, surface, here, counts);
          recorder_.caught(caught.light, behind * a);
          radiance += (behind * a) * through * caught.radiance;
          coverage += behind * a * caught.coverage;
        } else {
          radiance += (behind * a) * through * shade(r, it, surface, here, counts);
          coverage += behind * a;
        }
      }
      in_front = node;
      behind *= 1.0f - a;
      if (behind <= 0.0f) break;
      // The rest of the ray continues behind the cut-out, as far as it was allowed to go.
      const float left = r.t_max - glm::length(it.position - r.origin);
      if (!(left > 0.0f)) break;
      r = spawn_ray(it.position, it.position_error, it.geometric_normal, it.time, r.direction,
                    RayKind(r.kind), left);
      counts->transparent += 1;
    }
    if (alpha != nullptr) *alpha = coverage;
    return radiance;
  }

  // A surface lying in the plane of the volume bound `bound` that ray *r met (a fog box
  // standing on the floor): the ray going on from beyond the bound, off it by its rounding
  // error, would pass it, and which of two coplanar faces Embree reports first changes from
  // ray to ray. So a surface within the bound's error is met first, as if just in front of
  // it, and the bound is not crossed: *r becomes the short ray that found it (from the
  // bound's near side to its far side, surfaces only) and *hit its hit.
  bool surface_in_bound(const Interaction& bound, RayCounts* counts, Ray* r, Hit* hit) const {
    const Vec3& n = bound.geometric_normal;
    const float cos = glm::dot(r->direction, n);
    if (cos == 0.0f) return false;
    const Vec3 beyond = cos > 0.0f ? n : -n;
    const Vec3 near = offset_ray_origin(bound.position, bound.position_error, -beyond);
    const Vec3 far = offset_ray_origin(bound.position, bound.position_error, beyond);
    const Ray across{near,   r->direction, 0.0f, glm::dot(far - near, n) / cos, RayKind(r->kind),
                     r->time};
    Hit found;
    counts->volume_queries += 1;
    if (!in_.queries.intersect(across, &found)) return false;
    if (!in_.scene.interaction(across, found).material->surface) {
      return false;  // a bound of another medium (or of this one), crossed as bounds are
    }
    // The rest of the ray, from the near side: as far as it was allowed to go.
    const float left = r->t_max - glm::length(bound.position - r->origin);
    *r = Ray{near, r->direction, 0.0f, left, RayKind(r->kind), r->time};
    *hit = found;
    return true;
  }

  // What the step asks Embree for a ray: its kind, and in a scene with media the
  // volumes' bounds too (a camera ray where there is none, kNoRay, sees nothing still).
  Ray query(const Ray& r) const {
    if (!in_.has(kVolumeEffect) || r.kind == kNoRay) return r;
    Ray q = r;
    q.kind |= kVolumeBoundRay;
    return q;
  }

  // The radiance of the lamps whose shapes ray r meets before t (intersect_light), each
  // weighed by lamp_weight: those its kind of ray sees, within their Max Bounces (a
  // bounced ray is one deeper than the hit that sends feelers), linked to the surface it
  // left (camera rays see every lamp, as in Cycles).
  Color lamps(const Ray& r, float t, const NodeState& state) const {
    Color sum(0.0f);
    for (const Light& light : in_.scene.lights) {
      if ((light.visibility & r.kind) == 0) continue;
      if (r.kind != kCameraRay && state.depth - 1 > light.max_bounces) continue;
      if (state.receiver >= 0 &&
          !in_sets(light.light_sets, static_cast<uint32_t>(state.receiver))) {
        continue;
      }
      LightHit hit;
      if (intersect_light(light, r, t, &hit)) {
        sum += hit.radiance * lamp_weight(state.lamp_density, light, hit.density);
      }
    }
    return sum;
  }

  // The world where a ray escapes, `behind` of it uncovered, and the coverage it adds:
  // none where a transparent film hides the world from the camera. `through`, what the
  // media on its way let through, is for the recorder: the caller applies it.
  Color escape(const Ray& r, bool camera, const NodeState& state, typename Recorder::Node node,
               float behind, const Color& through, float* coverage) const {
    const bool shown = !(in_.settings.transparent_background && camera);
    if (!shown && !Recorder::kHiddenWorld) return Color(0.0f);
    // A ray drawn from a glossy lobe counts the world as its MIS weight against the world
    // light's feelers says (NodeState::world_weight; 1 for every other ray); a kind of
    // ray the world's Ray Visibility hides from it sees black.
    const Color world = (in_.scene.world_visibility & r.kind) != 0
                            ? state.world_weight * in_.scene.world_radiance(r, in_.context(state))
                            : Color(0.0f);
    recorder_.escaped(node, state.depth, behind, through, world, shown);
    if (!shown) return Color(0.0f);
    *coverage += behind;
    return behind * world;
  }

 private:
  // What a camera ray's hit on a shadow catcher shows (catcher.h), as Cycles' Combined:
  // without the Shadow Catcher pass, over a transparent film nothing, covering as much
  // as the shadow is strong, and over an opaque film the world the ray would have met
  // without the catcher, times the light left, covering all; with the pass, nothing,
  // covering nothing (the pass takes `light`).
  struct Caught {
    Color radiance;
    float coverage;
    CaughtLight light;
  };
  Caught catch_shadows(const Ray& ray, const Interaction& it, const SurfaceParams& surface,
                       const NodeState& state, RayCounts* counts) const {
    const bool entering = glm::dot(ray.direction, it.geometric_normal) < 0.0f;
    const ShadingPoint p = shading_point(ray, it, surface, entering);
    const CaughtLight light =
        caught_light(in_, p, emission_weight(in_, ray, p, state), state, counts);
    if ((in_.settings.passes & pass_bit(FilmPass::kShadowCatcher)) != 0) {
      return {Color(0.0f), 0.0f, light};
    }
    const float lit = light.left();
    if (in_.settings.transparent_background) return {Color(0.0f), 1.0f - lit, light};
    const Color world = (in_.scene.world_visibility & ray.kind) != 0
                            ? in_.scene.world_radiance(ray, in_.context(state))
                            : Color(0.0f);
    return {lit * world, 1.0f, light};
  }

  // The radiance a surface point sends back along the ray,
  // I = local + sigma_r * reflected + sigma_t * refracted.
  Color shade(const Ray& ray, const Interaction& it, const SurfaceParams& surface,
              const NodeState& state, RayCounts* counts) const {
    // Entering or leaving is decided by the geometric normal, never the shading normal.
    const bool entering = glm::dot(ray.direction, it.geometric_normal) < 0.0f;
    const Crossing beyond =
        crossing(in_.scene, in_.has(kRefractionEffect), it, surface, entering, state.media);
    if (beyond.false_interface) return pass_through(ray, it, state, beyond.media, counts);
    const ShadingPoint p = shading_point(ray, it, surface, entering);
    const bool bounces = in_.has(kReflectionEffect) || in_.has(kRefractionEffect);
    const Split split =
        bounces ? split_weights(ray, p, beyond.eta, in_.has(kReflectionEffect),
                                in_.has(kRefractionEffect), in_.settings.fresnel, counts)
                : Split{};
    recorder_.split(p, split, (in_.effects & kGlossyEffect) != 0);
    const Lights<kEffects, Recorder, Queries, Policy> lights(in_, recorder_, policy_);
    Color radiance = lights.local(p, glossy_rays(in_, p, split, state),
                                  emission_weight(in_, ray, p, state), state, counts);
    if (!bounces) return radiance;
    if (in_.has(kReflectionEffect) && !is_black(split.sigma_r)) {
      radiance += reflection(ray, p, split, state, counts);
    }
    if (split.refracts && !is_black(split.sigma_t)) {
      radiance += transmission(p, split, beyond, state, counts);
    }
    return radiance;
  }

  // A false interface (medium.h): the ray goes on straight and unshaded, into the media
  // beyond.
  Color pass_through(const Ray& ray, const Interaction& it, const NodeState& state,
                     const MediumStack& media, RayCounts* counts) const {
    counts->transparent += 1;
    return branch(spawn_ray(it.position, it.position_error, it.geometric_normal, it.time,
                            ray.direction, RayKind(ray.kind)),
                  state, Color(1.0f), media, /*from=*/nullptr, TreeRayKind::kTransparent, counts);
  }

  // The reflected term: over the layers' lobes (glossy.h, reflection_lobes), each lobe's
  // sigma times what its mirror ray brings back, or the mean of what rays drawn from it
  // bring back.
  Color reflection(const Ray& ray, const ShadingPoint& p, const Split& split,
                   const NodeState& state, RayCounts* counts) const {
    [[maybe_unused]] const auto term = recorder_.reflected(state.depth, split.sigma_r);
    Color reflected(0.0f);
    for (const Lobe& lobe : reflection_lobes(p, split, (in_.effects & kGlossyEffect) != 0)) {
      reflected +=
          lobe.sigma * (lobe.ggx.alpha() > 0.0f
                            ? glossy_reflection(in_, p, lobe, state, drawn_branch(p, state, counts))
                            : mirror(ray, p, split, lobe, state, counts));
    }
    return reflected;
  }

  // What the mirror ray of a lobe of alpha 0 brings back, per unit of its sigma.
  Color mirror(const Ray& ray, const ShadingPoint& p, const Split& split, const Lobe& lobe,
               const NodeState& state, RayCounts* counts) const {
    Vec3 r = reflect(ray.direction, lobe.ggx.n);
    if (glm::dot(r, p.ng) <= 0.0f) r = reflect(ray.direction, p.ng);  // below the surface
    const TreeRayKind kind = split.total_internal_reflection ? TreeRayKind::kTotalInternalReflection
                                                             : TreeRayKind::kReflection;
    return branch(spawn_ray(p.it.position, p.it.position_error, p.it.geometric_normal, p.it.time, r,
                            kReflectionRay),
                  state, lobe.sigma, state.media, /*from=*/&p.it, kind, counts);
  }

  // The refracted term: sigma_t times what the refracted ray brings back from the media
  // beyond, or the mean of what rays through a rough surface's facets bring (glossy.h).
  Color transmission(const ShadingPoint& p, const Split& split, const Crossing& beyond,
                     const NodeState& state, RayCounts* counts) const {
    [[maybe_unused]] const auto term = recorder_.refracted(state.depth, split.sigma_t);
    Color refracted;
    if (p.alpha > 0.0f && (in_.effects & kGlossyEffect) != 0) {
      refracted =
          rough_transmission(in_, p, split.sigma_t, beyond, state, drawn_branch(p, state, counts));
    } else {
      refracted = branch(spawn_ray(p.it.position, p.it.position_error, p.it.geometric_normal,
                                   p.it.time, split.refracted, kRefractionRay),
                         state, split.sigma_t, beyond.media, /*from=*/&p.it,
                         TreeRayKind::kRefraction, counts);
    }
    return split.sigma_t * refracted;
  }

  // branch() for the rays glossy.h draws from a lobe at p.
  auto drawn_branch(const ShadingPoint& p, const NodeState& state, RayCounts* counts) const {
    return [this, &p, &state, counts](const Ray& ray, const Color& weight, const MediumStack& media,
                                      const Drawn& drawn) {
      return branch(ray, state, weight, media, /*from=*/&p.it, TreeRayKind::kGlossy, counts,
                    &drawn);
    };
  }

  // Traces a secondary ray of weight `weight` (relative to this one), unless the depth or
  // the cutoff stops it; `from` is the surface it bounces off, null for a ray that only
  // continues straight on (`kind` names it for the inspector), `drawn` given for a ray
  // drawn from a glossy lobe. The one place the ray tree branches: the policy traces the
  // ray now (Recurse) or queues it (Enqueue, whose rays bring nothing back here).
  Color branch(const Ray& ray, const NodeState& state, const Color& weight,
               const MediumStack& media, const Interaction* from, TreeRayKind kind,
               RayCounts* counts, const Drawn* drawn = nullptr) const {
    const bool bounce = from != nullptr;
    // A glossy ray is one of several that share its lobe: its NodeState::weight is the
    // lobe's (what the cutoff compares: each of n rays below it may sum above it), its
    // share of the sample 1/n of that.
    const float share = drawn != nullptr ? drawn->share : 1.0f;
    const NodeState next =
        state.child(weight, media, bounce,
                    bounce ? in_.scene.instances[from->instance].links.light_set : -1, drawn);
    if (next.depth > in_.settings.max_depth) {
      counts->depth_limited += 1;
      recorder_.cut(ray, next.depth, kind, weight, share, TreeCut::kDepth);
      return Color(0.0f);
    }
    if (max_component(next.weight) < in_.settings.cutoff) {
      counts->cutoff_skipped += 1;  // its contribution could no longer show
      recorder_.cut(ray, next.depth, kind, weight, share, TreeCut::kCutoff);
      return Color(0.0f);
    }
    counts->traced(ray.kind, bounce, drawn != nullptr);
    if constexpr (Policy::kQueues) {
      // Traced in a later generation of the wave.
      policy_.child(ray, next, weight * share, recorder_.path(weight, share));
      return Color(0.0f);
    } else {
      [[maybe_unused]] const auto scope = recorder_.branch(weight, share, kind);
      return trace(ray, next, counts, nullptr);
    }
  }

  const Inputs in_;
  // Told what the kernel does: what changes in it (its position, its sums) is not the
  // kernel's state.
  [[no_unique_address]] mutable Recorder recorder_;
  [[no_unique_address]] const Policy policy_;
};

}  // namespace whitted
