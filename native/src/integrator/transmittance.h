// What fills a point (the media it is inside, summed) and what homogeneous media
// (integrator/volume.h) let through: exp(-sigma_t d) along a segment, and along a shadow
// feeler through the volume bounds it crosses.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include "core/limits.h"
#include "core/math.h"
#include "core/ray.h"
#include "integrator/kernel_inputs.h"
#include "integrator/medium.h"

namespace whitted {

// What fills a point, per unit length: the sum of the media it is inside, as Cycles sums
// the closures of overlapping volumes; a glass ball in fog is filled with the fog (and
// its own volume, if it has one). Those are the world's volume (everywhere), every medium
// whose bounds enclose the point and the dielectric owning it (MediumStack::current, the
// nested-dielectric rule). Several
// scatterings keep one Henyey-Greenstein lobe of their mean anisotropy weighted by their
// scattering, as the exporter does within a material (export/volume.py).
struct Medium {
  Color absorption{0.0f};  // sigma_a
  Color scattering{0.0f};  // sigma_s
  Color emission{0.0f};    // radiance per unit length
  float anisotropy = 0.0f;
  bool empty = true;  // no medium: nothing to absorb, scatter or emit
  // sigma_t = sigma_a + sigma_s.
  Color extinction() const { return absorption + scattering; }
};

inline Medium medium_at(const CompiledScene& scene, const MediumStack& media) {
  Medium out;
  float weighed = 0.0f;  // sum of the scatterings' means, weighing the anisotropies
  const auto add_material = [&](const Material& m) {
    if (!m.participating()) return;
    out.absorption += m.volume_absorption;
    out.scattering += m.volume_scattering;
    out.emission += m.volume_emission;
    const float w = (m.volume_scattering.x + m.volume_scattering.y + m.volume_scattering.z) / 3.0f;
    out.anisotropy += w * m.volume_anisotropy;
    weighed += w;
    out.empty = false;
  };
  const auto add = [&](uint32_t index) { add_material(scene.materials[index]); };
  add_material(scene.world_medium);  // the world's volume fills everything
  for (int i = 0; i < media.size(); ++i) {
    if (media.is_bound(i)) add(media.material(i));
  }
  if (const int32_t owner = media.current(); owner >= 0) add(static_cast<uint32_t>(owner));
  out.anisotropy = weighed > 0.0f ? out.anisotropy / weighed : 0.0f;
  return out;
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
// the recursion and the waves give the same answer.
template <uint32_t kEffects, class Queries>
Color media_transmittance(const KernelInputs<kEffects, Queries>& in, const Ray& feeler,
                          RayCounts* counts) {
  struct Bound {
    float t;
    uint32_t material;
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
                                          it.material_index,
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
    if (!entered) media.enter_bound(b.material);
  }
  // The optical depth along [0, t_max], segment by segment.
  Color depth(0.0f);
  float from = 0.0f;
  const auto cross = [&](float to) {
    if (const Medium m = medium_at(in.scene, media); !m.empty) {
      depth += m.extinction() * (to - from);
    }
    from = to;
  };
  for (int i = 0; i < count; ++i) {
    const Bound& b = bounds[static_cast<size_t>(i)];
    if (!(b.t < feeler.t_max)) break;
    cross(std::max(b.t, from));
    if (b.entering) {
      media.enter_bound(b.material);
    } else {
      media.leave(b.material);
    }
  }
  Color through = transmittance(depth, 1.0f);  // exp(-depth)
  if (const Medium m = medium_at(in.scene, media); !m.empty) {
    through *= transmittance(m.extinction(), feeler.t_max - from);  // t_max may be infinite
  }
  return through;
}

}  // namespace whitted
