// Tracing in waves (Settings::waves): the camera samples of a row of a tile traced
// together, one generation of rays at a time, instead of each sample's ray tree
// depth-first.
//
// The kernel is the recursive one's (kernel.h) with another policy: each ray of a
// generation is traced and shaded by the same code, but where the recursion (Recurse)
// would trace a child ray (branch) or a shadow feeler (lights.h's feelers), the wave's
// policy (Enqueue) appends it to the wave instead, with its factor on the sample (the
// product of the weights the recursion would multiply its radiance by). The wave then
// traces the generation's feelers (trace_feelers), grouped by light so that feelers
// towards one lamp from neighbouring hits go to Embree as packets, and moves on to the
// children (wave_rest).
//
// A sample's radiance is the sum of its rays' factors times their local terms, added in
// an order that depends only on the sample (its camera ray, its feelers in the order it
// sent them, then its children in the order it spawned them, and so on), so pixels stay
// independent of tiles and threads. The recursion sums the same terms bottom-up
// (I = local + sigma_r * (local' + ...)), so the two differ by float rounding only
// (tests/native/wave_test.cpp states the bound). The passes likewise: each queued ray
// and feeler takes its sample's record along, with what the recorder needs to put its
// terms where the recursion would (PassRecorder::resume, FeelerPasses). The default
// (Settings::waves); what it measured against the recursion is in docs/notes/waves.md.
#pragma once

#include <array>
#include <cstdint>
#include <type_traits>
#include <utility>
#include <vector>

#include "accel/embree.h"
#include "core/ray.h"
#include "integrator/film.h"
#include "integrator/kernel_inputs.h"
#include "integrator/passes.h"
#include "integrator/shadow.h"
#include "integrator/whitted.h"

namespace whitted {

// A ray waiting in a wave: what the recursion would have passed to trace(), and its
// factor on its sample.
struct WaveRay {
  Ray ray;
  NodeState state;
  Color factor{1.0f};
  uint32_t sample = 0;
  PassPath path;  // what it carries on its sample's passes (passes.h)
};

// A shadow feeler waiting in a wave: its first query (ray.h's opaque query where some
// surfaces let light through), what it adds to its sample if all of its light arrives,
// and what the translucent walk behind it needs.
struct WaveFeeler {
  Ray ray;
  Color contribution{0.0f};  // factor * the light sample's unshadowed share
  uint64_t shadow_sets = 0;  // the shadow sets that may block it (light.h)
  uint32_t sample = 0;
  int32_t light = -1;  // its lamp (CompiledScene::lights), -1 for an emissive mesh's
  int depth = 0;       // the depth of the hit it leaves, for shader programs on the way
};

// What a camera sample of a wave brought back: its radiance (not yet checked for NaN),
// its coverage and the rays it cost; and where its passes go, where passes are kept.
struct WaveSample {
  Color radiance{0.0f};
  float alpha = 1.0f;
  uint64_t rays = 0;
  SampleRecord* record = nullptr;
};

// Adaptive anti-aliasing's subdivision of a row, traced a wave per depth
// (CameraSampler::row_adaptive). A camera sample at image point (x, y), in pixels:
struct SubdivisionPoint {
  float x, y;
  uint32_t pixel;  // whose cost it is: the pixel whose square traced it (from the row's x0)
  Sample value;
  uint64_t rays;  // and its camera ray
};

// A square of the subdivision: its corners index SubdivisionPoints; a split square's
// quadrants are the squares child .. child + 3.
struct SubdivisionSquare {
  float x, y, size;
  std::array<uint32_t, 4> corners;  // bottom-left, bottom-right, top-left, top-right
  uint32_t pixel;
  int32_t child = -1;
};

// One worker's queues, reused from wave to wave (their capacity stays). The camera
// rays are not queued: each is traced as the sampler makes it (trace_camera), and
// what it spawns joins the queues.
struct Wave {
  std::vector<WaveRay> rays;  // the generation being traced
  std::vector<WaveRay> next;  // the children of this generation
  std::vector<WaveFeeler> feelers;
  // Each feeler's share of the passes, where a pass recorder queued it (else empty).
  std::vector<FeelerPasses> feeler_passes;
  std::vector<WaveSample> samples;
  // The camera samples' passes, where passes are kept.
  std::vector<SampleRecord> records;
  // Scratch of the feeler stage: where each light's group starts, the feelers' order
  // grouped by light, and each one's answer.
  std::vector<uint32_t> groups;
  std::vector<uint32_t> order;
  std::vector<uint8_t> blocked;
  // The adaptive sampler's squares and points of the row being traced.
  std::vector<SubdivisionPoint> points;
  std::vector<SubdivisionSquare> squares;
  std::vector<SampleRecord> point_records;  // the points' passes, where kept

