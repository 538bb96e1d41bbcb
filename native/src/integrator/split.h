// The split of weights: the weights of the secondary rays, Whitted's sigma_r and sigma_t,
// from the surface's reflectivity and transmissivity (the step, kernel.h, reads them).
#pragma once

#include <algorithm>

#include "core/math.h"
#include "core/ray.h"
#include "integrator/settings.h"
#include "integrator/shading_point.h"
#include "integrator/whitted.h"

namespace whitted {

struct Split {
  Color sigma_r{0.0f};
  Color sigma_t{0.0f};
  Vec3 refracted{0.0f};  // the refracted direction, when `refracts`
  bool refracts = false;
  bool total_internal_reflection = false;  // the whole transmissive layer is in sigma_r
  bool about_coat = false;                 // the mirror ray reflects about the coat's normal
};

// sigma_r and sigma_t of the secondary rays (none where the kernel traces no reflection,
// no refraction). The transmissive layer splits by Fresnel into a reflected and a
// refracted share (all reflected on total internal reflection); the coat's mirror goes on
// top and takes its share of both; then sigma_r + sigma_t <= 1.
// Always inlined into the step, as it was as a member of the one-class kernel called once:
// GCC inlines a function called once only where it is of internal linkage, and this one is
// not (callgrind on the demo scene: whitted.cpp's queries say what it cost).
[[gnu::always_inline]] inline Split split_weights(const Ray& ray, const ShadingPoint& p, float eta,
                                                  bool reflection, bool refraction, Fresnel fresnel,
                                                  RayCounts* counts) {
  Split split;
  split.sigma_r = reflection ? p.surface.reflectivity : Color(0.0f);
  split.sigma_t = refraction ? p.surface.transmissivity : Color(0.0f);
  if (is_black(split.sigma_r) && is_black(split.sigma_t) && p.coat.mirror <= 0.0f) return split;
  if (!is_black(split.sigma_t)) {
    split.refracts = refract(ray.direction, p.ns, eta, &split.refracted) &&
                     glm::dot(split.refracted, p.ng) < 0.0f;
    const float cos_i = std::min(1.0f, glm::dot(p.wo, p.ns));
    const float f = !split.refracts                ? 1.0f
                    : fresnel == Fresnel::kExact   ? fresnel_exact(cos_i, eta)
                    : fresnel == Fresnel::kSchlick ? fresnel_schlick(cos_i, eta)
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

}  // namespace whitted
