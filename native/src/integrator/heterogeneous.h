// Heterogeneous participating media (issue 48, part 2): a medium whose coefficients the
// material's program drives (Material::heterogeneous: density, colour, absorption,
// emission, anisotropy from noise, coordinates, ramps), read at points inside its mesh
// (CompiledScene::medium). Traced as Cycles 3.x traces them (shade_volume.h's
// volume_integrate_heterogeneous): the segment inside is marched in steps (march.h), each
// step's coefficients those at one point of it; Cycles 5.0 replaced this by unbiased
// null-scattering tracking, which converges to the same integral (measured against both
// in tests/blender/test_volume.py). Along the segment, with Volume Bounces 0:
//   - what lies beyond is dimmed by exp(-sum sigma_t,i dt_i);
//   - each step adds its emission, integral over it of T(t) e dt;
//   - every light's (the lamps', the emissive meshes', the world's) is scattered once at a
//     distance drawn along the segment by the loops homogeneous media use (volume.h's
//     scattered_lights: equiangular towards a lamp with a place, else by the marched
//     transmittance, exactly invertible for piecewise constant sigma_t), with the sigma_s
//     and Henyey-Greenstein lobe of the step it falls in and the transmittance up to it
//     (MarchedSegment); its feeler carries what the media it crosses let through
//     (transmittance.h, marching heterogeneous ones by optical_depth).
// Homogeneous media never come here: their path (volume.h) stays as it was.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "core/limits.h"
#include "core/math.h"
#include "core/ray.h"
#include "integrator/kernel_inputs.h"
#include "integrator/march.h"
#include "integrator/medium.h"
#include "integrator/shadow.h"
#include "integrator/strata.h"
#include "integrator/transmittance.h"
#include "integrator/volume.h"
#include "scene/light.h"

namespace whitted {

// One marched step: the optical depth before it, its coefficients.
struct MarchedStep {
  Color depth;  // integral of sigma_t from the segment's start to the step's
  Color sigma_t;
  Color scattering;
  float anisotropy;
};

// A distance along the marched steps drawn by their transmittance (the channels' mean
// extinction): the sun's draw, as by_transmittance (volume.h) is a homogeneous medium's.
inline DrawnDistance by_marched_transmittance(const std::vector<MarchedStep>& marched,
                                              const Steps& steps, float u) {
  const int last = static_cast<int>(marched.size()) - 1;
  const float end = steps.end(last);
  const MarchedStep& final_step = marched.back();
  const float total =
      mean_component(final_step.depth + final_step.sigma_t * (end - steps.start(last)));
  if (!(total > 1e-4f)) {
    if (!(end > 0.0f)) return {};
    return {u * end, 1.0f / end};  // optically thin: uniform
  }
  const float kept = -std::expm1(-total);  // 1 - exp(-total)
  const float target = -std::log1p(-u * kept);
  for (int i = 0; i <= last; ++i) {
    const float before = mean_component(marched[static_cast<size_t>(i)].depth);
    const float sigma = mean_component(marched[static_cast<size_t>(i)].sigma_t);
    const float dt = steps.end(i) - steps.start(i);
    if (i < last && !(before + sigma * dt > target)) continue;
    if (!(sigma > 0.0f)) return {};
    const float t = std::min(steps.start(i) + (target - before) / sigma, end);
    return {t, sigma * std::exp(-target) / kept};
  }
  return {};
}

// A marched segment, as the loops that scatter light along it ask of it (volume.h's
// scattered_lights; ConstantSegment is a homogeneous one's): the part marched, distances
// drawn by its transmittance, and at a drawn distance the step it falls in: the
// transmittance up to it, that step's sigma_s and Henyey-Greenstein lobe, over the pdf.
struct MarchedSegment {
  const std::vector<MarchedStep>& marched;
  const Steps& steps;

  float reach() const { return steps.end(static_cast<int>(marched.size()) - 1); }
  DrawnDistance drawn(float u) const { return by_marched_transmittance(marched, steps, u); }
  Color share(const Ray& r, const DrawnDistance& at, const Vec3& wi) const {
    const int i = std::min(steps.at(at.t), static_cast<int>(marched.size()) - 1);
    const MarchedStep& step = marched[static_cast<size_t>(i)];
    if (is_black(step.scattering)) return Color(0.0f);
    const float phase = henyey_greenstein(glm::dot(wi, r.direction), step.anisotropy);
    const Color reaching = step.depth + step.sigma_t * (at.t - steps.start(i));
    return transmittance(reaching, 1.0f) * step.scattering * (phase / at.pdf);
  }
};

// What the media the ray is in, some heterogeneous (medium.h's medium_at sums them, each
// program run at the point), send back along the segment [0, length] of r and let
// through (module comment), each feeler told to the recorder. `length` may be infinite (a
// ray escaping inside an open mesh): the heterogeneous media then end at their objects'
// boxes. The march's offsets and the lamps' distances are the camera sample's draws (Strata,
// `layer` telling a ray's segments apart), so threads and tiles change nothing. Out of line:
// only scenes with such media call it.
template <uint32_t kEffects, class Queries, class Recorder>
[[gnu::noinline]] SegmentLight heterogeneous_segment(const KernelInputs<kEffects, Queries>& in,
                                                     Recorder& recorder, const Ray& r, float length,
                                                     const MediumStack& media,
                                                     const NodeState& state, int layer,
                                                     RayCounts* counts) {
  const CompiledScene& scene = in.scene;
  // An infinite segment: marched to where the heterogeneous media end (their objects'
  // boxes); whatever of constant coefficients fills the rest lets nothing through.
  const bool endless = std::isinf(length);
  if (endless) length = march_reach(scene, media, r);
  const bool sobol = jittered_samples(in.settings);
  const glm::vec2 offsets =
      Strata(state, 1, 0x68657400u ^ static_cast<uint32_t>(layer), sobol).point(0);
  const Steps steps = march_steps(length, march_step(scene, in.settings, media),
                                  in.settings.volume_max_steps, offsets.x, offsets.y);
  const RayContext context = in.context(state);
  SegmentLight out;
  std::vector<MarchedStep> marched;
  marched.reserve(static_cast<size_t>(steps.count));
  Color depth(0.0f);
  bool scatters = false;
  for (int i = 0; i < steps.count; ++i) {
    const float dt = steps.end(i) - steps.start(i);
    const Medium c = medium_at(scene, media, r.origin + steps.shaded(i) * r.direction, r, context);
    counts->volume_steps += 1;
    out.steps += 1;
    const Color sigma_t = c.absorption + c.scattering;
    out.emitted += transmittance(depth, 1.0f) * medium_emission(c.emission, sigma_t, dt);
    marched.push_back({depth, sigma_t, c.scattering, c.anisotropy});
    scatters |= !is_black(c.scattering);
    depth += sigma_t * dt;
    if (max_component(transmittance(depth, 1.0f)) < limits::kVolumeOpaque) break;
  }
  out.transmittance = transmittance(depth, 1.0f);  // exp(-depth)
  if (endless) out.transmittance *= transmittance(medium_at(scene, media).extinction(), kInfinity);
  if (max_component(out.transmittance) < limits::kVolumeOpaque) out.transmittance = Color(0.0f);
  if (!scatters) return out;
  // Single scattering of every light, over the part marched.
  out.scattered =
      scattered_lights(in, recorder, r, MarchedSegment{marched, steps}, state, layer, counts);
  return out;
}

}  // namespace whitted
