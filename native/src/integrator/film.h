// The film: what a render accumulates per pixel, and what Python reads of it.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/math.h"
#include "integrator/passes.h"

namespace whitted {

// What a camera sample, or a whole pixel, contributes: radiance and coverage.
struct Sample {
  Color radiance;
  float alpha;
};

// Noise-driven sampling's estimate of a pixel's error (Cycles' film_adaptive_sampling_
// convergence_check, after "A hierarchical automatic stopping condition for Monte Carlo
// global illumination", section 2.1): `mean` the mean of all its samples, `half` the mean
// of its class-A samples (core/sobol.h class_a, by the sample's index, as Cycles'). The summed
// absolute RGB difference, over sqrt(luminance sum) below 1 and the sum itself above, plus 1e-4.
float noise_error(const Color& mean, const Color& half);

// Cycles scales the user's noise threshold by this before comparing ("an arbitrary
// factor", scene/integrator.cpp Integrator::get_adaptive_sampling).
inline constexpr float kNoiseThresholdScale = 5.0f;

// Each pixel shows the mean of its own samples, or, while it has none, the preview a
// coarse pass left there; its cost is the rays its samples took (or its preview's).
// Writers: one worker per pixel at a time (a pass gives each pixel to one tile, and the
// passes run in order). Readers may read while workers write: every float of the shown
// buffers is stored and loaded atomically (relaxed), so a copy shows each value old or
// new, never torn, and a pixel's value is always a mean of whole samples.
class Film {
 public:
  // `accumulate`: keep sums and counts for pixels built one sample at a time
  // (progressive); without it only set() may be used. `passes` (bits of FilmPass) are
  // kept besides the image and the cost; `contribution_depth` sizes Contributions.
  // `adaptive` (needs `accumulate`): keep the class-A half sums and the active mask of
  // noise-driven sampling (converge(), active()).
  Film(int width, int height, bool accumulate, uint32_t passes = 0, int contribution_depth = 1,
       bool adaptive = false);

  int width() const { return width_; }
  int height() const { return height_; }

  // What pixel (x, y) shows, and the rays it took: the final value of a pixel rendered
  // whole from `samples` camera samples, or a preview (0 samples of its own), shown until
  // the pixel has a sample of its own. `record`, the pixel's (the mean of its samples'
  // records), fills the kept passes the kernel records; Sample Count takes `samples`.
  void set(int x, int y, const Sample& value, float cost, uint32_t samples,
           const SampleRecord* record = nullptr);
  // One more sample of pixel (x, y), and its rays: the pixel shows the mean so far.
  void add(int x, int y, const Sample& sample, float cost, const SampleRecord* record = nullptr);
  // `count` more samples of pixel (x, y) in order, each with its rays (`costs`) and, where
  // passes are kept, its record: the sums of adding them one at a time, the shown values
  // written once at the end (a round's samples of a pixel).
  void add(int x, int y, const Sample* samples, const float* costs, int count,
           const SampleRecord* records = nullptr);

  // Noise-driven sampling, between rounds (no writer running): each pixel of `area`
  // (x, y, width, height) converged when noise_error < kNoiseThresholdScale * threshold;
  // a pixel stays active while it or one of its 8 neighbours inside `area` is not
  // converged (Cycles' dilation). Returns the active pixels. All pixels start active.
  size_t converge(float threshold, int x, int y, int width, int height);
  bool active(int x, int y) const { return active_.empty() || active_[index(x, y)] != 0; }
  // Pixel (x, y)'s noise_error, from the mean of its samples and of its class-A half
  // (adaptive only); NaN while it has no class-A sample (fewer than 3 samples).
  float noise(int x, int y) const;
  // Samples taken by pixel (x, y) (accumulating only).
  uint32_t samples(int x, int y) const { return count_[index(x, y)]; }

  bool has_pass(FilmPass pass) const { return (passes_ & pass_bit(pass)) != 0; }
  // Floats per pixel of a pass: 1 (Depth, Mist, indices, Cut Weight), 3 per depth bin
  // (Contributions), 3 for the others.
  int pass_channels(FilmPass pass) const { return channels_[static_cast<size_t>(pass)]; }
  // A kept pass as shown, pass_channels floats per pixel, rows bottom to top: Direct
  // and Indirect divided by their Color where it is kept and not 0, Mist as 1 - the
  // summed coverage-weighted (1 - mist).
  const std::vector<float>& pass(FilmPass pass) const { return shown_[static_cast<size_t>(pass)]; }

  // As shown, rows bottom to top: RGBA, and rays per pixel. A finished tile's pixels no
  // longer change and may be read directly.
  const std::vector<float>& pixels() const { return pixels_; }
  const std::vector<float>& cost() const { return cost_; }

  // Copies for a half-float display texture, width * height * 4 floats, rows bottom to
  // top. The image: RGBA as shown, each value clamped to [0, 65000] (half's range) and
  // NaN made 0. The cost: a heat map of rays per pixel, normalised by the largest so far,
  // alpha 1.
  void display_image(float* out) const;
  void display_cost(float* out) const;
  // A kept pass, channels `first` .. `first` + 2 (or `first` alone, shown grey, for a
  // pass of one float), clamped as the image is; Depth is divided by the farthest
  // surface shown, so that it spans 0 .. 1.
  void display_pass(FilmPass pass, int first, float* out) const;

 private:
  size_t index(int x, int y) const { return static_cast<size_t>(y) * width_ + x; }
  // A kept pass the kernel records (kRecordedPasses), as opposed to the film's own.
  bool has_recorded(FilmPass pass) const {
    return (passes_ & kRecordedPasses & pass_bit(pass)) != 0;
  }
  // Sample Count, where it is kept: pixel i took `samples` camera samples.
  void store_count(size_t i, uint32_t samples);

  int width_;
  int height_;
  std::vector<float> pixels_;    // RGBA shown
  std::vector<float> cost_;      // rays per pixel shown
  std::vector<float> sum_;       // RGBA sums of the samples (accumulating only)
  std::vector<uint32_t> count_;  // samples taken (accumulating only)
  std::vector<float> half_;      // RGB sums of the class-A samples (adaptive only)
  std::vector<uint8_t> active_;  // whether a pixel takes more samples (adaptive only)
  uint32_t passes_;
  std::array<int, kFilmPassCount> channels_{};
  std::array<std::vector<float>, kFilmPassCount> shown_;  // each kept pass as shown
  std::array<std::vector<float>, kFilmPassCount> sums_;   // their sums (accumulating only)
};

}  // namespace whitted
