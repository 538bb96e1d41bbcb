#include "integrator/whitted.h"

#include <array>
#include <cmath>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "core/limits.h"
#include "integrator/kernel_recorder.h"
#include "integrator/lobes.h"
#include "integrator/shading_point.h"
#include "integrator/tree_recorder.h"
#include "integrator/wave.h"
#include "scene/mesh_light.h"

namespace whitted {
namespace {

using limits::kMaxTransparentLayers;

// IOR of a medium (-1 is the surrounding air): its material's constant ior, since a
// program's ior belongs to a hit, not to the volume behind it.
float ior_of(const CompiledScene& scene, int32_t medium) {
  return medium < 0 ? 1.0f : scene.materials[static_cast<size_t>(medium)].ior;
}

// The interface step's answer: what lies beyond a transmissive surface for the refracted
// ray (medium.h's rule for nested media).
struct Crossing {
  MediumStack media;             // the media the refracted ray is inside
  float eta = 1.0f;              // eta_incident / eta_transmitted
  bool false_interface = false;  // the current medium stays what it was: go on straight
};

// The split of weights: the weights of the secondary rays, Whitted's sigma_r and sigma_t,
// from the surface's reflectivity and transmissivity.
struct Split {
  Color sigma_r{0.0f};
  Color sigma_t{0.0f};
  Vec3 refracted{0.0f};  // the refracted direction, when `refracts`
  bool refracts = false;
  bool total_internal_reflection = false;  // the whole transmissive layer is in sigma_r
  bool about_coat = false;                 // the mirror ray reflects about the coat's normal
};

// The glossy rays a hit will send, as the feelers to emissive meshes weigh their glossy
// share against them (multiple importance sampling, Veach 1995): the lobe they are drawn
// from and how many there are per feeler. count 0: none will be sent (no glossy lobe,
// the depth, the cutoff), and the feelers count whole.
struct GlossyRays {
  Vec3 normal{0.0f, 0.0f, 1.0f};
  float alpha = 0.0f;
  float count = 0.0f;
};

// Veach's power heuristic (exponent 2): the weight of a sample drawn with density `a`
// (per solid angle, times its technique's sample count) against the other technique's
// density `b` for the same direction. The two weights of a direction sum to 1.
float power_heuristic(float a, float b) {
  if (!(a > 0.0f)) return 0.0f;
  const float r = b / a;
  if (std::isnan(r)) return 0.5f;  // both infinite
  return 1.0f / (1.0f + r * r);
}

// The kernel's queries in a render: straight to Embree.
class SceneQueries {
 public:
  explicit SceneQueries(const WhittedIntegrator& w) : accel_(*w.scene().accel) {}
  bool intersect(const Ray& ray, Hit* hit) const { return accel_.intersect(ray, hit); }
  bool occluded(const Ray& ray, const Blockers* blockers) const {
    return accel_.occluded(ray, blockers);
  }
  void intersect_packet(const Ray* rays, int count, Hit* hits) const {
    accel_.intersect_packet(rays, count, hits);
  }
  void occluded_packet(const Ray* rays, int count, bool* blocked, const Blockers* blockers) const {
    accel_.occluded_packet(rays, count, blocked, blockers);
  }

 private:
  const SceneAccel& accel_;
};

// The benchmark's, in a render given a RayLog (recorder.h): the queries made while the
// log is active go to it, which makes and notes them or answers them from a recording;
// the others straight to Embree.
class LoggedQueries {
 public:
  explicit LoggedQueries(const WhittedIntegrator& w) : accel_(*w.scene().accel), log_(*w.log()) {}
  bool intersect(const Ray& ray, Hit* hit) const {
    return log_.active ? log_.intersect(accel_, ray, hit) : accel_.intersect(ray, hit);
  }
  bool occluded(const Ray& ray, const Blockers* blockers) const {
    return log_.active ? log_.occluded(accel_, ray, blockers) : accel_.occluded(ray, blockers);
  }
  void intersect_packet(const Ray* rays, int count, Hit* hits) const {
    if (log_.active) {
      log_.intersect_packet(accel_, rays, count, hits);
    } else {
      accel_.intersect_packet(rays, count, hits);
    }
  }
  void occluded_packet(const Ray* rays, int count, bool* blocked, const Blockers* blockers) const {
    if (log_.active) {
      log_.occluded_packet(accel_, rays, count, blocked, blockers);
    } else {
      accel_.occluded_packet(rays, count, blocked, blockers);
    }
  }

 private:
  const SceneAccel& accel_;
  RayLog& log_;
};

// kEffects of a kernel that reads the effects at run time.
constexpr uint32_t kRuntimeEffects = ~0u;

// The Whitted recursion. What it records and how it queries are chosen at compile time:
// Recorder (kernel_recorder.h) is told, hook by hook, what is traced and what each node
// adds (NoRecorder, whose empty hooks compile away, for renders without passes;
// PassRecorder, passes.h, with passes; TreeRecorder, tree_recorder.h, for the
// inspector), and Queries takes the queries to Embree (SceneQueries) or, in the
// benchmark's recorded and replayed renders, through their log (LoggedQueries). The
// effects the analysis chose (EffectBits) are read with has(): constants in the kernels
// compiled per set of effects (kEffects, for renders without passes: measured faster,
// docs/EFFECTS.md), run-time flags in the others (kRuntimeEffects). The code is the same
// either way.
template <uint32_t kEffects, class Recorder, class Queries>
class Kernel {
 public:
  Kernel(const WhittedIntegrator& w, SampleRecord* record)
      : scene_(w.scene()),
        settings_(w.settings()),
        camera_(w.camera()),
        queries_(w),
        effects_(w.effects().bits),
        emitters_((effects_ & kEmitterEffect) != 0 && !scene_.mesh_lights->empty()),
        recorder_(w, record) {}

  static Color run(const WhittedIntegrator& w, const Ray& ray, const NodeState& state,
                   RayCounts* counts, float* alpha, const Hit* first, SampleRecord* record) {
    return Kernel(w, record).trace(ray, state, counts, alpha, first);
  }

  // The same recursion traced in waves (wave.h): each generation's rays are traced and
  // shaded as above, their children and feelers appended to the wave (branch,
  // feelers); then the generation's feelers are traced, and the children become the
  // next generation. The first generation, the camera rays, one by one as the sampler
  // makes them (run_camera); the rest here (run_wave).
  static void run_camera(const WhittedIntegrator& w, Wave* wave, const Ray& ray,
                         const NodeState& state, uint32_t sample, const Hit* first,
                         RayCounts* counts, SampleRecord* record) {
    Kernel kernel(w, record);
    WaveCursor cursor{wave};
    cursor.sample = sample;
    kernel.cursor_ = &cursor;
    WaveSample& s = wave->samples[sample];
    const uint64_t before = counts->total();
    s.radiance += kernel.trace(ray, state, counts, &s.alpha, first);
    s.rays += counts->total() - before;
  }
  static void run_wave(const WhittedIntegrator& w, Wave* wave, RayCounts* counts) {
    Kernel kernel(w, nullptr);
    WaveCursor cursor{wave};
    kernel.cursor_ = &cursor;
    for (kernel.trace_feelers(wave, counts); !wave->next.empty();
         kernel.trace_feelers(wave, counts)) {
      std::swap(wave->rays, wave->next);
      wave->next.clear();
      wave->feelers.clear();
      for (const WaveRay& r : wave->rays) {
        WaveSample& sample = wave->samples[r.sample];
        cursor.factor = r.factor;
        cursor.sample = r.sample;
        const uint64_t before = counts->total();
        sample.radiance += r.factor * kernel.trace(r.ray, r.state, counts, nullptr, nullptr);
        sample.rays += counts->total() - before;
      }
    }
  }

