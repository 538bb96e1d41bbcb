#include "integrator/whitted.h"

#include <cmath>
#include <type_traits>

#include "core/limits.h"

namespace whitted {
namespace {

using limits::kMaxTransparentLayers;

// IOR of a medium (-1 is the surrounding air): its material's constant ior, since a
// program's ior belongs to a hit, not to the volume behind it.
float ior_of(const CompiledScene& scene, int32_t medium) {
  return medium < 0 ? 1.0f : scene.materials[static_cast<size_t>(medium)].ior;
}

// The coat of a hit as the ray sees it: a clear layer over the base whose reflectance is
// its weights times the exact dielectric Fresnel factor of its IOR at its own normal; the
// base beneath receives the rest, 1 - cover, of the light.
struct Coat {
  float highlight = 0.0f;  // weight of its Phong highlight
  float mirror = 0.0f;     // weight of its mirror reflection
  float cover = 0.0f;      // highlight + mirror: the share it takes from the base
  float shininess = 1.0f;
  Vec3 normal{0.0f, 0.0f, 1.0f};  // facing the ray
};

Coat coat_of(const SurfaceParams& surface, const Vec3& wo, const Vec3& ng, bool entering) {
  Coat coat;
  const float weight = surface.coat_specular + surface.coat_reflectivity;
  if (!(weight > 0.0f)) return coat;
  coat.normal = entering ? surface.coat_normal : -surface.coat_normal;
  if (glm::dot(coat.normal, ng) <= 0.0f) coat.normal = ng;  // as the base's normal
  const float f = fresnel_exact(glm::dot(wo, coat.normal), 1.0f / surface.coat_ior);
  const float scale = f / std::max(weight, 1.0f);  // weights beyond 1 cover all
  coat.highlight = std::max(surface.coat_specular, 0.0f) * scale;
  coat.mirror = std::max(surface.coat_reflectivity, 0.0f) * scale;
  coat.cover = coat.highlight + coat.mirror;
  coat.shininess = surface.coat_shininess;
  return coat;
}

// The coat's highlight for light arriving from wi, per unit irradiance: the normalised
// Phong lobe ks*(f+2)/(2pi)*(v.r)^f*(l.n) about the coat's normal.
float coat_highlight(const Coat& coat, const Vec3& wo, const Vec3& wi) {
  if (coat.highlight <= 0.0f) return 0.0f;
  const float cos_l = glm::dot(coat.normal, wi);
  if (cos_l <= 0.0f) return 0.0f;
  const float v_dot_r = std::max(0.0f, glm::dot(wo, reflect(-wi, coat.normal)));
  return coat.highlight * (coat.shininess + 2.0f) * (0.5f * kInvPi) *
         std::pow(v_dot_r, coat.shininess) * cos_l;
}

// The pass listener of a kernel that records no passes: it is never called.
struct NoRecorder {
  NoRecorder(const CompiledScene& /*scene*/, const Settings& /*settings*/, const Camera& /*camera*/,
             SampleRecord* /*record*/) {}
};

// The Whitted recursion, with the effects the analysis chose (EffectBits) as run-time
// flags: compiling a kernel per set of effects measured no faster (docs/EFFECTS.md). With
// kRecord (the inspector only) every ray and term also goes into the integrator's
// RayTree; renders run the kernel without it. With a Recorder other than NoRecorder
// (PassRecorder, passes.h: renders with passes) the kernel also tells it, node by node,
// where each share of a sample's radiance comes from; with NoRecorder none of that is
// compiled in.
template <bool kRecord, class Recorder>
class Kernel {
  static constexpr bool kPasses = !std::is_same_v<Recorder, NoRecorder>;

 public:
  Kernel(const WhittedIntegrator& w, SampleRecord* record)
      : scene_(w.scene()),
        settings_(w.settings()),
        camera_(w.camera()),
        log_(w.log()),
        tree_(w.tree()),
        effects_(w.effects().bits),
        recorder_(w.scene(), w.settings(), w.camera(), record) {}

