// Glowing media as lights (issue 48): a medium's emission lights what is around it, as
// Cycles' diffuse rays (from surfaces) and volume scattering (in media) gather it even
// with no bounce. A glowing object (CompiledScene::glowing) is aimed at through the
// sphere around it: directions uniform in the cone it fills (GlowCone), each marched
// through the media (glow_along). Surfaces' feelers are lights.h's, media's volume.h's.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/math.h"
#include "core/ray.h"
#include "integrator/kernel_inputs.h"
#include "integrator/transmittance.h"
#include "scene/microfacet.h"
#include "scene/scene.h"

namespace whitted {

// The directions from a point towards a glowing medium's sphere (CompiledScene::Glow):
// the cone it fills, or every direction from inside it; drawn uniformly.
struct GlowCone {
  Vec3 axis{0.0f, 0.0f, 1.0f};
  float cos_max = -1.0f;  // -1: the whole sphere of directions
  GlowCone(const CompiledScene::Glow& g, const Vec3& from) {
    const Vec3 to = g.centre - from;
    const float d2 = glm::dot(to, to);
    if (d2 > g.radius * g.radius) {
      axis = to / std::sqrt(d2);
      cos_max = std::sqrt(1.0f - g.radius * g.radius / d2);
    }
  }
  // Per steradian, uniform over the cone.
  float pdf() const { return 1.0f / (2.0f * kPi * (1.0f - cos_max)); }
  bool holds(const Vec3& wi) const { return glm::dot(wi, axis) >= cos_max; }
  Vec3 draw(const glm::vec2& u) const {
    const float cos_theta = 1.0f - u.x * (1.0f - cos_max);
    const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
    const float phi = 2.0f * kPi * u.y;
    return Frame(axis).to_world({sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta});
  }
};

// Where a ray from `from` along unit `wi` leaves a glowing medium's sphere (0: it misses).
inline float sphere_exit(const CompiledScene::Glow& g, const Vec3& from, const Vec3& wi) {
  const Vec3 to = g.centre - from;
  const float b = glm::dot(to, wi);
  const float h2 = g.radius * g.radius - (glm::dot(to, to) - b * b);
  return h2 > 0.0f ? std::max(0.0f, b + std::sqrt(h2)) : 0.0f;
}

// What arrives along a glow feeler, per unit of the density it was drawn with, and how far
// it was marched.
struct GlowArriving {
  Color radiance{0.0f};
  float distance = 0.0f;
};

// The glow arriving at `feeler`'s origin along its direction from every glowing medium:
// the feeler marched through the media (media_along, their emission dimmed by the media
// in front) up to the first surface (glass too: no caustics) or past every glowing
// sphere, over the densities of all the glow cones holding its direction summed (the
// balance heuristic: objects whose cones overlap are not counted twice). Nothing where
// no cone holds it.
template <uint32_t kEffects, class Queries>
GlowArriving glow_along(const KernelInputs<kEffects, Queries>& in, Ray feeler, int depth,
                        RayCounts* counts) {
  float density = 0.0f;
  float reach = 0.0f;
  for (const CompiledScene::Glow& g : in.scene.glowing) {
    const GlowCone cone(g, feeler.origin);
    if (cone.holds(feeler.direction)) density += cone.pdf();
    reach = std::max(reach, sphere_exit(g, feeler.origin, feeler.direction));
  }
  if (!(density > 0.0f) || !(reach > 0.0f)) return {};
  feeler.t_max = reach;
  feeler.kind = kOpaqueShadowRay | kTranslucentShadowRay;
  Hit hit;
  if (in.queries.intersect(feeler, &hit)) feeler.t_max = std::min(feeler.t_max, hit.t);
  counts->volume_feelers += 1;
  const MediaAlong along = media_along<true>(in, feeler, depth, counts);
  return {along.emitted / density, feeler.t_max};
}

}  // namespace whitted