 private:
  // Where a kernel tracing a wave stands: the ray being traced (its factor on its
  // sample) and the factor of the surface being shaded (times the coverage in front).
  struct WaveCursor {
    Wave* wave;
    Color factor{1.0f};
    Color layer{1.0f};
    uint32_t sample = 0;
  };

  // The wave's feeler stage: each feeler's first query, those towards one lamp (with
  // one set of blockers) as packets, in runs of neighbouring hits; then, in the order
  // they were sent, what each lets through times its contribution is added to its sample.
  void trace_feelers(Wave* wave, RayCounts* counts) const {
    const std::vector<WaveFeeler>& feelers = wave->feelers;
    const size_t n = feelers.size();
    // Grouped by light, in their order within each group (a counting sort: lamps, then
    // the emissive meshes').
    const size_t groups = scene_.lights.size() + 1;
    const auto group = [&](const WaveFeeler& f) {
      return f.light < 0 ? groups - 1 : static_cast<size_t>(f.light);
    };
    std::vector<uint32_t>& starts = wave->groups;
    starts.assign(groups + 1, 0);
    for (const WaveFeeler& f : feelers) starts[group(f) + 1] += 1;
    for (size_t g = 0; g < groups; ++g) starts[g + 1] += starts[g];
    std::vector<uint32_t>& sorted = wave->order;
    sorted.resize(n);
    for (size_t i = 0; i < n; ++i) sorted[starts[group(feelers[i])]++] = static_cast<uint32_t>(i);
    wave->blocked.assign(n, 0);
    std::array<Ray, kFeelerBatch> rays;
    std::array<bool, kFeelerBatch> blocked;
    for (size_t first = 0; first < n;) {
      const WaveFeeler& lead = feelers[sorted[first]];
      size_t end = first + 1;
      while (end < n && end - first < static_cast<size_t>(kFeelerBatch) &&
             group(feelers[sorted[end]]) == group(lead) &&
             feelers[sorted[end]].shadow_sets == lead.shadow_sets) {
        ++end;
      }
      const int count = static_cast<int>(end - first);
      Blockers storage;
      const Blockers* linked = blockers(lead.shadow_sets, &storage);
      if (count == 1) {
        for (size_t k = first; k < end; ++k) {
          wave->blocked[sorted[k]] = queries_.occluded(feelers[sorted[k]].ray, linked) ? 1 : 0;
        }
      } else {
        for (int k = 0; k < count; ++k) rays[k] = feelers[sorted[first + k]].ray;
        queries_.occluded_packet(rays.data(), count, blocked.data(), linked);
        for (int k = 0; k < count; ++k) wave->blocked[sorted[first + k]] = blocked[k] ? 1 : 0;
      }
      first = end;
    }
    for (size_t i = 0; i < n; ++i) {
      const WaveFeeler& f = feelers[i];
      WaveSample& sample = wave->samples[f.sample];
      const uint64_t before = counts->total();
      Blockers storage;
      const Color transmittance = shadow_transmittance(
          f.ray, wave->blocked[i] != 0, blockers(f.shadow_sets, &storage), f.depth, counts);
      sample.radiance += f.contribution * transmittance;
      sample.rays += counts->total() - before;
    }
  }

  bool has(uint32_t bit) const {
    if constexpr (kEffects == kRuntimeEffects) {
      return (effects_ & bit) != 0;
    } else {
      return (kEffects & bit) != 0;
    }
  }

  // Shadow linking: the instances that may block a feeler of an emitter whose shadows
  // the shadow sets `sets` cast (null: every instance), held in *storage.
  const Blockers* blockers(uint64_t sets, Blockers* storage) const {
    if (sets == kAllLightSets) return nullptr;
    *storage = Blockers{scene_.shadow_sets.data(), sets};
    return storage;
  }

