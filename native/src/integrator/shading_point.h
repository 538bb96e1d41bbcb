// A hit as the Whitted step shades it, and one light sample's terms there: what the
// kernel (whitted.cpp) computes, and what its recorders (kernel_recorder.h) read of it.
#pragma once

#include "core/math.h"
#include "core/ray.h"
#include "integrator/lobes.h"
#include "scene/scene.h"

namespace whitted {

// The surface, its normals turned to face the ray, the direction back along the ray,
// and what the local term reads of them.
struct ShadingPoint {
  const Interaction& it;
  const SurfaceParams& surface;
  Vec3 ng;      // geometric normal, facing the ray
  Vec3 ns;      // shading normal, facing the ray (never away from ng)
  Vec3 smooth;  // the interpolated normal on the ray's side (diffuse_shadowing)
  Vec3 wo;      // back along the ray
  Coat coat;
  float base;          // 1 - coat.cover (1 if the coat is not layered): what reaches the base
  float phong_norm;    // (f+2)/(2pi), the normalisation of the Phong lobe
  Color multiscatter;  // kOrenNayarEnergy: the diffuse lobe's multiple scattering, per
                       // unit LightTerms::loss (0 for the other diffuse models)
  float alpha;         // GGX alpha of the reflection lobe; 0: a mirror (microfacet.h)
  Color energy;        // the lobe's multiple-scattering scale (Material::multiscatter), or 1
};

// One light sample's Phong terms at a shading point, per unit irradiance and unshadowed:
// the pieces the sum, the passes and the inspector multiply out.
struct LightTerms {
  float lit;     // (1 - coat) * max(0, n.l): the light the base receives
  float fade;    // diffuse_fade: kd/pi * fade + multiscatter * loss is the diffuse lobe
  float loss;    // what a kOrenNayarEnergy lobe's single scattering loses of this light
  float lobe;    // (v.r)^f: ks * phong_norm * lobe is the Phong lobe
  float coat;    // the coat's highlight
  float glossy;  // (1 - coat) * the GGX lobe times (l.n): reflectivity * glossy is its share
};

// The geometric and shading normals of a hit turned to face the ray; a shading normal
// cannot face away.
inline void facing_normals(const Ray& ray, const Interaction& it, const SurfaceParams& surface,
                           Vec3* ng, Vec3* ns) {
  // Entering or leaving is decided by the geometric normal, never the shading normal.
  const bool entering = glm::dot(ray.direction, it.geometric_normal) < 0.0f;
  *ng = entering ? it.geometric_normal : -it.geometric_normal;
  *ns = entering ? surface.normal : -surface.normal;
  if (glm::dot(*ns, *ng) <= 0.0f) *ns = *ng;
}

}  // namespace whitted
