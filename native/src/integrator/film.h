// The film: what a render accumulates per pixel, and what Python reads of it.
#pragma once

#include <cstdint>
#include <vector>

#include "core/math.h"

namespace whitted {

// What a camera sample, or a whole pixel, contributes: radiance and coverage.
struct Sample {
  Color radiance;
  float alpha;
};

// Each pixel shows the mean of its own samples, or, while it has none, the preview a
// coarse pass left there; its cost is the rays its samples took (or its preview's).
// Writers: one worker per pixel at a time (a pass gives each pixel to one tile, and the
// passes run in order). Readers may read while workers write: every float of the shown
// buffers is stored and loaded atomically (relaxed), so a copy shows each value old or
// new, never torn, and a pixel's value is always a mean of whole samples.
class Film {
 public:
  // `accumulate`: keep sums and counts for pixels built one sample at a time
  // (progressive); without it only set() may be used.
  Film(int width, int height, bool accumulate);

  int width() const { return width_; }
  int height() const { return height_; }

  // What pixel (x, y) shows, and the rays it took: the final value of a pixel rendered
  // whole, or a preview, shown until the pixel has a sample of its own.
  void set(int x, int y, const Sample& value, float cost);
  // One more sample of pixel (x, y), and its rays: the pixel shows the mean so far.
  void add(int x, int y, const Sample& sample, float cost);

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

 private:
  size_t index(int x, int y) const { return static_cast<size_t>(y) * width_ + x; }

  int width_;
  int height_;
  std::vector<float> pixels_;    // RGBA shown
  std::vector<float> cost_;      // rays per pixel shown
  std::vector<float> sum_;       // RGBA sums of the samples (accumulating only)
  std::vector<uint32_t> count_;  // samples taken (accumulating only)
};

}  // namespace whitted