  // Along a ray, through cut-outs: each surface adds its share, the rest goes on behind.
  // `first`, when given, is the ray's first hit, already found.
  Color trace(const Ray& ray, const NodeState& state, RayCounts* counts, float* alpha,
              const Hit* first = nullptr) const {
    Color radiance(0.0f);
    float coverage = 0.0f;
    float behind = 1.0f;  // the share of the ray not yet covered by a surface
    Ray r = ray;
    typename Recorder::Node in_front{};  // the recorder's node of the layer in front
    for (int layer = 0; behind > 0.0f; ++layer) {
      Hit hit;
      bool found = false;
      if (layer == 0 && first != nullptr) {
        hit = *first;
        found = hit.t < kInfinity;
      } else {
        found = queries_.intersect(r, &hit);
      }
      const auto node = recorder_.ray(r, state.depth, in_front, behind);
      if (!found) {
        // A transparent film shows nothing where camera rays miss.
        const bool shown = !(settings_.transparent_background && ray.kind == kCameraRay);
        if (shown || Recorder::kHiddenWorld) {
          const Color world = scene_.world_radiance(r, context(state));
          if (shown) {
            radiance += behind * world;
            coverage += behind;
          }
          recorder_.escaped(node, state.depth, behind, world, shown);
        }
        break;
      }
      const Interaction it = scene_.interaction(r, hit);
      recorder_.hit(node, it);
      if (it.holdout) break;  // a holdout shows nothing and covers nothing
      const SurfaceParams surface = scene_.surface(it, r, context(state));
      float a = 1.0f;
      if (has(kTranslucencyEffect)) {
        a = layer == kMaxTransparentLayers ? 1.0f : surface.alpha;
      }
      if (a > 0.0f) {
        if (cursor_ != nullptr) cursor_->layer = cursor_->factor * (behind * a);
        [[maybe_unused]] const auto covered = recorder_.cover(node, behind, a);
        recorder_.surface(state.depth, r, it, surface);
        radiance += (behind * a) * shade(r, it, surface, state, counts);
        coverage += behind * a;
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

  // The Whitted step, the seed's RayTrace: the radiance a surface point sends back along
  // the ray, I = local + sigma_r * reflected + sigma_t * refracted.
  Color shade(const Ray& ray, const Interaction& it, const SurfaceParams& surface,
              const NodeState& state, RayCounts* counts) const {
    // Entering or leaving is decided by the geometric normal, never the shading normal.
    const bool entering = glm::dot(ray.direction, it.geometric_normal) < 0.0f;
    const Crossing beyond = crossing(it, surface, entering, state.media);
    if (beyond.false_interface) return pass_through(ray, it, state, beyond.media, counts);
    const ShadingPoint p = shading_point(ray, it, surface, entering);
    const bool bounces = has(kReflectionEffect) || has(kRefractionEffect);
    const Split split = bounces ? split_weights(ray, p, beyond.eta, counts) : Split{};
    Color radiance =
        local(p, glossy_rays(p, split, state), emission_weight(ray, p, state), state, counts);
    if (!bounces) return radiance;
    if (has(kReflectionEffect) && !is_black(split.sigma_r)) {
      radiance += reflection(ray, p, split, state, counts);
    }
    if (split.refracts && !is_black(split.sigma_t)) {
      radiance += transmission(p, split, beyond, state, counts);
    }
    return radiance;
  }

  // The interface step: which media lie beyond a transmissive surface (the ray enters
  // its medium or leaves it), the ratio of indices across it, and whether it is a false
  // interface, inside a medium of higher priority. Elsewhere the media stay as they are.
  Crossing crossing(const Interaction& it, const SurfaceParams& surface, bool entering,
                    const MediumStack& media) const {
    Crossing beyond{media};
    const Material& m = *it.material;
    if (!has(kRefractionEffect) || !m.transmissive()) return beyond;
    const int32_t from = media.current();
    if (entering) {
      beyond.false_interface = from >= 0 && m.priority < scene_.materials[from].priority;
      beyond.media.enter(it.material_index, m.priority);
      beyond.eta = ior_of(scene_, from) / surface.ior;
    } else if (beyond.media.leave(it.material_index)) {
      beyond.false_interface = from != static_cast<int32_t>(it.material_index);
      beyond.eta = surface.ior / ior_of(scene_, beyond.media.current());
    } else {
      // Leaving a medium it never entered (flipped normals, an open mesh): out into the
      // current medium, as a renderer without media lists would.
      beyond.eta = surface.ior / ior_of(scene_, from);
    }
    return beyond;
  }

  // A false interface: the ray goes on straight and unshaded, into the media beyond.
  Color pass_through(const Ray& ray, const Interaction& it, const NodeState& state,
                     const MediumStack& media, RayCounts* counts) const {
    counts->transparent += 1;
    return branch(spawn_ray(it.position, it.position_error, it.geometric_normal, it.time,
                            ray.direction, RayKind(ray.kind)),
                  state, Color(1.0f), media, /*from=*/nullptr, TreeRayKind::kTransparent, counts);
  }

  // The hit as the local term and the split of weights read it: normals facing the ray,
  // the coat over the base.
  ShadingPoint shading_point(const Ray& ray, const Interaction& it, const SurfaceParams& surface,
                             bool entering) const {
    Vec3 ng;
    Vec3 ns;
    facing_normals(ray, it, surface, &ng, &ns);
    const Vec3 wo = -ray.direction;
    const Coat coat = coat_of(surface, wo, ng, entering, it.material->masking);
    // A program's normal fades the diffuse lobe towards the smooth surface's horizon, as
    // Cycles does (diffuse_shadowing).
    const Vec3 smooth =
        glm::dot(it.geometric_normal, ng) > 0.0f ? it.shading_normal : -it.shading_normal;
    const float base = it.material->coat_layered ? 1.0f - coat.cover : 1.0f;
    const float phong_norm = (surface.shininess + 2.0f) * (0.5f * kInvPi);
    const Color multiscatter =
        it.material->diffuse_model == DiffuseModel::kOrenNayarEnergy
            ? surface.diffuse * oren_nayar_multiscatter(surface.diffuse, surface.diffuse_roughness,
                                                        glm::dot(ns, wo))
            : Color(0.0f);
    // A lobe rougher than a mirror is GGX's, for lights and rays (microfacet.h).
    const float alpha = surface.roughness * surface.roughness;
    const bool glossy = alpha >= kMirrorAlpha &&
                        (!is_black(surface.reflectivity) || !is_black(surface.transmissivity));
    const Color energy =
        glossy && it.material->multiscatter
            ? ggx_multiscatter_scale(surface.reflectivity, glm::dot(ns, wo), surface.roughness)
            : Color(1.0f);
    return {it,
            surface,
            ng,
            ns,
            smooth,
            wo,
            coat,
            base,
            phong_norm,
            multiscatter,
            glossy ? alpha : 0.0f,
            energy};
  }

  bool emitters_on() const { return emitters_; }

  // Glossy rays per emitter feeler at a hit: each technique's sample count at `state`.
  float rays_per_feeler(const NodeState& state) const {
    const int glossy = Strata::side(state, settings_.glossy_samples);
    const int feelers = Strata::side(state, settings_.emitter_samples);
    return static_cast<float>(glossy * glossy) / static_cast<float>(feelers * feelers);
  }

  // The glossy rays reflection() will send from this hit, for the emitter feelers' MIS
  // weights: none without emitters, a glossy lobe, depth left or a weight above the cutoff.
  GlossyRays glossy_rays(const ShadingPoint& p, const Split& split, const NodeState& state) const {
    GlossyRays rays;
    if (!emitters_on() || (effects_ & kGlossyEffect) == 0 || !has(kReflectionEffect)) return rays;
    if (split.total_internal_reflection || is_black(split.sigma_r)) return rays;
    const bool coat = split.about_coat && p.coat.alpha > 0.0f;
    if (!coat && (split.about_coat || !(p.alpha > 0.0f))) return rays;
    if (state.depth + 1 > settings_.max_depth) return rays;
    const Color energy = coat ? Color(1.0f) : p.energy;
    if (max_component(state.weight * split.sigma_r * energy) < settings_.cutoff) return rays;
    rays.normal = coat ? p.coat.normal : p.ns;
    rays.alpha = coat ? p.coat.alpha : p.alpha;
    rays.count = rays_per_feeler(state);
    return rays;
  }

  // What a glossy ray counts of the emission it meets: its MIS weight against the
  // feelers that sample this side of this triangle (1 where none do, and for every other
  // ray; 0 where light linking keeps the emitter from the surface the ray left). The
  // distance is from the ray's origin (behind a cut-out: from the cut-out).
  float emission_weight(const Ray& ray, const ShadingPoint& p, const NodeState& state) const {
    if (is_black(p.surface.emission)) return 1.0f;
    // Light linking: a bounce sees an emitter only if it lights the surface it left
    // (camera rays see every one, as in Cycles).
    if (scene_.light_linking && state.receiver >= 0 &&
        !in_sets(scene_.instances[p.it.instance].links.light_sets,
                 static_cast<uint32_t>(state.receiver))) {
      return 0.0f;
    }
    if (!(state.mis > 0.0f) || !emitters_on()) return 1.0f;
    const MeshLights& lights = *scene_.mesh_lights;
    const int32_t index = lights.find(p.it.instance, p.it.primitive);
    if (index < 0) return 1.0f;
    const auto found = static_cast<uint32_t>(index);
    const EmissiveTriangle triangle = lights.at(scene_, found, p.it.time);
    if (!triangle.lights(-ray.direction)) return 1.0f;
    const Vec3 d = p.it.position - ray.origin;
    const float cos_e = std::fabs(glm::dot(ray.direction, triangle.normal));
    const float density = lights.density(found, triangle) * glm::dot(d, d) / cos_e;
    return power_heuristic(state.mis, density);
  }

  // The split of weights: sigma_r and sigma_t of the secondary rays. The transmissive
  // layer splits by Fresnel into a reflected and a refracted share (all reflected on
  // total internal reflection); the coat's mirror goes on top and takes its share of both;
  // then sigma_r + sigma_t <= 1.
  Split split_weights(const Ray& ray, const ShadingPoint& p, float eta, RayCounts* counts) const {
    Split split;
    split.sigma_r = has(kReflectionEffect) ? p.surface.reflectivity : Color(0.0f);
    split.sigma_t = has(kRefractionEffect) ? p.surface.transmissivity : Color(0.0f);
    if (is_black(split.sigma_r) && is_black(split.sigma_t) && p.coat.mirror <= 0.0f) return split;
    if (!is_black(split.sigma_t)) {
      split.refracts = refract(ray.direction, p.ns, eta, &split.refracted) &&
                       glm::dot(split.refracted, p.ng) < 0.0f;
      const float cos_i = std::min(1.0f, glm::dot(p.wo, p.ns));
      const float f = !split.refracts                          ? 1.0f
                      : settings_.fresnel == Fresnel::kExact   ? fresnel_exact(cos_i, eta)
                      : settings_.fresnel == Fresnel::kSchlick ? fresnel_schlick(cos_i, eta)
                                                               : 0.0f;
      split.sigma_r += split.sigma_t * f;
      split.sigma_t *= 1.0f - f;
      split.total_internal_reflection = !split.refracts;
      if (!split.refracts) counts->total_internal_reflections += 1;
    }
    // One mirror ray: about the coat's normal where the coat gives most of its weight.
    split.about_coat = p.coat.mirror > p.base * max_component(split.sigma_r);
    split.sigma_r = p.base * split.sigma_r + Color(p.coat.mirror);
    split.sigma_t *= p.base;
    // A surface returns at most what arrives: sigma_r + sigma_t <= 1 keeps the ray tree
    // from growing without bound (two facing mirror-glass panes at depth 256).
    const float sum = max_component(split.sigma_r + split.sigma_t);
    if (sum > 1.0f) {
      split.sigma_r /= sum;
      split.sigma_t /= sum;
    }
    return split;
  }

  // The reflected term: sigma_r times what the mirror ray brings back, or the mean of
  // what rays drawn from a glossy lobe bring back.
  Color reflection(const Ray& ray, const ShadingPoint& p, const Split& split,
                   const NodeState& state, RayCounts* counts) const {
    if ((effects_ & kGlossyEffect) != 0 && !split.total_internal_reflection) {
      // The one reflection follows the lobe that gives it most of its weight.
      if (split.about_coat && p.coat.alpha > 0.0f) {
        return glossy_reflection(p, split, Lobe{p.coat.normal, p.coat.alpha, Color(1.0f), &p.coat},
                                 state, counts);
      }
      if (!split.about_coat && p.alpha > 0.0f) {
        return glossy_reflection(p, split, Lobe{p.ns, p.alpha, p.energy}, state, counts);
      }
    }
    Vec3 r = reflect(ray.direction, split.about_coat ? p.coat.normal : p.ns);
    if (glm::dot(r, p.ng) <= 0.0f) r = reflect(ray.direction, p.ng);  // below the surface
    const TreeRayKind kind = split.total_internal_reflection ? TreeRayKind::kTotalInternalReflection
                                                             : TreeRayKind::kReflection;
    const Color reflected = branch(spawn_ray(p.it.position, p.it.position_error,
                                             p.it.geometric_normal, p.it.time, r, kReflectionRay),
                                   state, split.sigma_r, state.media, /*from=*/&p.it, kind, counts);
    recorder_.reflected(state.depth, split.sigma_r, reflected);
    return split.sigma_r * reflected;
  }

  struct Lobe {
    Vec3 normal;                // facing the ray
    float alpha;                // GGX alpha
    Color energy;               // its multiple-scattering scale, or 1
    const Coat* coat{nullptr};  // a dielectric layer's: each ray by its facet's Fresnel
  };
  // Distributed ray tracing's glossy reflection (Cook et al. 1984): n x n rays drawn
  // from the GGX lobe (microfacet.h), one per stratum of [0, 1)^2, each weighing
  // sigma_r * G2/G1 / n^2 (the lobe over its density). Each stratum's point is placed by a
  // hash of the camera sample's seed (NodeState::seed; Strata), so every render of a
  // scene draws the same rays, whatever its scale, and neighbouring samples different
  // ones. A ray the lobe sends below the surface is lost, as light the single-scattering
  // lobe does not return.
  Color glossy_reflection(const ShadingPoint& p, const Split& split, const Lobe& lobe_of,
                          const NodeState& state, RayCounts* counts) const {
    const Strata strata(state, settings_.glossy_samples, 0x6c6fu);
    // Rays per emitter feeler, for each ray's MIS density (0: no emitters to weigh).
    const float per_feeler = emitters_on() ? rays_per_feeler(state) : 0.0f;
    Color mean(0.0f);  // sum over the rays of (weight / sigma_r) * radiance
    for (int k = 0; k < strata.count(); ++k) {
      const glm::vec2 u = strata.point(k);
      Vec3 wi;
      float lobe = 0.0f;  // G2 / G1
      if (!ggx_sample_reflection(lobe_of.normal, p.wo, lobe_of.alpha, u.x, u.y, &wi, &lobe,
                                 p.it.material->masking)) {
        continue;
      }
      if (glm::dot(wi, p.ng) <= 0.0f) continue;  // below the surface itself
      if (lobe_of.coat != nullptr) {
        lobe *= lobe_of.coat->facet_scale(p.wo, glm::normalize(p.wo + wi));
      }
      const Color weight = split.sigma_r * lobe_of.energy * lobe;
      // Its density, for the MIS weight of the emission it may meet (emission_weight).
      const float mis = per_feeler > 0.0f ? per_feeler * ggx_reflection_pdf(lobe_of.normal, p.wo,
                                                                            wi, lobe_of.alpha)
                                          : 0.0f;
      const Drawn drawn{strata.share, hash3(state.seed, static_cast<uint32_t>(k), 0x676cu), mis};
      const Color brought =
          branch(spawn_ray(p.it.position, p.it.position_error, p.it.geometric_normal, p.it.time, wi,
                           kReflectionRay),
                 state, weight, state.media, /*from=*/&p.it, TreeRayKind::kGlossy, counts, &drawn);
      mean += (lobe * strata.share) * lobe_of.energy * brought;
    }
    recorder_.reflected(state.depth, split.sigma_r, mean);
    return split.sigma_r * mean;
  }

  // The n x n strata of [0, 1)^2 a glossy lobe's rays (or the emitter feelers) are drawn
  // from: n = Glossy Samples (Emitter Samples) at a branch's first glossy hit and before,
  // 1 after; one point in each stratum, placed by a hash of the branch's seed and depth,
  // the stratum and `salt` (which tells the lobes of one hit apart). Jittered apart,
  // not shifted together: a lattice shifted as one errs by O(1/n) (its offset from the
  // cell centres), jittered strata by O(n^-1.5) (2% against 0.6% on a lit floor under a
  // quad emitter at n = 16, mesh_light_test.cpp).
  struct Strata {
    int n;
    float share;  // 1 / n^2: each ray's share of the lobe
    uint32_t base;

    static int side(const NodeState& state, int samples) { return state.glossy == 0 ? samples : 1; }
    Strata(const NodeState& state, int samples, uint32_t salt)
        : n(side(state, samples)),
          share(1.0f / static_cast<float>(n * n)),
          base(hash3(state.seed, static_cast<uint32_t>(state.depth), salt)) {}
    int count() const { return n * n; }
    // Stratum k's point.
    glm::vec2 point(int k) const {
      const uint32_t h = hash3(base, static_cast<uint32_t>(k), 0x9e3779b9u);
      const float jitter_x = unit_float(h);
      const float jitter_y = unit_float(hash3(h, 0x7f4au, 0x85ebu));
      // Below 1: the sum of the last cell's index and a jitter near 1 may round up to n.
      constexpr float kBelowOne = 0x1.fffffep-1f;
      return {std::min((static_cast<float>(k % n) + jitter_x) / static_cast<float>(n), kBelowOne),
              std::min((static_cast<float>(k / n) + jitter_y) / static_cast<float>(n), kBelowOne)};
    }
  };

  // The refracted term: sigma_t times what the refracted ray brings back from the media
  // beyond.
  Color transmission(const ShadingPoint& p, const Split& split, const Crossing& beyond,
                     const NodeState& state, RayCounts* counts) const {
    if (p.alpha > 0.0f && (effects_ & kGlossyEffect) != 0) {
      return rough_transmission(p, split, beyond, state, counts);
    }
    const Color refracted = branch(
        spawn_ray(p.it.position, p.it.position_error, p.it.geometric_normal, p.it.time,
                  split.refracted, kRefractionRay),
        state, split.sigma_t, beyond.media, /*from=*/&p.it, TreeRayKind::kRefraction, counts);
    recorder_.refracted(state.depth, split.sigma_t, refracted);
    return split.sigma_t * refracted;
  }

  // Frosted glass: the refracted term from n x n visible normals of the GGX lobe (as
  // glossy_reflection's), the view refracted through each (Walter et al. 2007), weighing
  // sigma_t * G2/G1 times its facet's Fresnel transmittance over the one sigma_t holds.
  // Where a facet totally reflects the view (inside the glass, past its critical angle),
  // its ray reflects about it and stays in the medium.
  Color rough_transmission(const ShadingPoint& p, const Split& split, const Crossing& beyond,
                           const NodeState& state, RayCounts* counts) const {
    const Strata strata(state, settings_.glossy_samples, 0x7472u);
    const float cos_o = glm::dot(p.ns, p.wo);
    const bool fresnel = settings_.fresnel != Fresnel::kOff;
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
      float lobe =
          ggx_transmission_weight(cos_o, glm::dot(p.ns, t), p.alpha, p.it.material->masking);
      if (through && fresnel && kept > 0.0f) {
        lobe *= (1.0f - fresnel_exact(std::max(0.0f, glm::dot(p.wo, m)), beyond.eta)) / kept;
      }
      // No feeler reaches an emitter through glass: what these rays meet counts whole.
      const Drawn drawn{strata.share, hash3(state.seed, static_cast<uint32_t>(k), 0x7463u), 0.0f};
      const Color brought =
          branch(spawn_ray(p.it.position, p.it.position_error, p.it.geometric_normal, p.it.time, t,
                           through ? kRefractionRay : kReflectionRay),
                 state, split.sigma_t * lobe, through ? beyond.media : state.media, /*from=*/&p.it,
                 TreeRayKind::kGlossy, counts, &drawn);
      mean += (lobe * strata.share) * brought;
    }
    recorder_.refracted(state.depth, split.sigma_t, mean);
    return split.sigma_t * mean;
  }

  // A ray drawn from a glossy lobe, as branch() takes it: its share of the lobe, the seed
  // of the strata below it, and its density for MIS (NodeState::mis).
  struct Drawn {
    float share;
    uint32_t seed;
    float mis;
  };

  // Traces a secondary ray of weight `weight` (relative to this one), unless the depth or
  // the cutoff stops it; `from` is the surface it bounces off, null for a ray that only
  // continues straight on (`kind` names it for the inspector), `drawn` given for a ray
  // drawn from a glossy lobe. The one place the ray tree branches.
  Color branch(const Ray& ray, const NodeState& state, const Color& weight,
               const MediumStack& media, const Interaction* from, TreeRayKind kind,
               RayCounts* counts, const Drawn* drawn = nullptr) const {
    const bool bounce = from != nullptr;
    // A glossy ray is one of several that share its lobe: its NodeState::weight is the
    // lobe's (what the cutoff compares: each of n rays below it may sum above it), its
    // share of the sample 1/n of that.
    const bool glossy = drawn != nullptr;
    const float share = glossy ? drawn->share : 1.0f;
    NodeState next{bounce ? state.depth + 1 : state.depth, state.weight * weight, media};
    next.glossy = state.glossy + (glossy ? 1 : 0);
    next.seed = glossy ? drawn->seed : state.seed;
    // A continuation straight on is still the same ray; a bounce of any other kind
    // counts the emission it meets whole.
    next.mis = glossy ? drawn->mis : (bounce ? 0.0f : state.mis);
    // Light linking: what it meets is lit for the surface it left (emission_weight).
    next.receiver = bounce ? scene_.instances[from->instance].links.light_set : state.receiver;
    if (next.depth > settings_.max_depth) {
      counts->depth_limited += 1;
      recorder_.cut(ray, next.depth, kind, weight, share, TreeCut::kDepth);
      return Color(0.0f);
    }
    if (max_component(next.weight) < settings_.cutoff) {
      counts->cutoff_skipped += 1;  // its contribution could no longer show
      recorder_.cut(ray, next.depth, kind, weight, share, TreeCut::kCutoff);
      return Color(0.0f);
    }
    if (glossy) {
      counts->glossy += 1;
    } else if (bounce && ray.kind == kReflectionRay) {
      counts->reflection += 1;
    }
    if (bounce && ray.kind == kRefractionRay) counts->refraction += 1;
    if (cursor_ != nullptr) {  // traced in a later generation of the wave
      cursor_->wave->next.push_back(
          {ray, next, cursor_->layer * (weight * share), cursor_->sample});
      return Color(0.0f);
    }
    [[maybe_unused]] const auto scope = recorder_.branch(weight, share, kind);
    return trace(ray, next, counts, nullptr);
  }

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
    const SurfaceParams& surface = p.surface;
    const Color emission = surface.emission * seen;
    const Color ambient = p.base * p.it.material->ambient * scene_.ambient * surface.diffuse;
    Color phong = ambient;
    const uint32_t receiver = scene_.instances[p.it.instance].links.light_set;
    for (const Light& light : scene_.lights) {
      if (state.depth > light.max_bounces) continue;       // past its Max Bounces
      if (!in_sets(light.light_sets, receiver)) continue;  // not linked to this surface
      const int samples = light.sample_count();
      const Feeler feeler{light.cast_shadows,
                          samples,
                          static_cast<int32_t>(&light - scene_.lights.data()),
                          -1,
                          light.diffuse,
                          light.glossy,
                          light.shadow_sets};
      const auto draw = [&](int s) {
        return Drawing{feeler, sample_light(light, p.it.position, s), 1.0f};
      };
      feelers(p, samples, draw, state, counts, &phong);
    }
    if (emitters_on()) emitters(p, rays, state, counts, &phong);
    const Color radiance = emission + phong;
    recorder_.local(p, state.depth, emission, ambient, radiance);
    return radiance;
  }

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
    float mis;
  };