  static Color run(const WhittedIntegrator& w, const Ray& ray, const PathState& path,
                   RayCounts* counts, float* alpha, const Hit* first, SampleRecord* record) {
    return Kernel(w, record).trace(ray, path, counts, alpha, first);
  }

 private:
  bool has(uint32_t bit) const { return (effects_ & bit) != 0; }

  // Every query of the kernel goes through these two (and into the log when recording).
  bool intersect(const Ray& ray, Hit* hit) const {
    if (log_ != nullptr && log_->active) log_->queries.push_back({ray, false});
    return scene_.accel->intersect(ray, hit);
  }
  bool occluded(const Ray& ray) const {
    if (log_ != nullptr && log_->active) log_->queries.push_back({ray, true});
    return scene_.accel->occluded(ray);
  }

  // Along a ray, through cut-outs: each surface adds its share, the rest goes on behind.
  // `first`, when given, is the ray's first hit, already found.
  Color trace(const Ray& ray, const PathState& path, RayCounts* counts, float* alpha,
              const Hit* first = nullptr) const {
    Color radiance(0.0f);
    float coverage = 0.0f;
    float behind = 1.0f;  // the share of the ray not yet covered by a surface
    Ray r = ray;
    [[maybe_unused]] int previous = -1;  // recording: the layer in front of this one
    for (int layer = 0; behind > 0.0f; ++layer) {
      Hit hit;
      bool found = false;
      if (layer == 0 && first != nullptr) {
        hit = *first;
        found = hit.t < kInfinity;
      } else {
        found = intersect(r, &hit);
      }
      [[maybe_unused]] int node = -1;  // recording: this layer's node
      if constexpr (kRecord) {
        node = record_ray(r, path, layer == 0 ? tree_->next_kind : TreeRayKind::kTransparent,
                          layer == 0 ? tree_->current : previous, Color(behind));
      }
      if (!found) {
        // A transparent film shows nothing where camera rays miss.
        const bool shown = !(settings_.transparent_background && ray.kind == kCameraRay);
        if (shown) {
          const Color background = scene_.world_radiance(r, context(path));
          radiance += behind * background;
          coverage += behind;
          if constexpr (kRecord) record_background(node, background);
          if constexpr (kPasses) {
            recorder_.escaped(path.depth, path.throughput * behind, background, true);
          }
        } else if constexpr (kPasses) {
          recorder_.escaped(path.depth, path.throughput * behind,
                            scene_.world_radiance(r, context(path)), false);
        }
        break;
      }
      const Interaction it = scene_.interaction(r, hit);
      if constexpr (kRecord) record_end(node, it);
      if (it.holdout) break;  // a holdout shows nothing and covers nothing
      const SurfaceParams surface = scene_.surface(it, r, context(path));
      float a = 1.0f;
      if (has(kTranslucencyEffect)) {
        a = layer == kMaxTransparentLayers ? 1.0f : surface.alpha;
      }
      if (a > 0.0f) {
        if constexpr (kRecord) {
          const RayTree::Scope scope(tree_, node, tree_->nodes[node].weight * a);
          radiance += (behind * a) * shade(r, it, surface, path, counts);
        } else if constexpr (kPasses) {
          // This layer's share of the sample, for what the recorder is told below it.
          PathState layer = path;
          layer.throughput = path.throughput * (behind * a);
          if (path.depth == 0) {
            Vec3 ng;
            Vec3 ns;
            facing_normals(r, it, surface, &ng, &ns);
            recorder_.camera_surface(it, surface, ns, max_component(layer.throughput));
          }
          radiance += (behind * a) * shade(r, it, surface, layer, counts);
        } else {
          radiance += (behind * a) * shade(r, it, surface, path, counts);
        }
        coverage += behind * a;
      }
      if constexpr (kRecord) previous = node;
      behind *= 1.0f - a;
      if (behind <= 0.0f) break;
      // The rest of the ray continues behind the cut-out, as far as it was allowed to go.
      const float left = r.t_max - glm::length(it.position - r.origin);
      if (!(left > 0.0f)) break;
      r = spawn_ray(it.position, it.position_error, it.geometric_normal, r.direction,
                    RayKind(r.kind), left);
      counts->transparent += 1;
    }
    if (alpha != nullptr) *alpha = coverage;
    return radiance;
  }

