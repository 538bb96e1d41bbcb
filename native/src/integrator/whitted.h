// The Whitted (1980) integrator: local Phong shading gated by shadow rays, plus mirror
// reflection and refraction, recursing to a maximum depth. Its vocabulary is the paper's:
// sigma_r and sigma_t are the weights of the reflected and refracted rays after the
// Fresnel split (a material's reflectivity and transmissivity are their values before
// it); a shadow ray is what the lecture calls a feeler (hence Settings::feeler_pruning).
#pragma once

#include <cstdint>
#include <vector>

#include "integrator/analysis.h"
#include "integrator/medium.h"
#include "integrator/passes.h"
#include "integrator/ray_tree.h"
#include "integrator/recorder.h"
#include "integrator/settings.h"
#include "scene/scene.h"

namespace whitted {

struct Wave;

// Rays traced by type, and rays not traced by reason, per thread, summed after each tile.
// Named as in the statistics dict and JSON (addon/stats.py).
struct RayCounts {
  uint64_t camera = 0;
  uint64_t shadow = 0;
  uint64_t reflection = 0;
  uint64_t refraction = 0;
  uint64_t glossy = 0;                      // reflections drawn from a glossy lobe
  uint64_t transparent = 0;                 // continuations behind cut-outs (alpha < 1)
  uint64_t total_internal_reflections = 0;  // refracted rays that became reflections
  uint64_t depth_limited = 0;               // secondary rays not traced: maximum depth
  uint64_t cutoff_skipped = 0;              // secondary rays not traced: weight below cutoff
  // Shadow rays not sent, by reason.
  struct ShadowRaysSkipped {
    uint64_t backfacing = 0;  // the light is behind the surface
    uint64_t unlit = 0;       // no light arrives (outside a spot's cone, behind an area light)
    uint64_t cutoff = 0;      // the light's contribution is below the cutoff
  } shadow_rays_skipped;
  uint64_t nonfinite_samples = 0;  // samples discarded as NaN or infinite
  uint64_t world_feelers = 0;      // light samples drawn towards the world (scene/world_light.h)
  // Feelers to the lamps, emitters and world from points inside a medium (in-scattering,
  // integrator/volume.h; among `shadow`), the queries that walked shadow feelers through
  // volume bounds (transmittance.h) or looked for a surface in a bound's plane (kernel.h),
  // and the rays going on behind the volume bounds they crossed (kernel.h).
  uint64_t volume_feelers = 0;
  uint64_t volume_queries = 0;
  uint64_t volume_bounds = 0;
  // Points a heterogeneous medium's program ran at along the segments and feelers that
  // crossed it (integrator/heterogeneous.h, march.h).
  uint64_t volume_steps = 0;
  // Rays an Ambient Occlusion node traced from the hits its program ran at (shader/program.h
  // HitRays).
  uint64_t ambient_occlusion = 0;
  // Queries a Bevel node's probes made near the hits its program ran at.
  uint64_t bevel = 0;