  // Adds the shares of `samples` light samples, draw(s) for s in order, to *phong one by
  // one, as light_sample's are. A single feeler, or those of different lights, trace
  // faster one at a time (docs/notes/performance_reading.md), and the inspector records
  // each alone; the feelers of a sized light leave one point for one small region of
  // space: they go to Embree as packets of up to kFeelerBatch (the same sum to the bit).
  template <class Draw>
  void feelers(const ShadingPoint& p, int samples, const Draw& draw, const NodeState& state,
               RayCounts* counts, Color* phong) const {
    if (cursor_ != nullptr) {
      for (int s = 0; s < samples; ++s) defer_sample(p, draw(s), state, counts, phong);
      return;
    }
    if (!Recorder::kBatchesFeelers || samples == 1) {
      for (int s = 0; s < samples; ++s) *phong += light_sample(p, draw(s), state, counts);
      return;
    }
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

  // The feelers to the emissive meshes: n x n samples of their power table (the strata
  // shifted per branch, as glossy rays'), each a point on a triangle lighting p as a patch
  // of an area light, E = L cos_e / (d^2 density) / n^2. The glossy share of each is
  // weighed against the glossy rays that may meet the same point (MIS; emission_weight).
  // Out of line, and light_sample and prepare_sample always inlined: as GCC chose, the
  // lamps' feelers went through calls that cost a scene without emitters 6% more of
  // Whitted's own instructions (85.2 M before emitters, 90.5 M; now 88.3 M: callgrind,
  // python -m whitted_tools.builds --small).
  [[gnu::noinline]] void emitters(const ShadingPoint& p, const GlossyRays& rays,
                                  const NodeState& state, RayCounts* counts, Color* phong) const {
    const MeshLights& lights = *scene_.mesh_lights;
    const Strata strata(state, settings_.emitter_samples, 0x656du);
    const uint32_t receiver = scene_.instances[p.it.instance].links.light_set;
    const auto draw = [&](int k) {
      const glm::vec2 u = strata.point(k);
      // Where the emitter is at the shading point's time (a moving one's place then).
      const MeshLights::Sample s = lights.sample(scene_, u.x, u.y, p.it.time);
      const EmissiveTriangle& triangle = s.triangle;
      const InstanceLinks& links = scene_.instances[triangle.instance].links;
      Drawing out{{true, strata.count(), -1, static_cast<int32_t>(triangle.instance), true, true,
                   links.shadow_sets},
                  {Vec3(0.0f, 0.0f, 1.0f), 0.0f, Color(0.0f)},
                  1.0f};
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
      const Color radiance = emitted(scene_, triangle, s.barycentric, towards, context(state));
      out.sample.irradiance = radiance * (cos_e * strata.share / (dist2 * s.density));
      if (rays.count > 0.0f) {
        out.mis = power_heuristic(
            s.density * dist2 / cos_e,
            rays.count * ggx_reflection_pdf(rays.normal, p.wo, out.sample.wi, rays.alpha));
      }
      return out;
    };
    feelers(p, strata.count(), draw, state, counts, phong);
  }

  // A light sample in a wave: its share added now if no feeler is sent, else its feeler
  // appended to the wave, which adds its share once the feeler's answer is known.
  [[gnu::flatten]] void defer_sample(const ShadingPoint& p, const Drawing& drawing,
                                     const NodeState& state, RayCounts* counts,
                                     Color* phong) const {
    PreparedSample prepared;
    prepare_sample(p, drawing, state, counts, typename Recorder::Node{}, &prepared);
    if (prepared.dark) return;
    if (!prepared.sends_feeler) {
      *phong += arrived(p, prepared, Color(1.0f));
      return;
    }
    cursor_->wave->feelers.push_back({first_query(prepared.feeler),
                                      cursor_->layer * prepared.unshadowed, prepared.shadow_sets,
                                      cursor_->sample, drawing.feeler.light, state.depth});
  }

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
  // A batch's feelers fill at most one packet.
  static constexpr int kFeelerBatch = SceneAccel::kPacketSize;

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
      const Blockers* linked = blockers(prepared.shadow_sets, &storage);
      transmittance = shadow_transmittance(ray, queries_.occluded(first_query(ray), linked), linked,
                                           state.depth, counts);
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
    out->dark = has(kPruningEffect) && dark(cos_l, ls, node, counts);
    out->sends_feeler = false;
    if (out->dark) return;
    out->t = light_terms(p, ls.wi, cos_l);
    if (drawing.mis < 1.0f) weigh_glossy(p, ls.wi, drawing.mis, &out->t);
    if (!drawing.feeler.diffuse || !drawing.feeler.glossy) unseen(drawing.feeler, &out->t);
    out->irradiance = ls.irradiance;
    const LightTerms& t = out->t;
    const SurfaceParams& surface = p.surface;
    const Color brdf = surface.diffuse * (kInvPi * t.fade) + p.multiscatter * t.loss +
                       surface.specular * (p.phong_norm * t.lobe);
    out->unshadowed = (t.lit * brdf + Color(t.coat)) * ls.irradiance;
    if (p.alpha > 0.0f) {
      out->unshadowed += surface.reflectivity * p.energy * t.glossy * ls.irradiance;
    }
    recorder_.unshadowed(node, p, t, ls);
    out->sends_feeler = shadow(p, drawing.feeler, ls, out->unshadowed, state, counts, &out->feeler);
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
        rays[static_cast<size_t>(feelers++)] = first_query(batch[i].feeler);
        shared = shared && batch[i].shadow_sets == batch[0].shadow_sets;
      }
    }
    Blockers storage;
    const Blockers* linked = blockers(batch[0].shadow_sets, &storage);
    if (feelers == 1 || (feelers > 1 && !shared)) {
      for (int i = 0, f = 0; i < n; ++i) {
        if (!batch[i].sends_feeler) continue;
        Blockers own;
        blocked[static_cast<size_t>(f)] =
            queries_.occluded(rays[static_cast<size_t>(f)], blockers(batch[i].shadow_sets, &own));
        ++f;
      }
    }
    if (feelers > 1 && shared) {
      queries_.occluded_packet(rays.data(), feelers, blocked.data(), linked);
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
        transmittance =
            shadow_transmittance(prepared.feeler, first_blocked,
                                 blockers(prepared.shadow_sets, &own), state.depth, counts);
      }
      *phong += arrived(p, prepared, transmittance);
    }
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

