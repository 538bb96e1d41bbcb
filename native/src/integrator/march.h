// The march through a heterogeneous medium (issue 48, part 2; integrator/heterogeneous.h):
// the steps a ray's segment inside it is cut into, each taken as constant at one point of
// it, as Cycles 3.x marches such media (kernel/integrator/shade_volume.h: volume_step_init,
// volume_shadow_heterogeneous; Object::compute_volume_step_size). What fills a point is
// medium_at's answer (medium.h: the media it is inside summed, each program run there by
// CompiledScene::medium), the one question asked of it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/exponential.hpp>

#include "core/limits.h"
#include "core/math.h"
#include "core/ray.h"
#include "integrator/medium.h"
#include "integrator/settings.h"
#include "integrator/whitted.h"
#include "scene/scene.h"

namespace whitted {

// The step a medium is marched with, as Cycles' Object::compute_volume_step_size: a
// Volume object's grids' (VolumeObject::step: its voxels or its Render step size, in the
// world), else (a procedural volume in a mesh) a tenth of the mean side of its object's
// world box; times its material's Volume Step Rate and the render's
// (Settings::volume_step_rate). Cycles takes the smallest step rate of the heterogeneous
// materials an object has; here each medium keeps its material's.
inline float volume_step(const CompiledScene& scene, const Settings& settings, uint32_t material,
                         uint32_t instance) {
  const CompiledScene::Instance& in = scene.instances[instance];
  float step = in.volume ? in.volume->step() : 0.0f;
  if (!(step > 0.0f)) {
    const Vec3 side = in.world_box.upper - in.world_box.lower;
    step = 0.1f * (side.x + side.y + side.z) / 3.0f;
  }
  return step * scene.materials[material].volume_step_rate * settings.volume_step_rate;
}

// Where ray r leaves `box` (0 if it never is inside it): how far a medium the box holds
// can reach along a ray that meets no more of its bounds (an open mesh).
inline float box_exit(const Box& box, const Ray& r) {
  float exit = kInfinity;
  for (int axis = 0; axis < 3; ++axis) {
    if (r.direction[axis] == 0.0f) continue;
    const float a = (box.lower[axis] - r.origin[axis]) / r.direction[axis];
    const float b = (box.upper[axis] - r.origin[axis]) / r.direction[axis];
    exit = std::min(exit, std::max(a, b));
  }

  return std::isfinite(exit) ? std::max(exit, 0.0f) : 0.0f;
}

// The step of the media a point is inside: the finest of the heterogeneous ones' (Cycles
// marches an object's media with their smallest step).
inline float march_step(const CompiledScene& scene, const Settings& settings,
                        const MediumStack& media) {
  float step = kInfinity;
  for (int i = 0; i < media.size(); ++i) {
    if (!scene.materials[media.material(i)].heterogeneous()) continue;
    step = std::min(step, volume_step(scene, settings, media.material(i), media.instance(i)));
  }
  return step;
}

// How far along r the heterogeneous media a point is inside can reach where no more of
// their bounds are met (an open mesh): the farthest of their objects' boxes' exits.
inline float march_reach(const CompiledScene& scene, const MediumStack& media, const Ray& r) {
  float reach = 0.0f;
  for (int i = 0; i < media.size(); ++i) {
    if (!scene.materials[media.material(i)].heterogeneous()) continue;
    reach = std::max(reach, box_exit(scene.instances[media.instance(i)].world_box, r));
  }
  return reach;
}

// The steps a segment [0, length] of a ray is marched in: step i ends at
// (i + offset) * size (the last at `length`) and starts where step i - 1 ended (the first
// at 0), its coefficients read at the fraction `shade` of it. Cycles draws both offsets
// per sample (a grid shifted against banding at the bounds, a point anywhere in each step);
// a feeler, which has no draw of its own here, takes 1 and 1/2 (the midpoint rule, exact
// for a density linear along the step).
struct Steps {
  float length = 0.0f;
  float size = 0.0f;
  float offset = 1.0f;
  float shade = 0.5f;
  int count = 1;