  RayCounts& operator+=(const RayCounts& o);
  // A secondary ray of kind `kind` traced: drawn from a glossy lobe (`glossy`), or a
  // mirror reflection or a refraction where it bounces off a surface (`bounce`).
  void traced(uint32_t kind, bool bounce, bool glossy) {
    if (glossy) {
      this->glossy += 1;
    } else if (bounce && kind == kReflectionRay) {
      reflection += 1;
    }
    if (bounce && kind == kRefractionRay) refraction += 1;
  }
  // The rays media cost besides their feelers: the continuations through volume bounds
  // and the queries through them (0 in a scene without media).
  uint64_t volume() const { return volume_bounds + volume_queries; }
  // Every ray traced (the Whitted Rays pass counts each pixel's).
  uint64_t total() const {
    return camera + shadow + reflection + refraction + glossy + transparent + volume() +
           ambient_occlusion + bevel;
  }
};

// A ray drawn from a glossy lobe, as the kernel's branch takes it: its share of the lobe,
// the seed of the strata below it, its index in the pixel's sequences (NodeState::index)
// and its density for MIS (NodeState::mis).
struct Drawn {
  float share;
  uint32_t seed;
  uint32_t index;
  float mis;
  float world_weight = 1.0f;  // NodeState::world_weight
  float lamp_density = 0.0f;  // NodeState::lamp_density
};

// Where a ray stands in its ray tree: its recursion depth, its weight on the pixel (the
// product of the sigma_r/sigma_t along the way; for a ray drawn from a glossy lobe, the
// whole lobe's, which its n^2 rays share), and the media it is inside. Named for the
// node of the ray tree it describes: a Whitted ray tree branches, so it is no path; the
// inspector's record of a traced ray is RayTreeNode (ray_tree.h).
struct NodeState {
  int depth = 0;
  Color weight{1.0f};
  MediumStack media;
  int glossy = 0;  // glossy bounces on the way here (Settings::glossy_samples)
  // Where the strata of glossy rays start where the camera samples are not Monte Carlo
  // ones (the regular grid, Whitted's adaptive corners): the camera sample's seed
  // (sampler.cpp), mixed at each glossy bounce with the ray's index, so each branch has
  // its own.
  uint32_t seed = 0;
  // Where the camera samples are Monte Carlo ones (jittered_samples, settings.h), each 2D
  // draw along the sample's chain (a lamp's feelers, a glossy lobe, the emitter feelers)
  // is point `index` of the pixel's Owen-scrambled Sobol sequence of its dimension
  // (core/sobol.h), seeded by hash3(pixel, depth, the dimension's salt): `pixel` a key of
  // the pixel, `index` the camera sample's; a split into m rays gives its ray j the index
  // index * m + j, so that all the rays of a pixel in one dimension form one sequence.
  uint32_t pixel = 0;
  uint32_t index = 0;
  // A ray drawn from a glossy lobe: its density there per unit solid angle, times its
  // lobe's rays per emitter feeler, for the MIS weight of the emission it meets
  // (mis.h); 0 for every other ray, which counts emission whole.
  float mis = 0.0f;
  // What of the world this ray counts where it escapes: a ray drawn from a glossy lobe
  // its MIS weight against the feelers to the world (scene/world_light.h), decided where
  // it was drawn (the world is as far in every direction, so the weight holds along the
  // ray); 1 for every other ray.
  float world_weight = 1.0f;
  // A ray drawn from a glossy lobe: its density there per unit solid angle times its
  // lobe's number of rays, for its MIS weight on the lamps whose shapes it meets against
  // their feelers (mis.h, lamp_weight); 0 for every other ray, which sees lamps whole.
  float lamp_density = 0.0f;
  // Light linking: the light set of the surface this ray left, whose emitters it sees;
  // -1 for a camera ray, which sees every emitter (as in Cycles).
  int receiver = -1;

  // The state of a secondary ray of `w` relative to this node, in `m`: one deeper when
  // it bounces off the surface (`bounce`, whose light set is `light_set`), at this depth
  // when it goes straight on; `drawn` given for a ray drawn from a glossy lobe.
  NodeState child(const Color& w, const MediumStack& m, bool bounce, int light_set,
                  const Drawn* drawn) const;
};

inline NodeState NodeState::child(const Color& w, const MediumStack& m, bool bounce, int light_set,
                                  const Drawn* drawn) const {
  NodeState next{bounce ? depth + 1 : depth, weight * w, m};
  next.glossy = glossy + (drawn != nullptr ? 1 : 0);
  next.seed = drawn != nullptr ? drawn->seed : seed;
  next.pixel = pixel;
  next.index = drawn != nullptr ? drawn->index : index;
  // A continuation straight on is still the same ray; a bounce of any other kind counts
  // the emission it meets whole.
  next.mis = drawn != nullptr ? drawn->mis : (bounce ? 0.0f : mis);
  next.world_weight = drawn != nullptr ? drawn->world_weight : (bounce ? 1.0f : world_weight);
  next.lamp_density = drawn != nullptr ? drawn->lamp_density : (bounce ? 0.0f : lamp_density);
  // Light linking: what it meets is lit for the surface it left (emission_weight).
  next.receiver = bounce ? light_set : receiver;
  return next;
}

// Analyses the scene once, then traces only the effects the scene calls for, with the
// kernel (kernel.h) chosen once (whitted.cpp: a kernel per recorder, way of querying and
// policy, the effects compiled in or read at run time).
class WhittedIntegrator {
 public:
  // `camera` is the render's view, for the camera and window inputs of shader programs;
  // `log`, when given, takes the queries made while it is active (records them, or
  // answers them in a replay: recorder.h); `tree`, when given, receives every ray and
  // term of what is traced (the inspector: slower, never for renders). Not both: throws
  // std::invalid_argument.
  WhittedIntegrator(const CompiledScene& scene, const Settings& settings,
                    const Camera& camera = Camera{}, RayLog* log = nullptr,
                    RayTree* tree = nullptr);

