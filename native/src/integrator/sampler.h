// Camera samples: where a pixel's camera rays go (grid, jitter, adaptive subdivision),
// and what they bring back through the integrator.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "integrator/film.h"
#include "integrator/pixel_filter.h"
#include "integrator/wave.h"
#include "integrator/whitted.h"
#include "scene/camera.h"

namespace whitted {

// Whether camera rays go to Embree as packets (Settings::packets allowing; FirstHits).
// A packet pays when its rays stay together and loses when they part for different
// instances: Embree then walks each instance's BVH for the whole packet. Callgrind
// counted, per camera ray, 0.85 of a single ray's traversal for a packet on 100 spheres
// in view and 1.78 on 7,000 spheres a few pixels across. What sorted every scene
// measured was the number of instances in view per pixel (each instance's bounding
// sphere as the camera projects it, inside the image and not behind the camera); packets
// are kept up to the measured break-even (kPacketInstancesPerPixel, sampler.cpp). A pure
// function of the scene, the camera and the settings, so tiles and threads change
// nothing; packets change no pixel but where two faces tie (settings.h, `packets`).
struct PacketChoice {
  bool packets = true;
  size_t visible_instances = 0;   // instances in view
  float instances_per_pixel = 0;  // visible_instances / pixels
};
PacketChoice choose_packets(const CompiledScene& scene, const Camera& camera,
                            const Settings& settings);

// The first hits of the camera rays of a block of pixels in one row, found as Embree
// packets (CameraSampler::first_hits): a block is `width` pixels from a column that is a
// multiple of `width`, counted from the image's left edge, so which rays share a packet
// depends on neither tiles, threads nor the border.
struct FirstHits {
  int x0 = -1;
  int y = -1;
  int width = 0;          // pixels in the block (the last block of a row may have fewer)
  std::vector<Ray> rays;  // pixel by pixel, each pixel's grid samples in order
  std::vector<Hit> hits;
  // Whether hits[i] was found by a packet; a lone ray left over is traced by the
  // integrator itself, as it would be without packets.
  std::vector<uint8_t> found;
  bool holds(int x, int row) const { return row == y && x >= x0 && x < x0 + width; }
};

// The camera rays of one pixel's samples in a round of noise-driven sampling
// (CameraSampler::round_hits), in the order of their index, with their first hits found as
// Embree packets of this pixel's rays alone, so which rays share a packet depends on the
// pixel and the round only (not on tiles, threads or which neighbours are active).
struct RoundHits {
  int first = 0;  // the index of the round's first sample
  std::vector<Ray> rays;
  std::vector<Hit> hits;
  std::vector<uint8_t> found;  // as FirstHits::found
};

// Where camera sample k of a pixel's regular n x n grid (and Cryptomatte's coverage
// sample k) is on the lens and in the shutter; the Monte Carlo camera samples take theirs
// from Sobol sequences instead (CameraSampler::grid_ray). Each is stratified apart from the
// film (and from the other) by its own permutation of the n^2 strata, chosen by the pixel,
// and jittered within its stratum; a fixed pairing (sample (i, j) with stratum (j, i) in
// every pixel) covers only n^2 of the n^4 joint cells of film and lens, the same in every
// pixel, and blurs wrongly (against Cycles, a panorama's defocus erred 0.006 where this
// errs less than 0.001). The time goes through the camera's Shutter. The lens centre and
// time 0 where `camera` has no aperture and nothing `moves`.
struct LensTime {
  glm::vec2 lens{0.5f};
  float time = 0.0f;
};
LensTime lens_and_time(const Camera& camera, bool moves, uint32_t seed, int x, int y, int k, int n,
                       int height);

// Pixel (x, y)'s random key for `salt` (each kind of draw its own salt): a hash of the
// pixel and the salt, changed by the render's Seed (Settings::seed; 0 changes nothing).
// Every key a pixel's samples are drawn from comes from it, so another seed draws other,
// equally distributed samples.
uint32_t pixel_key(uint32_t seed, int x, int y, uint32_t salt);

// The cell (row by row) of a regular grid's sample k of pixel (x, y): k itself, but with
// noise-driven sampling a permutation of the grid chosen by the pixel, so that the first
// samples of a pixel stopped early are a uniform subset of its cells (row order would
// leave it its bottom rows). The Monte Carlo samples need none: their index is their
// order, every power-of-two prefix stratified (CameraSampler::grid_ray).
int regular_cell(const Settings& settings, int x, int y, int k);

// One per worker (it traces through that worker's integrator). Everything it returns
// depends only on the pixel and the sample, never on tiles or threads.
class CameraSampler {
 public:
  // `camera_media`: the glass the camera is inside, if any; `packets`: choose_packets'
  // answer for the render (a pixel's camera rays as one Embree packet, or one by one).
  CameraSampler(const WhittedIntegrator& integrator, const Camera& camera,
                const MediumStack& camera_media, bool packets);