  float end(int i) const {
    return i + 1 >= count ? length : std::min(length, (static_cast<float>(i) + offset) * size);
  }
  float start(int i) const { return i == 0 ? 0.0f : end(i - 1); }
  float shaded(int i) const { return start(i) + shade * (end(i) - start(i)); }
  // The step holding distance t of [0, length].
  int at(float t) const {
    if (!(size > 0.0f)) return 0;
    const float i = std::ceil(t / size - offset);
    return static_cast<int>(std::clamp(i, 0.0f, static_cast<float>(count - 1)));
  }
};

// Steps of `step` along [0, length] (length finite), longer where more than `max_steps`
// would be needed (Cycles: the segment cut into max_steps equal steps then).
inline Steps march_steps(float length, float step, int max_steps, float offset, float shade) {
  Steps s;
  s.length = length;
  s.offset = offset;
  s.shade = shade;
  s.size = std::min(step, length);
  if (length > static_cast<float>(max_steps) * s.size)
    s.size = length / static_cast<float>(max_steps);
  if (!(s.size > 0.0f)) return s;  // an empty segment: one step of length 0
  const float count = std::ceil(length / s.size - offset) + 1.0f;
  s.count = static_cast<int>(std::clamp(count, 1.0f, static_cast<float>(max_steps + 1)));
  return s;
}

// What a medium of constant extinction sigma_t and emission e emits over a length d (the
// segment's, or a marched step's; infinite for a ray escaping inside an open mesh), seen
// from its start: integral_0^d exp(-sigma_t t) e dt, per channel (e d where sigma_t is 0,
// none over an infinite d then).
inline Color medium_emission(const Color& e, const Color& sigma_t, float d) {
  Color out(0.0f);
  for (int i = 0; i < 3; ++i) {
    if (!(e[i] > 0.0f)) continue;
    if (sigma_t[i] > 0.0f) {
      out[i] = e[i] * -std::expm1(-sigma_t[i] * d) / sigma_t[i];
    } else if (std::isfinite(d)) {
      out[i] = e[i] * d;
    }
  }
  return out;
}

// The optical depth integral of sigma_t over [from, to] along a feeler (its kind and
// `context` what the programs' Light Path inputs read) inside `media`, some of them
// heterogeneous, by the midpoint of each step. `to` may be infinite (a feeler to the sun
// from inside an open mesh): the heterogeneous media end at their objects' boxes, and
// constant ones beyond are the caller's (media_transmittance). With `glow`, adds what the
// media emit towards `from` on the way, each step's emission dimmed by the steps before.
inline Color optical_depth(const CompiledScene& scene, const Settings& settings,
                           const RayContext& context, const Ray& feeler, float from, float to,
                           const MediumStack& media, RayCounts* counts, Color* glow = nullptr) {
  const float end = std::min(to, march_reach(scene, media, feeler));
  if (!(end > from)) return Color(0.0f);
  const Steps steps = march_steps(end - from, march_step(scene, settings, media),
                                  settings.volume_max_steps, 1.0f, 0.5f);
  Color depth(0.0f);
  for (int i = 0; i < steps.count; ++i) {
    const Vec3 x = feeler.origin + (from + steps.shaded(i)) * feeler.direction;
    const Medium c = medium_at(scene, media, x, feeler, context);
    counts->volume_steps += 1;
    const float length = steps.end(i) - steps.start(i);
    if (glow != nullptr) {
      *glow += glm::exp(-depth) * medium_emission(c.emission, c.extinction(), length);
    }
    depth += c.extinction() * length;
    // Past this nothing gets through (Cycles checks every 8th step, to the same end).
    if (std::exp(-std::min({depth.x, depth.y, depth.z})) < limits::kVolumeOpaque) break;
  }
  return depth;
}

}  // namespace whitted
