// The Whitted (1980) integrator: local Phong shading gated by shadow feelers, plus
// mirror reflection and refraction, recursing to a maximum depth.
#pragma once

#include <cstdint>

#include "integrator/medium.h"
#include "integrator/settings.h"
#include "scene/scene.h"

namespace whitted {

// Rays traced by type, per thread, summed at the end of a render.
struct RayCounts {
  uint64_t camera = 0;
  uint64_t shadow = 0;
  uint64_t reflection = 0;
  uint64_t refraction = 0;
  uint64_t transparent = 0;                // continuations behind cut-outs (alpha < 1)
  uint64_t total_internal_reflection = 0;  // refracted rays that became reflections
  uint64_t depth_limited = 0;              // secondary rays not traced: maximum depth
  uint64_t cutoff = 0;                     // secondary rays not traced: weight below cutoff
  uint64_t nonfinite_samples = 0;          // samples discarded as NaN or infinite

  RayCounts& operator+=(const RayCounts& o);
  uint64_t total() const { return camera + shadow + reflection + refraction + transparent; }
};

// Where a ray is in its ray tree: its recursion depth, its weight on the pixel (the
// product of the sigma_r/sigma_t along the way), and the media it is inside.
struct PathState {
  int depth = 0;
  Color weight{1.0f};
  MediumStack media;
};

class WhittedIntegrator {
 public:
  WhittedIntegrator(const CompiledScene& scene, const Settings& settings);

  // Radiance arriving along `ray` (camera rays: a default PathState, or the media the
  // camera is inside). Passes through cut-outs; `alpha`, when given, receives the
  // coverage (0..1).
  Color trace(const Ray& ray, const PathState& path, RayCounts* counts,
              float* alpha = nullptr) const;

  // The media that contain point p (the camera inside glass), innermost current.
  MediumStack media_at(const Vec3& p) const;

 private:
  // Radiance leaving a surface point towards the ray: the Whitted step.
  Color shade(const Ray& ray, const Interaction& it, const SurfaceParams& surface,
              const PathState& path, RayCounts* counts) const;
  // Traces a secondary ray of weight `weight` (relative to this one), unless the depth
  // or the cutoff stops it; `bounce` is false for a ray that only continues straight on.
  // The one place the ray tree branches.
  Color branch(const Ray& ray, const PathState& path, const Color& weight, const MediumStack& media,
               bool bounce, RayCounts* counts) const;
  // `ng` and `n` are the geometric and shading normals turned towards `wo`.
  Color local(const Interaction& it, const SurfaceParams& surface, const Vec3& wo, const Vec3& ng,
              const Vec3& n, RayCounts* counts) const;
  Color shadow_transmittance(Ray ray, RayCounts* counts) const;

  const CompiledScene& scene_;
  const Settings settings_;
  bool any_translucent_ = false;  // coloured shadows need a walk through glass
};

}  // namespace whitted