  // The Phong terms of a light sample from wi, per unit irradiance, unshadowed.
  static LightTerms light_terms(const ShadingPoint& p, const Vec3& wi, float cos_l) {
    const float v_dot_r = std::max(0.0f, glm::dot(p.wo, reflect(-wi, p.ns)));
    LightTerms t{p.base * std::max(0.0f, cos_l),
                 1.0f,
                 0.0f,
                 phong_lobe(p, v_dot_r),
                 coat_highlight(p.coat, p.wo, wi, p.it.material->masking),
                 p.alpha > 0.0f
                     ? p.base * ggx_reflection(p.ns, p.wo, wi, p.alpha, p.it.material->masking)
                     : 0.0f};
    diffuse_fade(p, wi, cos_l, &t);
    return t;
  }

  // A lamp's terms its ray visibility hides: the diffuse ones when it lights no diffuse
  // surface, the specular ones (Phong, coat, glossy) when no glossy one shows it.
  static void unseen(const Feeler& feeler, LightTerms* t) {
    if (!feeler.diffuse) t->fade = t->loss = 0.0f;
    if (!feeler.glossy) t->lobe = t->coat = t->glossy = 0.0f;
  }

  // An emitter feeler's MIS weight (GlossyRays) on its glossy lobes' share of t: the
  // base's GGX lobe and a rough coat's.
  static void weigh_glossy(const ShadingPoint& p, const Vec3& wi, float mis, LightTerms* t) {
    t->glossy *= mis;
    if (p.coat.alpha > 0.0f && t->coat > 0.0f) {
      const float glossy = coat_glossy(p.coat, p.wo, wi, p.it.material->masking);
      t->coat = std::max(0.0f, t->coat - (1.0f - mis) * glossy);
    }
  }

