#include "integrator/film.h"

#include "core/sobol.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>

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

int channels_of(FilmPass pass, int contribution_depth) {
  const int channels = kFilmPasses[static_cast<size_t>(pass)].channels;
  return pass == FilmPass::kContributions ? channels * (contribution_depth + 1) : channels;
}

// The floats a pass sums per pixel: those it shows, but for Shadow Catcher, which sums
// the light on the catchers with and without the other objects (RGB each) and the
// catchers' coverage, and shows their quotient.
constexpr int kCaughtSums = 7;
int sums_of(FilmPass pass, int channels) {
  return pass == FilmPass::kShadowCatcher ? kCaughtSums : channels;
}
// The floats gather() may write.
constexpr size_t kRawFloats =
    std::max(size_t{3} * (kMaxContributionDepth + 1), size_t{kCaughtSums});

// Passes a pixel takes from its first sample alone (as Cycles), not a mean.
bool first_sample_only(FilmPass pass) {
  return pass == FilmPass::kDepth || pass == FilmPass::kPosition ||
         pass == FilmPass::kObjectIndex || pass == FilmPass::kMaterialIndex;
}

void put(float* out, const Color& c) {
  out[0] = c.x;
  out[1] = c.y;
  out[2] = c.z;
}

// The floats `pass` takes from a record, before resolve().
void gather(FilmPass pass, const SampleRecord& r, float* out) {
  switch (pass) {
    case FilmPass::kEmission:
      return put(out, r.emission);
    case FilmPass::kEnvironment:
      return put(out, r.environment);
    case FilmPass::kDiffuseDirect:
      return put(out, r.diffuse_direct);
    case FilmPass::kDiffuseIndirect:
      return put(out, r.diffuse_indirect);
    case FilmPass::kDiffuseColor:
      return put(out, r.diffuse_color);
    case FilmPass::kGlossyDirect:
      return put(out, r.glossy_direct);
    case FilmPass::kGlossyIndirect:
      return put(out, r.glossy_indirect);
    case FilmPass::kGlossyColor:
      return put(out, r.glossy_color);
    case FilmPass::kTransmissionDirect:
      return put(out, Color(0.0f));
    case FilmPass::kTransmissionIndirect:
      return put(out, r.transmission_indirect);
    case FilmPass::kTransmissionColor:
      return put(out, r.transmission_color);
    case FilmPass::kVolumeDirect:
      return put(out, r.volume_direct);
    case FilmPass::kVolumeIndirect:
      return put(out, Color(0.0f));
    case FilmPass::kDepth:
      out[0] = r.depth;
      return;
    case FilmPass::kMist:
      out[0] = r.mist;
      return;
    case FilmPass::kNormal:
      return put(out, r.normal);
    case FilmPass::kPosition:
      return put(out, r.position);
    case FilmPass::kUV:
      return put(out, r.uv);
    case FilmPass::kObjectIndex:
      out[0] = r.object_index;
      return;
    case FilmPass::kMaterialIndex:
      out[0] = r.material_index;
      return;
    case FilmPass::kContributions:
      for (size_t d = 0; d < r.contributions.size(); ++d) put(out + 3 * d, r.contributions[d]);
      return;
    case FilmPass::kCutWeight:
      out[0] = r.cut_weight;
      return;
    case FilmPass::kDenoisingAlbedo:
      return put(out, r.denoising_albedo);
    case FilmPass::kDenoisingNormal:
      return put(out, r.denoising_normal);
    case FilmPass::kShadowCatcher:
      put(out, r.caught.with);
      put(out + 3, r.caught.without);
      out[6] = r.caught_coverage;
      return;
    case FilmPass::kSampleCount:  // the film's, not the record's
    case FilmPass::kCount:
      return;
  }
}

// The Color a Direct or Indirect pass is divided by; kCount for the other passes.
FilmPass color_of(FilmPass pass) {
  switch (pass) {
    case FilmPass::kDiffuseDirect:
    case FilmPass::kDiffuseIndirect:
      return FilmPass::kDiffuseColor;
    case FilmPass::kGlossyDirect:
    case FilmPass::kGlossyIndirect:
      return FilmPass::kGlossyColor;
    case FilmPass::kTransmissionDirect:
    case FilmPass::kTransmissionIndirect:
      return FilmPass::kTransmissionColor;
    default:
      return FilmPass::kCount;
  }
}

// The Shadow Catcher pass as shown from its sums' means (`raw`: with, without, the
// catchers' coverage) and Combined's alpha, as Cycles' film_calculate_shadow_catcher:
// with / without per channel where the pixel met a catcher (1 where it met none), then
// over white by the alpha the pixel has with the catchers in it (Combined's, which
// leaves them out, plus their coverage), which keeps the catcher's edges clean.
void resolve_caught(const float* raw, float alpha, float* shown) {
  const CaughtLight light{Color(raw[0], raw[1], raw[2]), Color(raw[3], raw[4], raw[5])};
  const Color ratio = raw[6] > 0.0f ? light.ratio() : Color(1.0f);
  const float covered = std::clamp(alpha + raw[6], 0.0f, 1.0f);
  for (int c = 0; c < 3; ++c) store(shown[c], (1.0f - covered) + covered * ratio[c]);
}