  // The pixel whose bottom-left corner is (x, y), whole, by the anti-aliasing mode: the
  // mean of its regular or jittered grid samples, or Whitted's adaptive subdivision.
  // `weights`, when given, receives each camera sample's weight in the pixel, in the
  // order they were traced (the inspector's). `record` (when passes are requested; a
  // default SampleRecord) receives the pixel's passes: its samples' records weighted as
  // their radiance is.
  // `block`, when given, holds the first hits of the pixel's block (first_hits);
  // otherwise the sampler finds them itself, the same way.
  Sample pixel(int x, int y, RayCounts* counts, std::vector<float>* weights = nullptr,
               SampleRecord* record = nullptr, const FirstHits* block = nullptr) const;
  // Grid sample k of pixel (x, y), alone: the centre of its cell (regular_cell) for
  // regular anti-aliasing, else point k of the pixel's Sobol sequences (grid_ray). The same ray as
  // in pixel(), traced on its own.
  Sample grid_sample(int x, int y, int k, RayCounts* counts, SampleRecord* record = nullptr) const;
  // Pixels per block of pixel() (whole pixels' camera rays in packets); 0 when camera rays
  // are traced one by one: packets off, adaptive anti-aliasing, or one sample per pixel.
  int block_width() const;
  // The first hits of the block holding pixel (x, y) (block_width() > 0).
  void first_hits(int x, int y, FirstHits* out) const;
  // Samples first .. first + count - 1 of pixel (x, y): their rays and,
  // where the render uses packets (choose_packets, any anti-aliasing mode: a round samples
  // the grid), their first hits in packets of this pixel's rays.
  void round_hits(int x, int y, int first, int count, RoundHits* out) const;
  // Sample i of `round` (round_hits of pixel (x, y)): grid_sample of index round.first + i,
  // its first hit taken from the packet where one found it.
  Sample round_sample(int x, int y, const RoundHits& round, int i, RayCounts* counts,
                      SampleRecord* record) const;
  // Whether pixels and grid samples are traced in waves (row()): where the integrator
  // has a wave kernel.
  bool waves() const;
  // Pixels [x0, x1) of row y traced in waves (waves()), as one wave: each pixel whole
  // when `sample` < 0 (its grid, or adaptive subdivision a wave per depth: row_adaptive),
  // (*values)[i] pixel x0 + i's value as pixel() gives it; else its samples `sample` ..
  // `sample` + `count` - 1, each apart, (*values)[i * count + j]
  // sample `sample` + j of pixel x0 + i as grid_sample() gives it. Up to float rounding
  // (wave.h); (*rays) the rays each cost, and, where passes are kept, (*records) the
  // records pixel() or grid_sample() fills, up to float rounding. Whole pixels:
  // (*samples)[i] the camera samples pixel x0 + i took (its grid, or its points).
  void row(int x0, int x1, int y, int sample, int count, Wave* wave, RayCounts* counts,
           std::vector<Sample>* values, std::vector<uint64_t>* rays,
           std::vector<SampleRecord>* records, std::vector<uint32_t>* samples) const;
  // One camera ray through image point (px, py), in pixels from the bottom-left corner.
  Sample point(float px, float py, RayCounts* counts, SampleRecord* record = nullptr) const;