  // Radiance leaving a surface point towards the ray: the Whitted step.
  Color shade(const Ray& ray, const Interaction& it, const SurfaceParams& surface,
              const PathState& path, RayCounts* counts) const {
    const Material& m = *it.material;
    // Entering or leaving is decided by the geometric normal, never the shading normal.
    const bool entering = glm::dot(ray.direction, it.geometric_normal) < 0.0f;
    MediumStack media = path.media;  // the media on the far side of this surface
    float eta = 1.0f;                // eta_incident / eta_transmitted
    if (has(kRefractionEffect) && m.transmissive()) {
      const int32_t from = media.current();
      bool false_interface = false;  // the current medium stays what it was
      if (entering) {
        false_interface = from >= 0 && m.priority < scene_.materials[from].priority;
        media.enter(it.material_index, m.priority);
        eta = ior_of(scene_, from) / surface.ior;
      } else if (media.leave(it.material_index)) {
        false_interface = from != static_cast<int32_t>(it.material_index);
        eta = surface.ior / ior_of(scene_, media.current());
      } else {
        // Leaving a medium it never entered (flipped normals, an open mesh): out into the
        // current medium, as a renderer without media lists would.
        eta = surface.ior / ior_of(scene_, from);
      }
      if (false_interface) {
        counts->transparent += 1;
        return branch(spawn_ray(it.position, it.position_error, it.geometric_normal, ray.direction,
                                RayKind(ray.kind)),
                      path, Color(1.0f), media, /*bounce=*/false, TreeRayKind::kTransparent,
                      counts);
      }
    }
    Vec3 ng;
    Vec3 ns;
    facing_normals(ray, it, surface, &ng, &ns);
    const Vec3 wo = -ray.direction;
    const Coat coat = coat_of(surface, wo, ng, entering);
    if constexpr (kRecord) tree_->nodes[tree_->current].emission = tree_->scale * surface.emission;
    NodeTerms terms;  // filled only by kernels that record passes
    Color radiance = surface.emission + local(it, surface, coat, wo, ng, ns, path, counts, &terms);
    if constexpr (kPasses) {
      terms.emission = surface.emission;
      terms.total = radiance;
      terms.diffuse_color = (1.0f - coat.cover) * surface.diffuse;
      terms.specular_color = (1.0f - coat.cover) * surface.specular + Color(coat.highlight);
      recorder_.node(path.depth, path.throughput, terms);
    }
    if (!has(kReflectionEffect) && !has(kRefractionEffect)) return radiance;

    Color kr = has(kReflectionEffect) ? surface.reflectivity : Color(0.0f);
    Color kt = has(kRefractionEffect) ? surface.transmissivity : Color(0.0f);
    if (is_black(kr) && is_black(kt) && coat.mirror <= 0.0f) return radiance;
    Vec3 t_dir(0.0f);
    bool total_internal_reflection = false;
    const bool refracts = has(kRefractionEffect) && refract(ray.direction, ns, eta, &t_dir) &&
                          glm::dot(t_dir, ng) < 0.0f;
    if (!is_black(kt)) {
      const float cos_i = std::min(1.0f, glm::dot(wo, ns));
      const float f = !refracts                                ? 1.0f
                      : settings_.fresnel == Fresnel::kExact   ? fresnel_exact(cos_i, eta)
                      : settings_.fresnel == Fresnel::kSchlick ? fresnel_schlick(cos_i, eta)
                                                               : 0.0f;
      // The reflected share of the transmissive layer: all of it on total internal
      // reflection.
      kr += kt * f;
      kt *= 1.0f - f;
      total_internal_reflection = !refracts;
      if (!refracts) counts->total_internal_reflections += 1;
    }
    // The coat's mirror on top; beneath it, the base's rays get what the coat lets through.
    // One mirror ray: about the coat's normal where the coat gives most of its weight.
    const bool coat_ray = coat.mirror > (1.0f - coat.cover) * max_component(kr);
    kr = (1.0f - coat.cover) * kr + Color(coat.mirror);
    kt *= 1.0f - coat.cover;
    // A surface returns at most what arrives: sigma_r + sigma_t <= 1 keeps the ray tree
    // from growing without bound (two facing mirror-glass panes at depth 256).
    const float sum = max_component(kr + kt);
    if (sum > 1.0f) {
      kr /= sum;
      kt /= sum;
    }
    if (has(kReflectionEffect) && !is_black(kr)) {
      Vec3 r = reflect(ray.direction, coat_ray ? coat.normal : ns);
      if (glm::dot(r, ng) <= 0.0f) r = reflect(ray.direction, ng);  // below the surface
      const Color reflected =
          branch(spawn_ray(it.position, it.position_error, it.geometric_normal, r, kReflectionRay),
                 path, kr, path.media, /*bounce=*/true,
                 total_internal_reflection ? TreeRayKind::kTotalInternalReflection
                                           : TreeRayKind::kReflection,
                 counts);
      radiance += kr * reflected;
      if constexpr (kPasses) recorder_.reflected(path.depth, path.throughput, kr, reflected);
    }
    if (refracts && !is_black(kt)) {
      const Color refracted = branch(
          spawn_ray(it.position, it.position_error, it.geometric_normal, t_dir, kRefractionRay),
          path, kt, media, /*bounce=*/true, TreeRayKind::kRefraction, counts);
      radiance += kt * refracted;
      if constexpr (kPasses) recorder_.refracted(path.depth, path.throughput, kt, refracted);
    }
    return radiance;
  }

