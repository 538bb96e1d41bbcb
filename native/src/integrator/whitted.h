// The Whitted (1980) integrator: local Phong shading gated by shadow feelers, plus
// mirror reflection and refraction, recursing to a maximum depth.
#pragma once

#include <cstdint>

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
  uint64_t nonfinite_samples = 0;          // samples discarded as NaN or infinite

  RayCounts& operator+=(const RayCounts& o);
  uint64_t total() const { return camera + shadow + reflection + refraction + transparent; }
};

class WhittedIntegrator {
 public:
  WhittedIntegrator(const CompiledScene& scene, const Settings& settings);

  // Radiance arriving along `ray`, which is at recursion depth `depth` (camera rays: 0).
  // Passes through cut-outs; `alpha`, when given, receives the coverage (0..1).
  Color trace(const Ray& ray, int depth, RayCounts* counts, float* alpha = nullptr) const;

 private:
  // Radiance leaving an opaque surface point towards the ray: the Whitted step.
  Color shade(const Ray& ray, const Interaction& it, const SurfaceParams& surface, int depth,
              RayCounts* counts) const;
  // `ng` and `n` are the geometric and shading normals turned towards `wo`.
  Color local(const Interaction& it, const SurfaceParams& surface, const Vec3& wo, const Vec3& ng,
              const Vec3& n, RayCounts* counts) const;
  Color shadow_transmittance(Ray ray, RayCounts* counts) const;

  const CompiledScene& scene_;
  const Settings settings_;
  bool any_translucent_ = false;  // coloured shadows need a walk through glass
};

}  // namespace whitted
