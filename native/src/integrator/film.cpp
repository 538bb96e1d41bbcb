#include "integrator/film.h"

#include <algorithm>
#include <array>
#include <atomic>

namespace whitted {
namespace {

// Buffers a worker writes while Python may copy them: relaxed atomic access per float
// (a plain move on x86), so the copy is race-free without a lock.
void store(float& value, float v) {
  std::atomic_ref<float>(value).store(v, std::memory_order_relaxed);
}
float load(const float& value) {
  // atomic_ref needs a mutable reference (until C++26); the float itself is not const.
  return std::atomic_ref<float>(const_cast<float&>(value)).load(std::memory_order_relaxed);
}

void store_rgba(float* out, const Sample& s) {
  store(out[0], s.radiance.x);
  store(out[1], s.radiance.y);
  store(out[2], s.radiance.z);
  store(out[3], s.alpha);
}

// Half floats reach 65504; NaN (which compares false) and negatives become 0.
float displayable(float v) {
  return v > 0.0f ? std::min(v, 65000.0f) : 0.0f;
}

// Cividis (Nunez, Anderton and Renslow 2018), a perceptually uniform ramp from dark blue
// to yellow, sampled at 0, 1/8, ..., 1 and converted from sRGB to linear: the display
// texture is scene-linear, and Blender applies the view transform.
constexpr std::array<std::array<float, 3>, 9> kRamp = {{{0.0000f, 0.0164f, 0.0756f},
                                                        {0.0106f, 0.0398f, 0.1593f},
                                                        {0.0566f, 0.0772f, 0.1494f},
                                                        {0.1198f, 0.1295f, 0.1592f},
                                                        {0.2037f, 0.2007f, 0.1882f},
                                                        {0.3293f, 0.2955f, 0.1819f},
                                                        {0.5017f, 0.4209f, 0.1503f},
                                                        {0.7307f, 0.5863f, 0.0966f},
                                                        {0.9903f, 0.8060f, 0.0389f}}};

// The ramp at t in [0, 1], linearly between its samples.
void ramp(float t, float* out) {
  const float x = std::clamp(t, 0.0f, 1.0f) * static_cast<float>(kRamp.size() - 1);
  const auto i = std::min(static_cast<size_t>(x), kRamp.size() - 2);
  const float f = x - static_cast<float>(i);
  for (int c = 0; c < 3; ++c) out[c] = kRamp[i][c] + f * (kRamp[i + 1][c] - kRamp[i][c]);
}

}  // namespace

Film::Film(int width, int height, bool accumulate)
    : width_(width),
      height_(height),
      pixels_(size_t{4} * width * height, 0.0f),
      cost_(static_cast<size_t>(width) * height, 0.0f) {
  if (accumulate) {
    sum_.assign(pixels_.size(), 0.0f);
    count_.assign(cost_.size(), 0);
  }
}

void Film::set(int x, int y, const Sample& value, float cost) {
  const size_t i = index(x, y);
  store_rgba(&pixels_[4 * i], value);
  store(cost_[i], cost);
}

void Film::add(int x, int y, const Sample& sample, float cost) {
  const size_t i = index(x, y);
  float* sum = &sum_[4 * i];
  // The same additions, in the same order, as a whole pixel's mean (CameraSampler), so
  // the last pass leaves exactly the value a pass of whole pixels gives.
  sum[0] += sample.radiance.x;
  sum[1] += sample.radiance.y;
  sum[2] += sample.radiance.z;
  sum[3] += sample.alpha;
  count_[i] += 1;
  const float w = 1.0f / static_cast<float>(count_[i]);
  store_rgba(&pixels_[4 * i], Sample{Color(sum[0], sum[1], sum[2]) * w, sum[3] * w});
  // The first sample's rays replace the preview's.
  store(cost_[i], count_[i] == 1 ? cost : load(cost_[i]) + cost);
}

void Film::display_image(float* out) const {
  for (size_t i = 0; i < pixels_.size(); ++i) out[i] = displayable(load(pixels_[i]));
}

void Film::display_cost(float* out) const {
  float most = 0.0f;
  for (const float& c : cost_) most = std::max(most, load(c));
  const float scale = most > 0.0f ? 1.0f / most : 0.0f;
  for (size_t i = 0; i < cost_.size(); ++i) {
    ramp(load(cost_[i]) * scale, &out[4 * i]);
    out[4 * i + 3] = 1.0f;
  }
}

}  // namespace whitted
