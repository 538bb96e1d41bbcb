// Tracing in waves (Settings::waves): the camera samples of a row of a tile traced
// together, one generation of rays at a time, instead of each sample's ray tree
// depth-first.
//
// The kernel is the recursive one's (whitted.cpp): each ray of a generation is traced and
// shaded by the same code, but where the recursion would trace a child ray (branch) or
// a shadow feeler (feelers), it appends it to the wave instead, with its factor on the
// sample (the product of the weights the recursion would multiply its radiance by). The
// wave then traces the generation's feelers, grouped by light so that feelers towards
// one lamp from neighbouring hits go to Embree as packets, and moves on to the children.
//
// A sample's radiance is the sum of its rays' factors times their local terms, added in
// an order that depends only on the sample (its camera ray, its feelers in the order it
// sent them, then its children in the order it spawned them, and so on), so pixels stay
// independent of tiles and threads. The recursion sums the same terms bottom-up
// (I = local + sigma_r * (local' + ...)), so the two differ by float rounding only
// (tests/native/wave_test.cpp states the bound). The default (Settings::waves); what it
// measured against the recursion is in docs/notes/waves.md.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "accel/embree.h"
#include "core/ray.h"
#include "integrator/film.h"
#include "integrator/passes.h"
#include "integrator/whitted.h"

namespace whitted {

// A ray waiting in a wave: what the recursion would have passed to trace(), and its
// factor on its sample.
struct WaveRay {
  Ray ray;
  NodeState state;
  Color factor{1.0f};
  uint32_t sample = 0;
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
// its coverage and the rays it cost.
struct WaveSample {
  Color radiance{0.0f};
  float alpha = 1.0f;
  uint64_t rays = 0;
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
  std::vector<WaveSample> samples;
  // The camera samples' data passes, where passes are kept (WhittedIntegrator::waves()).
  std::vector<SampleRecord> records;
  // Scratch of the feeler stage: where each light's group starts, the feelers' order
  // grouped by light, and each one's answer.
  std::vector<uint32_t> groups;
  std::vector<uint32_t> order;
  std::vector<uint8_t> blocked;
  // The adaptive sampler's squares and points of the row being traced.
  std::vector<SubdivisionPoint> points;
  std::vector<SubdivisionSquare> squares;
  std::vector<SampleRecord> point_records;  // the points' data passes, where kept

  // Starts a wave of `samples` camera samples, none yet traced; with their records
  // when passes are kept.
  void reset(size_t samples, bool passes) {
    rays.clear();
    next.clear();
    feelers.clear();
    this->samples.assign(samples, WaveSample{});
    records.assign(passes ? samples : 0, SampleRecord{});
  }
};

}  // namespace whitted
