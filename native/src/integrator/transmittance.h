// What a medium lets through: a homogeneous one's (integrator/volume.h) exp(-sigma_t d)
// along a segment, and along a shadow feeler through the volume bounds it crosses (a
// heterogeneous one's marched, march.h).
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

// The material of `medium` (a MediumStack's current()) when it fills its inside with a
// medium (Material::participating), else null.
inline const Material* medium_of(const CompiledScene& scene, int32_t medium) {
  if (medium < 0) return nullptr;
  const Material& m = scene.materials[static_cast<size_t>(medium)];
  return m.participating() ? &m : nullptr;
}

// sigma_t = sigma_a + sigma_s, per unit length.
inline Color extinction(const Material& m) {
  return m.volume_absorption + m.volume_scattering;
}

// exp(-sigma_t d) per channel; d may be infinite (a ray escaping inside an open mesh):
// none then gets through where sigma_t > 0, all where it is 0.
inline Color transmittance(const Color& sigma_t, float d) {
  Color out(1.0f);
  for (int i = 0; i < 3; ++i) {
    if (sigma_t[i] > 0.0f) out[i] = std::exp(-sigma_t[i] * d);
  }
  return out;
}

// The transmittance of the media a feeler crosses between its origin and its end (the
// volume bounds only: glass with a volume lets its surface's tint through, shadow.h).
// Which media enclose its origin is read off the feeler's own line, walked past its end to
// the world: a bound it leaves without having entered it encloses the origin (as media_at
// finds the camera's), so a feeler needs nothing of the media stack of the ray it left and
// the recursion and the waves give the same answer. `depth`: the feeler's node's, for a
// heterogeneous medium's program.
template <uint32_t kEffects, class Queries>
Color media_transmittance(const KernelInputs<kEffects, Queries>& in, const Ray& feeler, int depth,
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
    if (!entered) media.enter(b.material, b.instance, in.scene.materials[b.material].priority);
  }
  // The optical depth along [0, t_max], segment by segment.
  Color optical(0.0f);
  float from = 0.0f;
  const RayContext context{&in.camera, depth};
  // A heterogeneous medium's optical depth over [from, to] (march.h).
  const auto marched = [&](float to) {
    return optical_depth(in.scene, in.settings, context, feeler, from, to,
                         static_cast<uint32_t>(media.current()), media.current_instance(), counts);
  };
  const auto cross = [&](float to) {
    if (const Material* m = medium_of(in.scene, media.current())) {
      optical += m->heterogeneous() ? marched(to) : extinction(*m) * (to - from);
    }
    from = to;
  };
  for (int i = 0; i < count; ++i) {
    const Bound& b = bounds[static_cast<size_t>(i)];
    if (!(b.t < feeler.t_max)) break;
    cross(std::max(b.t, from));
    if (b.entering) {
      media.enter(b.material, b.instance, in.scene.materials[b.material].priority);
    } else {
      media.leave(b.material);
    }
  }
  Color through = transmittance(optical, 1.0f);  // exp(-optical)
  if (const Material* m = medium_of(in.scene, media.current())) {
    // t_max may be infinite (a heterogeneous medium ends at its object's box then).
    through *= m->heterogeneous() ? transmittance(marched(feeler.t_max), 1.0f)
                                  : transmittance(extinction(*m), feeler.t_max - from);
  }
  return through;
}

}  // namespace whitted
