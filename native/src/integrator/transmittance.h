// What fills a point (the media it is inside, summed) and what media let through: a
// homogeneous one's (integrator/volume.h) exp(-sigma_t d) along a segment, and along a
// shadow feeler through the volume bounds it crosses (heterogeneous ones marched, march.h).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include "core/limits.h"
#include "core/math.h"
#include "core/ray.h"
#include "integrator/kernel_inputs.h"
#include "integrator/march.h"
#include "integrator/medium.h"

namespace whitted {

// exp(-sigma_t d) per channel; d may be infinite (a ray escaping inside an open mesh):
// none then gets through where sigma_t > 0, all where it is 0.
inline Color transmittance(const Color& sigma_t, float d) {
  Color out(1.0f);
  for (int i = 0; i < 3; ++i) {
    if (sigma_t[i] > 0.0f) out[i] = std::exp(-sigma_t[i] * d);
  }
  return out;
}

// What the media a feeler crosses between its origin and its end send towards its origin:
// what they let through from its end, and (kGlow) what they emit on the way, each
// stretch's emission dimmed by the media before it (a glowing medium lighting a surface,
// integrator/lights.h).
struct MediaAlong {
  Color transmittance{1.0f};
  Color emitted{0.0f};
};

// MediaAlong of a feeler (the volume bounds only: glass with a volume lets its surface's
// tint through, shadow.h). Which media enclose its origin is read off the feeler's own
// line, walked past its end to the world: a bound it leaves without having entered it
// encloses the origin (as media_at finds the camera's), so a feeler needs nothing of the
// media stack of the ray it left and the recursion and the waves give the same answer.
// Heterogeneous media are marched (march.h); `depth` is the feeler's node's, for their
// programs.
template <bool kGlow, uint32_t kEffects, class Queries>
MediaAlong media_along(const KernelInputs<kEffects, Queries>& in, const Ray& feeler, int depth,
                       RayCounts* counts) {
  struct Bound {
    float t;
    uint32_t material;
    uint32_t instance;
    bool entering;
  };
  std::array<Bound, limits::kMaxVolumeCrossings> bounds;
  int count = 0;
  Ray r{feeler.origin, feeler.direction, 0.0f, kInfinity, kVolumeBoundRay, feeler.time};
  for (; count < limits::kMaxVolumeCrossings; ++count) {
    Hit hit;
    counts->volume_queries += 1;
    if (!in.queries.intersect(r, &hit)) break;
    const Interaction it = in.scene.interaction(r, hit);
    bounds[static_cast<size_t>(count)] = {glm::dot(it.position - feeler.origin, feeler.direction),
                                          it.material_index, it.instance,
                                          glm::dot(feeler.direction, it.geometric_normal) < 0.0f};
    r = spawn_ray(it.position, it.position_error, it.geometric_normal, it.time, feeler.direction,
                  kVolumeBoundRay);
  }
  // The media around the origin: the bounds left before being entered, innermost first.
  std::array<bool, limits::kMaxVolumeCrossings> matched{};
  MediumStack media;
  for (int i = count - 1; i >= 0; --i) {
    const Bound& b = bounds[static_cast<size_t>(i)];
    if (b.entering) continue;
    bool entered = false;
    for (int j = i - 1; j >= 0 && !entered; --j) {
      const Bound& e = bounds[static_cast<size_t>(j)];
      if (e.entering && e.material == b.material && !matched[static_cast<size_t>(j)]) {
        matched[static_cast<size_t>(j)] = true;
        entered = true;
      }
    }
    if (!entered) media.enter_bound(b.material, b.instance);
  }
  // The optical depth along [0, t_max], segment by segment; a last stretch reaching to
  // infinity (t_max, or past the heterogeneous media's boxes) lets `beyond` through.
  Color optical(0.0f);
  Color beyond(1.0f);
  Color emitted(0.0f);
  float from = 0.0f;
  const RayContext context{&in.camera, depth};
  const auto constant = [&](const Medium& m, float start, float to) {
    if (m.empty()) return;
    if constexpr (kGlow) {
      emitted += transmittance(optical, 1.0f) * beyond *
                 medium_emission(m.emission, m.extinction(), to - start);
    }
    if (std::isinf(to)) {
      beyond *= transmittance(m.extinction(), to);
    } else {
      optical += m.extinction() * (to - start);
    }
  };
  const auto cross = [&](float to) {
    if (heterogeneous(in.scene, media)) {
      Color glow(0.0f);
      const Color before = transmittance(optical, 1.0f) * beyond;
      optical += optical_depth(in.scene, in.settings, context, feeler, from, to, media, counts,
                               kGlow ? &glow : nullptr);
      if constexpr (kGlow) emitted += before * glow;
      // Past their boxes only the media of constant coefficients are left.
      const float reach = std::max(from, march_reach(in.scene, media, feeler));
      if (to > reach) constant(medium_at(in.scene, media), reach, to);
    } else {
      constant(medium_at(in.scene, media), from, to);
    }
    from = to;
  };
  for (int i = 0; i < count; ++i) {
    const Bound& b = bounds[static_cast<size_t>(i)];
    if (!(b.t < feeler.t_max)) break;
    cross(std::max(b.t, from));
    if (b.entering) {
      media.enter_bound(b.material, b.instance);
    } else {
      media.leave(b.material);
    }
  }
  cross(std::max(feeler.t_max, from));                      // t_max may be infinite
  return {transmittance(optical, 1.0f) * beyond, emitted};  // exp(-optical)
}

// The transmittance of the media a feeler crosses between its origin and its end
// (media_along's, without their emission).
template <uint32_t kEffects, class Queries>
Color media_transmittance(const KernelInputs<kEffects, Queries>& in, const Ray& feeler, int depth,
                          RayCounts* counts) {
  return media_along<false>(in, feeler, depth, counts).transmittance;
}

}  // namespace whitted