  // Traces a secondary ray of weight `weight` (relative to this one), unless the depth or
  // the cutoff stops it; `bounce` is false for a ray that only continues straight on
  // (`kind` names it for the inspector). The one place the ray tree branches.
  Color branch(const Ray& ray, const PathState& path, const Color& weight, const MediumStack& media,
               bool bounce, [[maybe_unused]] TreeRayKind kind, RayCounts* counts) const {
    PathState next{bounce ? path.depth + 1 : path.depth, path.weight * weight, media};
    if constexpr (kPasses) next.throughput = path.throughput * weight;
    if (next.depth > settings_.max_depth) {
      counts->depth_limited += 1;
      if constexpr (kRecord) record_cut(ray, next, kind, weight, TreeCut::kDepth);
      if constexpr (kPasses) recorder_.cut(next.throughput);
      return Color(0.0f);
    }
    if (max_component(next.weight) < settings_.cutoff) {
      counts->cutoff_skipped += 1;  // its contribution could no longer show
      if constexpr (kRecord) record_cut(ray, next, kind, weight, TreeCut::kCutoff);
      if constexpr (kPasses) recorder_.cut(next.throughput);
      return Color(0.0f);
    }
    if (bounce && ray.kind == kReflectionRay) counts->reflection += 1;
    if (bounce && ray.kind == kRefractionRay) counts->refraction += 1;
    if constexpr (kRecord) {
      const RayTree::Scope scope(tree_, tree_->current, tree_->scale * weight, kind);
      return trace(ray, next, counts, nullptr);
    }
    return trace(ray, next, counts, nullptr);
  }

