// The shadow catcher (Object > Visibility > Shadow Catcher, Cycles 3.x and later): a camera
// ray that meets a catcher shows only the shadows the other objects cast on it, to be
// composited over a plate.
//
// Cycles splits the camera path at the catcher: one path sees the whole scene, the other
// sees the catchers alone (the other objects are invisible to it), and its Shadow Catcher
// pass is, per pixel, the first's light on the catcher over the second's. Without that
// pass (Blender's default) it folds the ratio into Combined (the "approximate" shadow
// catcher, film/read.h): over a transparent film the catcher is black with alpha 1 - the
// ratio's mean over colour; over an opaque film it shows the world behind it (what the
// camera ray would have met without it) times that mean, alpha 1. With the pass (the
// film's FilmPass::kShadowCatcher) Combined leaves the catcher out, black and transparent
// over either film (measured in Cycles 3.4 and 5.0), and the pass keeps the two sums per
// channel (SampleRecord::caught), divided per pixel by the film.
//
// Whitted's form of the two paths: the catcher's local term (lights.h) is summed twice per
// light sample, each feeler answered once by every object and once by the catchers alone
// (kCatcherShadowRay), and the ratio is their quotient. Only the camera's hit is a catcher:
// every other ray (a mirror's, a glass's) sees it as an ordinary object, as in Cycles,
// where only a path still on its camera ray (through cut-outs) splits.
#pragma once

#include <cstdint>

#include "core/ray.h"
#include "integrator/kernel_inputs.h"
#include "integrator/kernel_recorder.h"
#include "integrator/lights.h"
#include "integrator/mis.h"
#include "integrator/passes.h"
#include "integrator/shading_point.h"
#include "integrator/shadow.h"

namespace whitted {

// The policy Lights (lights.h) runs with at a catcher's hit: the feelers it would queue are
// answered at once, each twice. *with sums the light samples' shares that arrive in the
// scene, *without those that would arrive if the catchers were alone in it.
template <uint32_t kEffects, class Queries>
struct CatcherFeelers {
  static constexpr bool kQueues = true;
  const KernelInputs<kEffects, Queries>* in;
  RayCounts* counts;
  Color* with;
  Color* without;

  template <class Queued>
  void feeler(const Ray& ray, const Color& unshadowed, uint64_t shadow_sets, int32_t /*light*/,
              int depth, const Queued& /*passes*/) const {
    Blockers storage;
    const Blockers* linked = blockers(in->scene, shadow_sets, &storage);
    const bool blocked = in->queries.occluded(ray, linked);
    *with += unshadowed * shadow_transmittance(*in, ray, blocked, linked, depth, counts);
    // The catchers alone: an any-hit query that sees no other object (scene.cpp gives the
    // catchers seen by shadow rays this bit).
    Ray alone = ray;
    alone.kind = kCatcherShadowRay;
    counts->shadow += 1;
    if (!in->queries.occluded(alone, linked)) *without += unshadowed;
  }
};

// The light reaching catcher point p, the catcher's local term in the scene and its local
// term with the catchers alone (their quotient is what the other objects leave).
// `seen` is what of the catcher's emission the ray counts (emission_weight): the
// catcher's emission and ambient term are in both sums.
template <uint32_t kEffects, class Queries>
CaughtLight caught_light(const KernelInputs<kEffects, Queries>& in, const ShadingPoint& p,
                         float seen, const NodeState& state, RayCounts* counts) {
  Color with(0.0f);
  Color without(0.0f);
  const CatcherFeelers<kEffects, Queries> policy{&in, counts, &with, &without};
  NoRecorder recorder;  // the catcher's light goes to no pass
  const Lights<kEffects, NoRecorder, Queries, CatcherFeelers<kEffects, Queries>> lights(
      in, recorder, policy);
  // No glossy ray leaves a catcher's hit: each feeler keeps its whole share (GlossyRays{}).
  const Color local = lights.local(p, GlossyRays{}, seen, state, counts);
  return {with + local, without + local};
}

}  // namespace whitted