  // (v.r)^f, without powf (about 61 instructions a call, callgrind) where its value is
  // known or cannot show, to the bit: for f > 0 it is +0 at v.r = 0, and where ks is 0 the
  // lobe is only ever multiplied by ks (then finite, as v.r <= 1), so 0 gives the same
  // products.
  static float phong_lobe(const ShadingPoint& p, float v_dot_r) {
    const float f = p.surface.shininess;
    const bool known =
        f > 0.0f && (v_dot_r <= 0.0f || (v_dot_r <= 1.0f && p.surface.specular == Color(0.0f)));
    return known ? 0.0f : std::pow(v_dot_r, f);
  }

  // The diffuse lobe's factors for light from wi (fade, loss): Cycles' bump shadowing,
  // times the lobe's shape where it is not Lambert's (material.h's DiffuseModel).
  static void diffuse_fade(const ShadingPoint& p, const Vec3& wi, float cos_l, LightTerms* t) {
    const Material& m = *p.it.material;
    t->fade = diffuse_shadowing(m.bump_shadowing, p.smooth, p.ns, wi);
    if (m.diffuse_model == DiffuseModel::kLambert) return;
    const float cos_v = glm::dot(p.ns, p.wo);
    const float l_dot_v = glm::dot(wi, p.wo);
    const float r = p.surface.diffuse_roughness;
    if (m.diffuse_model == DiffuseModel::kVelvet) {
      t->fade *= velvet_diffuse(cos_l, cos_v, l_dot_v, r);
      return;
    }
    if (m.diffuse_model == DiffuseModel::kBurley) {
      t->fade *= burley_diffuse(cos_l, cos_v, l_dot_v, r);
      return;
    }
    if (m.diffuse_model == DiffuseModel::kOrenNayarEnergy) {
      t->loss = t->fade * oren_nayar_loss(cos_l, r);
    }
    t->fade *= oren_nayar_diffuse(cos_l, cos_v, l_dot_v, r);
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
    if (!has(kShadowEffect) || !feeler.cast_shadows) return false;
    if (has(kPruningEffect)) {
      // The whole light is judged, not this sample's share of it: otherwise more samples
      // would each fall below the cutoff and soft shadows would fade.
      const float whole_light = static_cast<float>(feeler.samples);
      if (max_component(state.weight * unshadowed) * whole_light < settings_.cutoff) {
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

  // A shadow ray's first query, an any-hit test: against everything, or where anything
  // lets light through, against the opaque instances only (anything opaque in the way
  // blocks all of the light, whatever lies in front: ray.h).
  Ray first_query(Ray ray) const {
    if (has(kTranslucencyEffect)) ray.kind = kOpaqueShadowRay;
    return ray;
  }

  // Fraction of light that reaches the end of a shadow ray whose first query answered
  // `blocked` (both among `linked`, null: every instance): 0 behind anything opaque; through a
  // surface of coverage a, 1 - a passes (cut-outs), and of its covered part a*T with glass_shadows
  // tinted (coloured shadows behind glass, transmissivity T), else none (settings.h).
  Color shadow_transmittance(Ray ray, bool blocked, const Blockers* linked, int depth,
                             RayCounts* counts) const {
    counts->shadow += 1;
    if (blocked) return Color(0.0f);
    if (!has(kTranslucencyEffect)) return Color(1.0f);
    ray.kind = kTranslucentShadowRay;
    counts->shadow += 1;
    Color transmittance(1.0f);
    for (int i = 0; i < kMaxTransparentLayers; ++i) {
      Hit hit;
      if (!queries_.intersect(ray, &hit)) return transmittance;
      const Interaction it = scene_.interaction(ray, hit);
      // Under shadow linking, a surface that casts none of this light's shadows is passed.
      if (linked == nullptr || in_sets(linked->sets, scene_.shadow_sets[hit.instance])) {
        const SurfaceParams surface = scene_.surface(it, ray, RayContext{&camera_, depth});
        const float a = surface.alpha;
        const bool tinted = settings_.glass_shadows == GlassShadows::kTinted;
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

  // What a shader program may ask of a ray at `state` besides the ray.
  RayContext context(const NodeState& state) const { return {&camera_, state.depth}; }

  const CompiledScene& scene_;
  const Settings& settings_;
  const Camera& camera_;
  Queries queries_;
  uint32_t effects_;  // EffectBits
  bool emitters_;     // feelers go to emissive meshes (kEmitterEffect, and there are some)
  // Told what the kernel does: what changes in it (its position, its sums) is not the
  // kernel's state.
  [[no_unique_address]] mutable Recorder recorder_;
  // Tracing a wave (run_wave): where it stands; null in the recursion.
  WaveCursor* cursor_ = nullptr;
};

// The sets of effects a render without passes gets a kernel of its own for: those the
// analysis decides with pruning on, its default (refraction comes with reflection, as a
// transmissive material also reflects by Fresnel): 12 of the 32. A build with
// WHITTED_EFFECT_KERNELS off (CMakeLists.txt) has none, for docs/EFFECTS.md's (d).
constexpr bool specialised(uint32_t effects) {
#ifdef WHITTED_RUNTIME_EFFECTS_ONLY
  static_cast<void>(effects);
  return false;
#else
  return (effects & kPruningEffect) != 0 &&
         ((effects & kRefractionEffect) == 0 || (effects & kReflectionEffect) != 0);
#endif
}
template <uint32_t E, class Queries>
using RenderKernel = std::conditional_t<specialised(E), Kernel<E, NoRecorder, Queries>,
                                        Kernel<kRuntimeEffects, NoRecorder, Queries>>;
// Each set of effects' kernel, traced recursively and in waves.
template <class Queries>
struct RenderKernels {
  std::array<WhittedIntegrator::TraceFn, kAllEffects + 1> recursive;
  std::array<WhittedIntegrator::WaveFns, kAllEffects + 1> waves;
};
template <class Queries, size_t... E>
constexpr RenderKernels<Queries> render_kernels(std::index_sequence<E...> /*effects*/) {
  return {
      {&RenderKernel<static_cast<uint32_t>(E), Queries>::run...},
      {WhittedIntegrator::WaveFns{&RenderKernel<static_cast<uint32_t>(E), Queries>::run_camera,
                                  &RenderKernel<static_cast<uint32_t>(E), Queries>::run_wave}...}};
}
template <class Queries>
constexpr auto kRenderKernels =
    render_kernels<Queries>(std::make_index_sequence<kAllEffects + 1>{});

// The kernel of a render with these settings and effects, its queries made by Queries:
// with passes, the pass recorder's; without, the one for its effects. The benchmark's
// renders (LoggedQueries) run the same kernels as the others.
template <class Queries>
WhittedIntegrator::TraceFn render_kernel(const Settings& settings, uint32_t effects) {
  if (settings.passes != 0) return &Kernel<kRuntimeEffects, PassRecorder, Queries>::run;
  return kRenderKernels<Queries>.recursive[effects & kAllEffects];
}
// Its wave kernel: none when the settings ask for the recursion, or with passes other
// than the data passes (their recorder follows the recursion). The data passes are the
// camera's surface's: the pass recorder's kernel traces the camera rays (the first
// generation), the effects' kernel the rest, which records nothing.
template <class Queries>
WhittedIntegrator::WaveFns wave_kernel(const Settings& settings, uint32_t effects) {
  if (!settings.waves || (settings.passes & ~kDataPasses) != 0) return {};
  WhittedIntegrator::WaveFns fns = kRenderKernels<Queries>.waves[effects & kAllEffects];
  if (settings.passes != 0)
    fns.camera = &Kernel<kRuntimeEffects, PassRecorder, Queries>::run_camera;
  return fns;
}

// The camera rays' packets, queried as the kernel's queries are.
template <class Queries>
void intersect_packet_with(const WhittedIntegrator& w, const Ray* rays, int count, Hit* hits) {
  Queries(w).intersect_packet(rays, count, hits);
}

}  // namespace

RayCounts& RayCounts::operator+=(const RayCounts& o) {
  camera += o.camera;
  shadow += o.shadow;
  reflection += o.reflection;
  refraction += o.refraction;
  glossy += o.glossy;
  transparent += o.transparent;
  total_internal_reflections += o.total_internal_reflections;
  depth_limited += o.depth_limited;
  cutoff_skipped += o.cutoff_skipped;
  shadow_rays_skipped.backfacing += o.shadow_rays_skipped.backfacing;
  shadow_rays_skipped.unlit += o.shadow_rays_skipped.unlit;
  shadow_rays_skipped.cutoff += o.shadow_rays_skipped.cutoff;
  nonfinite_samples += o.nonfinite_samples;
  return *this;
}

WhittedIntegrator::WhittedIntegrator(const CompiledScene& scene, const Settings& settings,
                                     const Camera& camera, RayLog* log, RayTree* tree)
    : scene_(scene),
      settings_(settings),
      camera_(camera),
      effects_(analyse(scene, settings, camera)),
      trace_(tree != nullptr  ? &Kernel<kRuntimeEffects, TreeRecorder, SceneQueries>::run
             : log != nullptr ? render_kernel<LoggedQueries>(settings, effects_.bits)
                              : render_kernel<SceneQueries>(settings, effects_.bits)),
      intersect_packet_(log != nullptr ? &intersect_packet_with<LoggedQueries>
                                       : &intersect_packet_with<SceneQueries>),
      trace_wave_(tree != nullptr  ? WhittedIntegrator::WaveFns{}
                  : log != nullptr ? wave_kernel<LoggedQueries>(settings, effects_.bits)
                                   : wave_kernel<SceneQueries>(settings, effects_.bits)),
      log_(log),
      tree_(tree) {
  if (log != nullptr && tree != nullptr) {
    throw std::invalid_argument(
        "the inspector's ray tree and a query log are never traced together");
  }
}

// Walks a ray from p through every surface: a transmissive surface the walk leaves
// without having entered it encloses p. The first such surface is the innermost medium.
MediumStack WhittedIntegrator::media_at(const Vec3& p) const {
  // An arbitrary direction unlikely to graze edges of axis-aligned models.
  Ray ray{p, glm::normalize(Vec3(0.3717f, 0.5419f, 0.7537f)), 0.0f, kInfinity, kRefractionRay};
  std::vector<uint32_t> enclosing;  // innermost first
  std::vector<int> entered(scene_.materials.size(), 0);
  for (int i = 0; i < limits::kMaxMediaCrossings; ++i) {
    Hit hit;
    if (!scene_.accel->intersect(ray, &hit)) break;
    const Interaction it = scene_.interaction(ray, hit);
    if (it.material->transmissive()) {
      if (glm::dot(ray.direction, it.geometric_normal) < 0.0f) {
        entered[it.material_index] += 1;
      } else if (entered[it.material_index] > 0) {
        entered[it.material_index] -= 1;
      } else {
        enclosing.push_back(it.material_index);
      }
    }
    ray = spawn_ray(it.position, it.position_error, it.geometric_normal, it.time, ray.direction,
                    kRefractionRay);
  }
  MediumStack media;
  for (auto m = enclosing.rbegin(); m != enclosing.rend(); ++m) {
    media.enter(*m, scene_.materials[*m].priority);
  }
  return media;
}

}  // namespace whitted