  // I = (1 - coat) * [Ia*ka*kd + sum_i delta_i * (kd/pi + ks*(f+2)/(2pi)*(v.r)^f) * E_i * (l.n)]
  //     + sum_i delta_i * coat_highlight_i * E_i
  // A kernel that records passes also splits it into `terms` (ambient, diffuse, specular:
  // the coat's highlight counts as specular); the sum returned is the same either way.
  Color local(const Interaction& it, const SurfaceParams& surface, const Coat& coat, const Vec3& wo,
              const Vec3& ng, const Vec3& n, const PathState& path, RayCounts* counts,
              NodeTerms* terms) const {
    const float base = 1.0f - coat.cover;
    Color radiance = base * it.material->ambient * scene_.ambient * surface.diffuse;
    if constexpr (kPasses) terms->ambient = radiance;
    if constexpr (kRecord) tree_->nodes[tree_->current].ambient = tree_->scale * radiance;
    const float phong_norm = (surface.shininess + 2.0f) * (0.5f * kInvPi);
    // The interpolated normal on the ray's side: a program's normal fades the diffuse
    // lobe towards its horizon as Cycles does (diffuse_shadowing).
    const Vec3 smooth =
        glm::dot(it.geometric_normal, ng) > 0.0f ? it.shading_normal : -it.shading_normal;
    for (const Light& light : scene_.lights) {
      for (int s = 0; s < light.sample_count(); ++s) {
        const LightSample ls = sample_light(light, it.position, s);
        const float cos_l = glm::dot(n, ls.wi);
        [[maybe_unused]] int feeler = -1;  // recording: this feeler's node
        if constexpr (kRecord) feeler = record_feeler(it, ls, light, path);
        // The shading normal decides whether a light is behind the (smooth) surface, not
        // the flat facet: gating on the facet draws stair-steps along the terminator of a
        // coarse smooth mesh.
        if (has(kPruningEffect)) {
          if (cos_l <= 0.0f) {
            counts->shadow_rays_skipped.backfacing += 1;
            if constexpr (kRecord) tree_->nodes[feeler].cut = TreeCut::kBackfacing;
            continue;
          }
          if (is_black(ls.irradiance)) {
            counts->shadow_rays_skipped.unlit += 1;  // outside a spot's cone, behind an area light
            if constexpr (kRecord) tree_->nodes[feeler].cut = TreeCut::kUnlit;
            continue;
          }
        }
        const float v_dot_r = std::max(0.0f, glm::dot(wo, reflect(-ls.wi, n)));
        const float fade = diffuse_shadowing(it.material->bump_shadowing, smooth, n, ls.wi);
        const Color brdf = surface.diffuse * (kInvPi * fade) +
                           surface.specular * (phong_norm * std::pow(v_dot_r, surface.shininess));
        const Color contribution =
            (base * std::max(0.0f, cos_l) * brdf + Color(coat_highlight(coat, wo, ls.wi))) *
            ls.irradiance;
        if constexpr (kRecord) {
          // The coat's highlight counts as specular.
          const Color arriving = tree_->scale * ls.irradiance;
          const float lit = base * std::max(0.0f, cos_l);
          tree_->nodes[feeler].diffuse = arriving * (lit * kInvPi * fade) * surface.diffuse;
          tree_->nodes[feeler].specular =
              arriving *
              (lit * phong_norm * std::pow(v_dot_r, surface.shininess) * surface.specular +
               Color(coat_highlight(coat, wo, ls.wi)));
          tree_->nodes[feeler].cut = TreeCut::kUnshadowed;  // until a feeler is sent
        }
        // The diffuse and specular shares of a light that arrives through `transmittance`.
        const auto record = [&](const Color& transmittance) {
          if constexpr (kPasses) {
            const Color light_in = ls.irradiance * transmittance;
            const float lit = base * std::max(0.0f, cos_l);
            terms->diffuse += (lit * kInvPi * fade) * surface.diffuse * light_in;
            terms->specular +=
                (lit * surface.specular * (phong_norm * std::pow(v_dot_r, surface.shininess)) +
                 Color(coat_highlight(coat, wo, ls.wi))) *
                light_in;
          }
        };
        if (!has(kShadowEffect) || !light.cast_shadows) {
          radiance += contribution;
          record(Color(1.0f));
          continue;
        }
        if (has(kPruningEffect)) {
          // Lit or not, this light cannot change the pixel by more than the cutoff. The
          // whole light is judged, not this feeler's share of it: otherwise more samples
          // would each fall below the cutoff and soft shadows would fade.
          const float whole_light = static_cast<float>(light.sample_count());
          if (max_component(path.weight * contribution) * whole_light < settings_.cutoff) {
            counts->shadow_rays_skipped.cutoff += 1;
            radiance += contribution;
            record(Color(1.0f));
            continue;
          }
        }
        // Stop the feeler just short of the light sample.
        const float t_max =
            std::isinf(ls.distance) ? kInfinity : ls.distance * (1.0f - limits::kFeelerShortening);
        const Ray shadow_ray =
            spawn_ray(it.shadow_origin, it.position_error, ng, ls.wi, kShadowRay, t_max);
        const Color transmittance = shadow_transmittance(shadow_ray, path, counts);
        if constexpr (kRecord) record_shadow(feeler, shadow_ray, transmittance);
        radiance += contribution * transmittance;
        record(transmittance);
      }
    }
    return radiance;
  }

