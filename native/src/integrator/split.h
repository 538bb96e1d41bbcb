// The split of weights: the weights of the secondary rays, Whitted's sigma_r and sigma_t,
// from the surface's reflectivity and transmissivity (the step, kernel.h, reads them).
#pragma once

#include <algorithm>
#include <array>

#include "core/math.h"
#include "core/ray.h"
#include "integrator/settings.h"
#include "integrator/shading_point.h"
#include "integrator/whitted.h"

namespace whitted {

struct Split {
  Color sigma_r{0.0f};  // coat + layer + base
  Color sigma_t{0.0f};
  Vec3 refracted{0.0f};  // the refracted direction, when `refracts`
  bool refracts = false;
  bool total_internal_reflection = false;  // the whole transmissive layer is in sigma_r
  // sigma_r by the layer that reflects it, each reflected by its own lobe (glossy.h):
  // the coat's mirror, the specular layer's beneath it, the base's (its reflectivity and
  // its transmissive layer's reflected share).
  Color coat{0.0f};
  Color layer{0.0f};
  Color base{0.0f};
};

// sigma_r and sigma_t of the secondary rays (none where the kernel traces no reflection,
// no refraction). The transmissive layer splits by Fresnel into a reflected and a
// refracted share (all reflected on total internal reflection); the specular layer's
// mirror and the coat's go on top, each seen through what lies above it (ShadingPoint::
// base, layer_tint); then sigma_r + sigma_t <= 1.
// Always inlined into the step, as it was as a member of the one-class kernel called once:
// GCC inlines a function called once only where it is of internal linkage, and this one is
// not (callgrind on the demo scene: whitted.cpp's queries say what it cost).
[[gnu::always_inline]] inline Split split_weights(const Ray& ray, const ShadingPoint& p, float eta,
                                                  bool reflection, bool refraction, Fresnel fresnel,
                                                  RayCounts* counts) {
  Split split;
  split.sigma_r = reflection ? p.surface.reflectivity : Color(0.0f);
  split.sigma_t = refraction ? p.surface.transmissivity : Color(0.0f);
  const Color layer = reflection ? p.layer.mirror * p.layer_tint : Color(0.0f);
  if (is_black(split.sigma_r) && is_black(split.sigma_t) && p.coat.mirror <= 0.0f &&
      is_black(layer)) {
    return split;
  }
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
  split.base = p.base * split.sigma_r;
  split.layer = layer;
  split.coat = Color(p.coat.mirror);
  split.sigma_r = split.base + layer + split.coat;
  split.sigma_t *= p.base;
  // A surface returns at most what arrives: sigma_r + sigma_t <= 1 keeps the ray tree
  // from growing without bound (two facing mirror-glass panes at depth 256).
  const float sum = max_component(split.sigma_r + split.sigma_t);
  if (sum > 1.0f) {
    split.sigma_r /= sum;
    split.sigma_t /= sum;
    split.base /= sum;
    split.layer /= sum;
    split.coat /= sum;
  }
  return split;
}

// A lobe the reflected term draws its rays from: a layer's (Split: coat, layer, base).
struct Lobe {
  GgxLobe ggx{Vec3(0.0f, 0.0f, 1.0f), 0.0f};  // about the normal facing the ray; alpha 0: a mirror
  Color energy{1.0f};                         // its multiple-scattering scale, or 1
  const Coat* coat{nullptr};  // a dielectric layer's: each ray by its facet's Fresnel
  Color sigma{0.0f};          // its share of sigma_r

  // Its distribution: the coat's model (GTR1's for 3.x's Clearcoat), else GGX's.
  CoatModel model() const { return coat != nullptr ? coat->model : CoatModel::kGgx; }
};

// The lobes of a reflection, each of its own rays: up to one per layer (coat, specular
// layer, base), in that order.
struct Lobes {
  std::array<Lobe, 3> lobe;
  int count = 0;
  const Lobe* begin() const { return lobe.data(); }
  const Lobe* end() const { return lobe.data() + count; }
};

// The lobes the reflected term follows: each layer's where it reflects, glossy where its
// lobe is rougher than a mirror and the glossy effect is on (else a mirror's one ray about
// its normal; every layer's on total internal reflection). Mirrors about the same normal
// share their one ray (a deterministic direction: the sum of their weights is exact).
// A single lobe carries all of sigma_r, as the one reflection of a one-layer surface did.
inline Lobes reflection_lobes(const ShadingPoint& p, const Split& split, bool glossy) {
  const bool rough = glossy && !split.total_internal_reflection;
  Lobes lobes;
  const auto add = [&](const Vec3& n, float alpha, const Color& energy, const Coat* coat,
                       const Color& sigma, const GgxLobe* ggx) {
    if (is_black(sigma)) return;
    if (rough && alpha > 0.0f) {
      lobes.lobe[lobes.count++] =
          Lobe{ggx != nullptr ? *ggx : GgxLobe(n, alpha), energy, coat, sigma};
      return;
    }
    for (int i = 0; i < lobes.count; ++i) {
      if (lobes.lobe[i].ggx.alpha() == 0.0f && lobes.lobe[i].ggx.n == n) {
        lobes.lobe[i].sigma += sigma;
        return;
      }
    }
    lobes.lobe[lobes.count++] = Lobe{GgxLobe(n, 0.0f), Color(1.0f), nullptr, sigma};
  };
  add(p.coat.normal, p.coat.alpha, Color(1.0f), &p.coat, split.coat, nullptr);
  add(p.ns, p.layer.alpha, Color(1.0f), &p.layer, split.layer, &p.ggx);
  add(p.ns, p.alpha, p.energy, nullptr, split.base, &p.ggx);
  if (lobes.count == 1) lobes.lobe[0].sigma = split.sigma_r;
  return lobes;
}

}  // namespace whitted