 private:
  Sample pixel_grid(int x, int y, RayCounts* counts, std::vector<float>* weights,
                    SampleRecord* record, const FirstHits* block) const;
  // `block` if it holds (x, y); else, with blocks, `own` filled for it; else null.
  const FirstHits* block_for(int x, int y, const FirstHits* block, FirstHits* own) const;
  Sample pixel_adaptive(int x, int y, RayCounts* counts, std::vector<float>* weights,
                        SampleRecord* record) const;
  // Whitted's adaptive subdivision of the square at (x0, y0) of side `size` whose corner
  // samples are `corners` (bottom-left, bottom-right, top-left, top-right); with `weights`,
  // `ids` are the corners' indices into it; when passes are recorded, `records` are the
  // corners' records and `out` receives the square's.
  Sample subdivide(float x0, float y0, float size, const Sample corners[4], const size_t ids[4],
                   const SampleRecord* const records[4], int depth, RayCounts* counts,
                   std::vector<float>* weights, SampleRecord* out) const;
  // Whether pixels are Whitted's adaptive subdivision (pixel()).
  bool adaptive() const;
  // Whether the square of depth `depth` whose corner samples are `corners` splits: they
  // differ as shown by more than the threshold, and the depth allows.
  bool splits(const Sample corners[4], int depth) const;
  // row() for adaptive anti-aliasing: pixel_adaptive's subdivision breadth first, every
  // pixel's corners as one wave, then the midpoints of the squares that split at each
  // depth as the next; each square's mean then summed bottom-up in subdivide's order, so
  // values differ from pixel()'s by the wave's rounding only, except where that rounding
  // moves a square's spread across the threshold.
  void row_adaptive(int x0, int x1, int y, Wave* wave, RayCounts* counts,
                    std::vector<Sample>* values, std::vector<uint64_t>* rays,
                    std::vector<SampleRecord>* records, std::vector<uint32_t>* samples) const;
  // Camera ray `ray` of wave sample `index` (`root` its NodeState; `first` its first hit,
  // when found) traced into the wave, and counted, as shade() does; its data passes into
  // `record` (fresh) where passes are kept.
  void start(Wave* wave, const Ray& ray, const NodeState& root, uint32_t index, const Hit* first,
             RayCounts* counts, SampleRecord* record) const;
  // A wave sample's value as shade() returns it: not finite, it is counted and dropped,
  // and its record (if any) emptied. Inline: called out of line (through the PLT, as
  // the core's symbols can be interposed), its Sample was spilled and reloaded across
  // the call, a stall per camera sample (perf annotate, session 22).
  static Sample finished(const WaveSample& s, RayCounts* counts, SampleRecord* record) {
    if (!is_finite(s.radiance)) {
      counts->nonfinite_samples += 1;  // never let one bad sample poison a pixel
      if (record != nullptr) *record = SampleRecord{};
      return {Color(0.0f), 0.0f};
    }
    return {s.radiance, s.alpha};
  }
  // The first hits of `count` camera rays, a packet of up to kIntersectPacketSize at a
  // time in order; found[i] 0 for a lone ray left over (the integrator traces it).
  void packet_hits(const Ray* rays, int count, Hit* hits, uint8_t* found) const;
  // The next point sample's index into `weights` (0 without weights).
  static size_t new_weight(std::vector<float>* weights);
  // The camera ray of grid sample k of pixel (x, y).
  Ray grid_ray(int x, int y, int k) const;
  // Where grid sample k of pixel (x, y) starts: root_ with the sample's seed, the pixel's
  // key and the sample's index (NodeState::seed, pixel, index).
  NodeState grid_root(int x, int y, int k) const;
  // Where a camera sample at film position (px, py) that is no grid sample starts
  // (Whitted's adaptive corners): root_ with a seed hashed from the position.
  NodeState film_root(float px, float py) const;
  // The camera ray through film position (px, py), in pixels, from aperture sample `lens`
  // at shutter time `time`.
  Ray camera_ray(float px, float py, glm::vec2 lens, float time) const;
  // An aperture sample for a film position that is no grid sample (adaptive
  // anti-aliasing's corners): a hash of the position.
  glm::vec2 film_lens(float px, float py) const;
  // Its shutter time likewise (0 when nothing moves).
  float film_time(float px, float py) const;
  // The radiance and coverage of a camera ray whose first hit is known, or not (nullptr),
  // starting from `root` (grid_root, or a film position's seed).
  Sample shade(const Ray& ray, const Hit* first, RayCounts* counts, SampleRecord* record,
               const NodeState& root) const;

  const WhittedIntegrator& integrator_;
  const Settings& settings_;
  const Camera& camera_;
  const CameraFrame frame_;   // camera_'s, made once: not per camera ray
  const PixelFilter filter_;  // where grid samples land about the pixel's centre
  const bool packets_;        // choose_packets' answer, made once per render
  // Whether the camera or an instance moves within the shutter: camera samples then
  // spread over it (motion blur), else all are at time 0.
  const bool moves_;
  // Whether camera samples spread over the lens or the shutter: adaptive anti-aliasing
  // then takes the jittered grid (pixel()).
  const bool distributed_;
  // Where every camera ray starts (depth 0, weight 1, inside the camera's media), made
  // once: not copied per camera ray.
  const NodeState root_;
};

}  // namespace whitted