  // Starts a wave of `samples` camera samples, none yet traced; with their records
  // when passes are kept.
  void reset(size_t samples, bool passes) {
    rays.clear();
    next.clear();
    feelers.clear();
    feeler_passes.clear();
    this->samples.assign(samples, WaveSample{});
    records.assign(passes ? samples : 0, SampleRecord{});
  }
};

// Where a kernel tracing a wave stands: the ray being traced (its factor on its
// sample) and the factor of the surface being shaded (times the coverage in front).
struct WaveCursor {
  Wave* wave;
  Color factor{1.0f};
  Color layer{1.0f};
  uint32_t sample = 0;
};

// The kernel's policy in a wave (kernel.h's Recurse traces instead): what the recursion
// would trace is appended to the wave, with its factor on the sample.
struct Enqueue {
  static constexpr bool kQueues = true;
  WaveCursor* at;

  // The surface being shaded covers `share` of the ray (the coverage in front, and in a
  // scene with media what they let through).
  void shading(const Color& share) const { at->layer = at->factor * share; }
  // A child ray of `weight` relative to the surface, at `state`, carrying `path` on the
  // passes: the next generation's.
  void child(const Ray& ray, const NodeState& state, const Color& weight,
             const PassPath& path) const {
    at->wave->next.push_back({ray, state, at->layer * weight, at->sample, path});
  }
  // A light sample's feeler (its first query), its share if all of its light arrives,
  // and what the kernel's recorder needs of it then (Recorder::Queued).
  template <class Queued>
  void feeler(const Ray& ray, const Color& unshadowed, uint64_t shadow_sets, int32_t light,
              int depth, const Queued& passes) const {
    at->wave->feelers.push_back(
        {ray, at->layer * unshadowed, shadow_sets, at->sample, light, depth});
    if constexpr (!std::is_empty_v<Queued>) at->wave->feeler_passes.push_back(passes);
  }
};

// The wave's feeler stage: each feeler's first query, those towards one lamp (with
// one set of blockers) as packets, in runs of neighbouring hits; then, in the order
// they were sent, what each lets through times its contribution is added to its sample
// (and, kPasses, to its sample's passes: Wave::feeler_passes holds one per feeler).
template <bool kPasses, uint32_t kEffects, class Queries>
void trace_feelers(const KernelInputs<kEffects, Queries>& in, Wave* wave, RayCounts* counts) {
  const std::vector<WaveFeeler>& feelers = wave->feelers;
  const size_t n = feelers.size();
  // Grouped by light, in their order within each group (a counting sort: lamps, then
  // the emissive meshes').
  const size_t groups = in.scene.lights.size() + 1;
  const auto group = [&](const WaveFeeler& f) {
    return f.light < 0 ? groups - 1 : static_cast<size_t>(f.light);
  };
  std::vector<uint32_t>& starts = wave->groups;
  starts.assign(groups + 1, 0);
  for (const WaveFeeler& f : feelers) starts[group(f) + 1] += 1;
  for (size_t g = 0; g < groups; ++g) starts[g + 1] += starts[g];
  std::vector<uint32_t>& sorted = wave->order;
  sorted.resize(n);
  for (size_t i = 0; i < n; ++i) sorted[starts[group(feelers[i])]++] = static_cast<uint32_t>(i);
  wave->blocked.assign(n, 0);
  std::array<Ray, kFeelerBatch> rays;
  std::array<bool, kFeelerBatch> blocked;
  for (size_t first = 0; first < n;) {
    const WaveFeeler& lead = feelers[sorted[first]];
    size_t end = first + 1;
    while (end < n && end - first < static_cast<size_t>(kFeelerBatch) &&
           group(feelers[sorted[end]]) == group(lead) &&
           feelers[sorted[end]].shadow_sets == lead.shadow_sets) {
      ++end;
    }
    const int count = static_cast<int>(end - first);
    Blockers storage;
    const Blockers* linked = blockers(in.scene, lead.shadow_sets, &storage);
    if (count == 1) {
      for (size_t k = first; k < end; ++k) {
        wave->blocked[sorted[k]] = in.queries.occluded(feelers[sorted[k]].ray, linked) ? 1 : 0;
      }
    } else {
      for (int k = 0; k < count; ++k) rays[k] = feelers[sorted[first + k]].ray;
      in.queries.occluded_packet(rays.data(), count, blocked.data(), linked);
      for (int k = 0; k < count; ++k) wave->blocked[sorted[first + k]] = blocked[k] ? 1 : 0;
    }
    first = end;
  }
  for (size_t i = 0; i < n; ++i) {
    const WaveFeeler& f = feelers[i];
    WaveSample& sample = wave->samples[f.sample];
    const uint64_t before = counts->total();
    Blockers storage;
    const Color transmittance =
        shadow_transmittance(in, f.ray, wave->blocked[i] != 0,
                             blockers(in.scene, f.shadow_sets, &storage), f.depth, counts);
    const Color light = f.contribution * transmittance;
    sample.radiance += light;
    if constexpr (kPasses) wave->feeler_passes[i].arrived(transmittance, light, sample.record);
    sample.rays += counts->total() - before;
  }
}

// A wave traced by a kernel (kernel.h) whose policy is Enqueue. The first generation,
// the camera rays, one by one as the sampler makes them (WaveFns::camera): camera sample
// `sample`'s ray traced and shaded into wave->samples[sample].
template <class Kernel>
void wave_camera(const WhittedIntegrator& w, Wave* wave, const Ray& ray, const NodeState& state,
                 uint32_t sample, const Hit* first, RayCounts* counts, SampleRecord* record) {
  WaveCursor cursor{wave};
  cursor.sample = sample;
  const Kernel kernel(w, record, Enqueue{&cursor});
  WaveSample& s = wave->samples[sample];
  s.record = record;
  const uint64_t before = counts->total();
  s.radiance += kernel.trace(ray, state, counts, &s.alpha, first);
  s.rays += counts->total() - before;
}
// The rest (WaveFns::rest): each generation's feelers, then its children, traced and
// shaded as the next generation, until none is left.
template <class Kernel>
void wave_rest(const WhittedIntegrator& w, Wave* wave, RayCounts* counts) {
  WaveCursor cursor{wave};
  const Kernel kernel(w, nullptr, Enqueue{&cursor});
  // Only a pass recorder's feelers have passes (with the data passes alone, the camera
  // rays' kernel is one, and its feelers' passes hold nothing: the wave skips them).
  constexpr bool kPasses = Kernel::kQueuesPasses;
  for (trace_feelers<kPasses>(kernel.inputs(), wave, counts); !wave->next.empty();
       trace_feelers<kPasses>(kernel.inputs(), wave, counts)) {
    std::swap(wave->rays, wave->next);
    wave->next.clear();
    wave->feelers.clear();
    wave->feeler_passes.clear();
    for (const WaveRay& r : wave->rays) {
      WaveSample& sample = wave->samples[r.sample];
      cursor.factor = r.factor;
      cursor.sample = r.sample;
      const uint64_t before = counts->total();
      sample.radiance +=
          r.factor * kernel.resume(r.ray, r.state, r.factor, r.path, sample.record, counts);
      sample.rays += counts->total() - before;
    }
  }
}

}  // namespace whitted