  // Fraction of light that reaches the end of a shadow feeler: 0 behind anything opaque;
  // through a surface of coverage a, 1 - a passes (cut-outs), and of its covered part
  // a*T with glass_shadows tinted (coloured shadows behind glass, transmissivity T), else
  // none (settings.h).
  Color shadow_transmittance(Ray ray, const PathState& path, RayCounts* counts) const {
    counts->shadow += 1;
    if (!has(kTranslucencyEffect)) {
      return occluded(ray) ? Color(0.0f) : Color(1.0f);
    }
    // Anything opaque in the way blocks all of it, whatever lies in front (ray.h).
    ray.kind = kOpaqueShadowRay;
    if (occluded(ray)) return Color(0.0f);
    ray.kind = kTranslucentShadowRay;
    counts->shadow += 1;
    Color transmittance(1.0f);
    for (int i = 0; i < kMaxTransparentLayers; ++i) {
      Hit hit;
      if (!intersect(ray, &hit)) return transmittance;
      const Interaction it = scene_.interaction(ray, hit);
      const SurfaceParams surface = scene_.surface(it, ray, context(path));
      const float a = surface.alpha;
      const bool tinted = settings_.glass_shadows == GlassShadows::kTinted;
      transmittance *= (1.0f - a) + a * (tinted ? surface.transmissivity : Color(0.0f));
      if (is_black(transmittance)) return transmittance;
      const float remaining = ray.t_max - glm::length(it.position - ray.origin);
      if (!(remaining > 0.0f)) return transmittance;
      ray = spawn_ray(it.position, it.position_error, it.geometric_normal, ray.direction,
                      kTranslucentShadowRay, remaining);
      counts->shadow += 1;
    }
    return Color(0.0f);
  }

  // The geometric and shading normals of a hit turned to face the ray; a shading normal
  // cannot face away.
  static void facing_normals(const Ray& ray, const Interaction& it, const SurfaceParams& surface,
                             Vec3* ng, Vec3* ns) {
    // Entering or leaving is decided by the geometric normal, never the shading normal.
    const bool entering = glm::dot(ray.direction, it.geometric_normal) < 0.0f;
    *ng = entering ? it.geometric_normal : -it.geometric_normal;
    *ns = entering ? surface.normal : -surface.normal;
    if (glm::dot(*ns, *ng) <= 0.0f) *ns = *ng;
  }

  // What a shader program may ask of a ray on `path` besides the ray.
  RayContext context(const PathState& path) const { return {&camera_, path.depth}; }