  // Radiance arriving along `ray` (camera rays: a default NodeState, or the media the
  // camera is inside). Passes through cut-outs; `alpha`, when given, receives the
  // coverage (0..1). `record`, given when the settings request passes, receives what
  // the ray's tree contributed to them (it must start as a default SampleRecord).
  Color trace(const Ray& ray, const NodeState& state, RayCounts* counts, float* alpha = nullptr,
              SampleRecord* record = nullptr) const {
    return trace_(*this, ray, state, counts, alpha, nullptr, record);
  }
  // The same for a ray whose first hit is already known (from intersect_packet).
  Color trace_from(const Ray& ray, const Hit& first, const NodeState& state, RayCounts* counts,
                   float* alpha, SampleRecord* record = nullptr) const {
    return trace_(*this, ray, state, counts, alpha, &first, record);
  }
  // First hits of up to SceneAccel::kIntersectPacketSize coherent rays, traced as one
  // packet (through the log, as the kernel's queries, when there is one).
  void intersect_packet(const Ray* rays, int count, Hit* hits) const {
    intersect_packet_(*this, rays, count, hits);
  }

  // A wave's first generation (wave.h): camera sample `sample`'s ray (`first` its first
  // hit when already found), traced and shaded now into wave->samples[sample], the rays
  // and feelers it spawns appended to the wave; its passes, where kept, into `record`
  // (the rest of them as the wave traces what it spawned). Only where waves().
  void trace_camera(Wave* wave, const Ray& ray, const NodeState& state, uint32_t sample,
                    const Hit* first, RayCounts* counts, SampleRecord* record = nullptr) const {
    trace_wave_.camera(*this, wave, ray, state, sample, first, counts, record);
  }
  // Then the rest: the feelers and rays the camera rays spawned and everything they
  // spawn, generation by generation, adding into wave->samples.
  void trace_wave(Wave* wave, RayCounts* counts) const { trace_wave_.rest(*this, wave, counts); }
  // Whether renders with these settings trace in waves: Settings::waves (the
  // inspector's recorder follows the recursion).
  bool waves() const { return trace_wave_.rest != nullptr; }

  // The media that contain point p (the camera inside glass), innermost current.
  MediumStack media_at(const Vec3& p) const;

  const Effects& effects() const { return effects_; }
  const CompiledScene& scene() const { return scene_; }
  const Settings& settings() const { return settings_; }
  const Camera& camera() const { return camera_; }
  RayLog* log() const { return log_; }
  RayTree* tree() const { return tree_; }

  using TraceFn = Color (*)(const WhittedIntegrator&, const Ray&, const NodeState&, RayCounts*,
                            float*, const Hit*, SampleRecord*);
  using PacketFn = void (*)(const WhittedIntegrator&, const Ray*, int, Hit*);
  // A kernel's two wave stages (trace_camera, trace_wave); null where it traces
  // recursively.
  struct WaveFns {
    void (*camera)(const WhittedIntegrator&, Wave*, const Ray&, const NodeState&, uint32_t,
                   const Hit*, RayCounts*, SampleRecord*) = nullptr;
    void (*rest)(const WhittedIntegrator&, Wave*, RayCounts*) = nullptr;
  };

 private:
  const CompiledScene& scene_;
  const Settings settings_;
  const Camera camera_;
  Effects effects_;
  TraceFn trace_;
  PacketFn intersect_packet_;
  WaveFns trace_wave_;
  RayLog* log_;
  RayTree* tree_;
};

}  // namespace whitted