// A pass's value as shown from its mean (`raw`, `channels` floats) and, for Direct and
// Indirect, its Color's mean (nullptr when the Color pass is not kept: then, as in
// Cycles, the pass keeps colour times light); `alpha`, Combined's, for Shadow Catcher.
void resolve(FilmPass pass, const float* raw, const float* color, int channels, float alpha,
             float* shown) {
  if (pass == FilmPass::kShadowCatcher) return resolve_caught(raw, alpha, shown);
  for (int c = 0; c < channels; ++c) {
    float v = raw[c];
    if (pass == FilmPass::kMist) v = 1.0f - v;
    if (color != nullptr) v = color[c] != 0.0f ? v / color[c] : 0.0f;
    store(shown[c], v);
  }
}

}  // namespace

float noise_error(const Color& mean, const Color& half) {
  const float difference =
      std::fabs(mean.x - half.x) + std::fabs(mean.y - half.y) + std::fabs(mean.z - half.z);
  const float sum = mean.x + mean.y + mean.z;
  return difference / (1e-4f + (sum < 1.0f ? std::sqrt(std::max(sum, 0.0f)) : sum));
}

Film::Film(int width, int height, bool accumulate, uint32_t passes, int contribution_depth,
           bool adaptive)
    : width_(width),
      height_(height),
      pixels_(size_t{4} * width * height, 0.0f),
      cost_(static_cast<size_t>(width) * height, 0.0f),
      passes_(passes) {
  if (accumulate) {
    sum_.assign(pixels_.size(), 0.0f);
    count_.assign(cost_.size(), 0);
  }
  if (accumulate && adaptive) {
    half_.assign(3 * cost_.size(), 0.0f);
    active_.assign(cost_.size(), 1);
  }
  for (size_t p = 0; p < kFilmPassCount; ++p) {
    const auto pass = static_cast<FilmPass>(p);
    channels_[p] = channels_of(pass, contribution_depth);
    if (!has_pass(pass)) continue;
    const size_t size = cost_.size() * static_cast<size_t>(channels_[p]);
    // A pixel not traced yet shows the sky's depth, as Cycles does, and no catcher's
    // shadow.
    const float untraced =
        pass == FilmPass::kDepth ? kNoDepth : (pass == FilmPass::kShadowCatcher ? 1.0f : 0.0f);
    shown_[p].assign(size, untraced);
    if (accumulate) {
      sums_[p].assign(cost_.size() * static_cast<size_t>(sums_of(pass, channels_[p])), 0.0f);
    }
  }
}

void Film::set(int x, int y, const Sample& value, float cost, uint32_t samples,
               const SampleRecord* record) {
  const size_t i = index(x, y);
  store_rgba(&pixels_[4 * i], value);
  store(cost_[i], cost);
  store_count(i, samples);
  if (record == nullptr) return;
  std::array<float, kRawFloats> raw{};
  std::array<float, 3> color{};
  for (size_t p = 0; p < kFilmPassCount; ++p) {
    const auto pass = static_cast<FilmPass>(p);
    if (!has_recorded(pass)) continue;
    const int n = channels_[p];
    gather(pass, *record, raw.data());
    const FilmPass divisor = color_of(pass);
    const bool divide = divisor != FilmPass::kCount && has_pass(divisor);
    if (divide) gather(divisor, *record, color.data());
    resolve(pass, raw.data(), divide ? color.data() : nullptr, n, value.alpha, &shown_[p][n * i]);
  }
}

void Film::add(int x, int y, const Sample& sample, float cost, const SampleRecord* record) {
  add(x, y, &sample, &cost, 1, record);
}