  // The inspector's records (kRecord only): a ray of the tree, `share` its part of the
  // weight the tree's position carries (the part not yet covered by cut-outs in front,
  // or the sigma_r / sigma_t of the surface being shaded).
  int record_ray(const Ray& ray, const PathState& path, TreeRayKind kind, int parent,
                 const Color& share) const {
    RayTreeNode node;
    node.kind = kind;
    node.depth = path.depth;
    node.origin = ray.origin;
    node.direction = ray.direction;
    node.weight = tree_->scale * share;
    return tree_->add(node, parent);
  }
  void record_end(int node, const Interaction& it) const {
    RayTreeNode& n = tree_->nodes[static_cast<size_t>(node)];
    n.hit = true;
    n.end = it.position;
    n.instance = static_cast<int32_t>(it.instance);
    n.material = static_cast<int32_t>(it.material_index);
  }
  void record_background(int node, const Color& background) const {
    RayTreeNode& n = tree_->nodes[static_cast<size_t>(node)];
    n.background = n.weight * background;
  }
  // A secondary ray of `weight` (relative to the surface being shaded) that was not traced.
  void record_cut(const Ray& ray, const PathState& next, TreeRayKind kind, const Color& weight,
                  TreeCut cut) const {
    const int node = record_ray(ray, next, kind, tree_->current, weight);
    tree_->nodes[static_cast<size_t>(node)].cut = cut;
  }
  int record_feeler(const Interaction& it, const LightSample& ls, const Light& light,
                    const PathState& path) const {
    RayTreeNode node;
    node.kind = TreeRayKind::kShadow;
    node.depth = path.depth;
    node.origin = it.shadow_origin;
    node.direction = ls.wi;
    node.light = static_cast<int32_t>(&light - scene_.lights.data());
    node.weight = tree_->scale;
    if (!std::isinf(ls.distance)) node.end = it.shadow_origin + ls.wi * ls.distance;
    return tree_->add(node, tree_->current);
  }
  // A feeler that was sent: what got through, and the first surface in its way, if any.
  void record_shadow(int feeler, const Ray& ray, const Color& transmittance) const {
    RayTreeNode& node = tree_->nodes[static_cast<size_t>(feeler)];
    node.cut = TreeCut::kNone;
    node.transmittance = transmittance;
    Hit hit;
    if (transmittance != Color(1.0f) && scene_.accel->intersect(ray, &hit)) {
      record_end(feeler, scene_.interaction(ray, hit));
    }
  }

  const CompiledScene& scene_;
  const Settings& settings_;
  const Camera& camera_;
  RayLog* log_;
  RayTree* tree_;
  uint32_t effects_;  // EffectBits
  [[no_unique_address]] Recorder recorder_;
};

}  // namespace

RayCounts& RayCounts::operator+=(const RayCounts& o) {
  camera += o.camera;
  shadow += o.shadow;
  reflection += o.reflection;
  refraction += o.refraction;
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
      effects_(analyse(scene, settings)),
      trace_(tree != nullptr        ? &Kernel<true, NoRecorder>::run
             : settings.passes != 0 ? &Kernel<false, PassRecorder>::run
                                    : &Kernel<false, NoRecorder>::run),
      log_(log),
      tree_(tree) {}

void WhittedIntegrator::intersect_packet(const Ray* rays, int count, Hit* hits) const {
  if (log_ != nullptr && log_->active) {
    for (int i = 0; i < count; ++i) log_->queries.push_back({rays[i], false});
  }
  scene_.accel->intersect_packet(rays, count, hits);
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
    ray = spawn_ray(it.position, it.position_error, it.geometric_normal, ray.direction,
                    kRefractionRay);
  }
  MediumStack media;
  for (auto m = enclosing.rbegin(); m != enclosing.rend(); ++m) {
    media.enter(*m, scene_.materials[*m].priority);
  }
  return media;
}

}  // namespace whitted
