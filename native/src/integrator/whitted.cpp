// The kernel a render runs (kernel.h holds the Whitted step itself): one per recorder,
// way of querying, set of effects and policy, chosen once per render, and the
// integrator's other entry points.
#include "integrator/whitted.h"

#include <array>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "core/limits.h"
#include "integrator/kernel.h"
#include "integrator/kernel_recorder.h"
#include "integrator/recorder.h"
#include "integrator/tree_recorder.h"
#include "integrator/wave.h"

namespace whitted {
namespace {

// How a kernel asks Embree its queries, chosen at compile time (the product's kernels
// have no branch per query for the benchmark's log). Here, of internal linkage, so each
// kernel (kernel.h), its members and the concepts' templates it instantiates are too:
// GCC then inlines the step's helpers called once and trims their arguments, as when
// the kernel was one class here; with external linkage the demo scene took 1.6% (waves)
// and 2.8% (recursion) more instructions (callgrind, docs/notes/waves.md's command).
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
template <uint32_t E, class Queries, class Policy>
using RenderKernel = std::conditional_t<specialised(E), Kernel<E, NoRecorder, Queries, Policy>,
                                        Kernel<kRuntimeEffects, NoRecorder, Queries, Policy>>;
// With passes: the pass recorder's, the effects read at run time.
template <class Queries, class Policy>
using PassKernel = Kernel<kRuntimeEffects, PassRecorder, Queries, Policy>;
// Each set of effects' kernel, traced recursively (Recurse) and in waves (Enqueue).
template <class Queries>
struct RenderKernels {
  std::array<WhittedIntegrator::TraceFn, kAllEffects + 1> recursive;
  std::array<WhittedIntegrator::WaveFns, kAllEffects + 1> waves;
};
template <class Queries, size_t... E>
constexpr RenderKernels<Queries> render_kernels(std::index_sequence<E...> /*effects*/) {
  return {{&RenderKernel<static_cast<uint32_t>(E), Queries, Recurse>::run...},
          {WhittedIntegrator::WaveFns{
              &wave_camera<RenderKernel<static_cast<uint32_t>(E), Queries, Enqueue>>,
              &wave_rest<RenderKernel<static_cast<uint32_t>(E), Queries, Enqueue>>}...}};
}
template <class Queries>
constexpr auto kRenderKernels =
    render_kernels<Queries>(std::make_index_sequence<kAllEffects + 1>{});

// The kernel of a render with these settings and effects, its queries made by Queries:
// with passes, the pass recorder's; without, the one for its effects. The benchmark's
// renders (LoggedQueries) run the same kernels as the others.
template <class Queries>
WhittedIntegrator::TraceFn render_kernel(const Settings& settings, uint32_t effects) {
  if ((settings.passes & kRecordedPasses) != 0) return &PassKernel<Queries, Recurse>::run;
  return kRenderKernels<Queries>.recursive[effects & kAllEffects];
}
// Its wave kernel: none when the settings ask for the recursion. With passes, the pass
// recorder's; with the data passes alone, which are the camera's surface's, only for
// the camera rays (the first generation), the effects' kernel for the rest.
template <class Queries>
WhittedIntegrator::WaveFns wave_kernel(const Settings& settings, uint32_t effects) {
  if (!settings.waves) return {};
  using Passes = PassKernel<Queries, Enqueue>;
  if ((settings.passes & kRecordedPasses & ~kDataPasses) != 0) {
    return {&wave_camera<Passes>, &wave_rest<Passes>};
  }
  WhittedIntegrator::WaveFns fns = kRenderKernels<Queries>.waves[effects & kAllEffects];
  if ((settings.passes & kRecordedPasses) != 0) fns.camera = &wave_camera<Passes>;
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
  world_feelers += o.world_feelers;
  volume_feelers += o.volume_feelers;
  volume_queries += o.volume_queries;
  volume_bounds += o.volume_bounds;
  volume_steps += o.volume_steps;
  ambient_occlusion += o.ambient_occlusion;
  bevel += o.bevel;
  return *this;
}

WhittedIntegrator::WhittedIntegrator(const CompiledScene& scene, const Settings& settings,
                                     const Camera& camera, RayLog* log, RayTree* tree)
    : scene_(scene),
      settings_(settings),
      camera_(camera),
      effects_(analyse(scene, settings, camera)),
      trace_(tree != nullptr  ? &Kernel<kRuntimeEffects, TreeRecorder, SceneQueries, Recurse>::run
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

// Walks a ray from p through every surface: a transmissive surface (or, in a scene with
// media, a volume's bound) the walk leaves without having entered it encloses p. The
// first such surface is the innermost medium.
MediumStack WhittedIntegrator::media_at(const Vec3& p) const {
  const bool volumes = effects_.has(kVolumeEffect);
  // An arbitrary direction unlikely to graze edges of axis-aligned models.
  Ray ray{p, glm::normalize(Vec3(0.3717f, 0.5419f, 0.7537f)), 0.0f, kInfinity,
          volumes ? kRefractionRay | kVolumeBoundRay : kRefractionRay};
  std::vector<std::pair<uint32_t, uint32_t>> enclosing;  // (material, instance), innermost first
  std::vector<int> entered(scene_.materials.size(), 0);
  for (int i = 0; i < limits::kMaxMediaCrossings; ++i) {
    Hit hit;
    if (!scene_.accel->intersect(ray, &hit)) break;
    const Interaction it = scene_.interaction(ray, hit);
    const Material& m = *it.material;
    if (m.transmissive() || (volumes && !m.surface && m.participating())) {
      if (glm::dot(ray.direction, it.geometric_normal) < 0.0f) {
        entered[it.material_index] += 1;
      } else if (entered[it.material_index] > 0) {
        entered[it.material_index] -= 1;
      } else {
        enclosing.emplace_back(it.material_index, it.instance);
      }
    }
    ray = spawn_ray(it.position, it.position_error, it.geometric_normal, it.time, ray.direction,
                    RayKind(ray.kind));
  }
  MediumStack media;
  for (auto m = enclosing.rbegin(); m != enclosing.rend(); ++m) {
    const Material& material = scene_.materials[m->first];
    if (material.surface) {
      media.enter(m->first, m->second, material.priority);
    } else {
      media.enter_bound(m->first, m->second);  // a volume's bound
    }
  }
  return media;
}

}  // namespace whitted