void Film::add(int x, int y, const Sample* samples, const float* costs, int count,
               const SampleRecord* records) {
  const size_t i = index(x, y);
  float* sum = &sum_[4 * i];
  // The first sample's rays replace the preview's.
  float cost = count_[i] == 0 ? 0.0f : load(cost_[i]);
  std::array<float, kRawFloats> raw{};
  for (int k = 0; k < count; ++k) {
    const Sample& sample = samples[k];
    // The same additions, in the same order, as a whole pixel's mean (CameraSampler), so
    // the last pass leaves exactly the value a pass of whole pixels gives.
    sum[0] += sample.radiance.x;
    sum[1] += sample.radiance.y;
    sum[2] += sample.radiance.z;
    sum[3] += sample.alpha;
    if (!half_.empty() && class_a(count_[i])) {  // the sample's index is its position
      half_[3 * i] += sample.radiance.x;
      half_[3 * i + 1] += sample.radiance.y;
      half_[3 * i + 2] += sample.radiance.z;
    }
    count_[i] += 1;
    cost += costs[k];
    if (records == nullptr) continue;
    for (size_t p = 0; p < kFilmPassCount; ++p) {
      const auto pass = static_cast<FilmPass>(p);
      if (!has_recorded(pass)) continue;
      const int n = sums_of(pass, channels_[p]);
      float* pixel_sum = &sums_[p][n * i];
      gather(pass, records[k], raw.data());
      for (int c = 0; c < n; ++c) {
        pixel_sum[c] = first_sample_only(pass) ? (count_[i] == 1 ? raw[c] : pixel_sum[c])
                                               : pixel_sum[c] + raw[c];
      }
    }
  }
  // Shown once the run is in: the means.
  const float w = 1.0f / static_cast<float>(count_[i]);
  store_rgba(&pixels_[4 * i], Sample{Color(sum[0], sum[1], sum[2]) * w, sum[3] * w});
  store(cost_[i], cost);
  store_count(i, count_[i]);
  if (records == nullptr) return;
  std::array<float, 3> color{};
  for (size_t p = 0; p < kFilmPassCount; ++p) {
    const auto pass = static_cast<FilmPass>(p);
    if (!has_recorded(pass)) continue;
    const int n = channels_[p];
    const int summed = sums_of(pass, n);
    const float scale = first_sample_only(pass) ? 1.0f : w;
    for (int c = 0; c < summed; ++c) raw[c] = sums_[p][summed * i + c] * scale;
    const FilmPass divisor = color_of(pass);
    const bool divide = divisor != FilmPass::kCount && has_pass(divisor);
    if (divide) {
      for (int c = 0; c < 3; ++c) color[c] = sums_[static_cast<size_t>(divisor)][3 * i + c] * w;
    }
    resolve(pass, raw.data(), divide ? color.data() : nullptr, n, sum[3] * w, &shown_[p][n * i]);
  }
}

void Film::store_count(size_t i, uint32_t samples) {
  if (has_pass(FilmPass::kSampleCount)) {
    store(shown_[static_cast<size_t>(FilmPass::kSampleCount)][i], static_cast<float>(samples));
  }
}

float Film::noise(int x, int y) const {
  const size_t i = index(x, y);
  const uint32_t n = count_[i];
  const uint32_t a = class_a_count(n);
  if (a == 0) return std::numeric_limits<float>::quiet_NaN();
  const float w = 1.0f / static_cast<float>(n);
  const float h = 1.0f / static_cast<float>(a);
  const Color mean(sum_[4 * i] * w, sum_[4 * i + 1] * w, sum_[4 * i + 2] * w);
  const Color half(half_[3 * i] * h, half_[3 * i + 1] * h, half_[3 * i + 2] * h);
  return noise_error(mean, half);
}

size_t Film::converge(float threshold, int x, int y, int width, int height) {
  const float limit = kNoiseThresholdScale * threshold;
  // Not converged, inside the area (row by row from its corner). Written as "not below"
  // so that a NaN estimate (fewer than 2 samples, or a NaN sample) stays noisy.
  std::vector<uint8_t> noisy(static_cast<size_t>(width) * height, 0);
  for (int row = 0; row < height; ++row) {
    for (int column = 0; column < width; ++column) {
      // A pixel without samples at a check is one this render does not trace (a probe's
      // skipped tiles: probe_stride): it neither stays active nor keeps its neighbours so.
      if (count_[index(x + column, y + row)] == 0) continue;
      noisy[static_cast<size_t>(row) * width + column] = !(noise(x + column, y + row) < limit);
    }
  }
  size_t active = 0;
  for (int row = 0; row < height; ++row) {
    for (int column = 0; column < width; ++column) {
      bool any = false;
      for (int dy = std::max(0, row - 1); dy <= std::min(height - 1, row + 1); ++dy) {
        for (int dx = std::max(0, column - 1); dx <= std::min(width - 1, column + 1); ++dx) {
          any = any || noisy[static_cast<size_t>(dy) * width + dx] != 0;
        }
      }
      any = any && count_[index(x + column, y + row)] > 0;
      active_[index(x + column, y + row)] = any ? 1 : 0;
      active += any ? 1 : 0;
    }
  }
  return active;
}

void Film::display_image(float* out) const {
  for (size_t i = 0; i < pixels_.size(); ++i) out[i] = displayable(load(pixels_[i]));
}

void Film::display_pass(FilmPass pass, int first, float* out) const {
  const std::vector<float>& values = shown_[static_cast<size_t>(pass)];
  const int n = channels_[static_cast<size_t>(pass)];
  float scale = 1.0f;
  if (pass == FilmPass::kDepth) {
    float farthest = 0.0f;
    for (const float& v : values) {
      const float d = load(v);
      if (d < kNoDepth) farthest = std::max(farthest, d);
    }
    scale = farthest > 0.0f ? 1.0f / farthest : 1.0f;
  }
  const int shown = n == 1 ? 1 : 3;
  for (size_t i = 0; i < cost_.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const float v = load(values[n * i + first + (shown == 1 ? 0 : c)]) * scale;
      out[4 * i + c] = displayable(v);
    }
    out[4 * i + 3] = 1.0f;
  }
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
