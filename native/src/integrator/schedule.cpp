#include "integrator/schedule.h"

#include <cmath>
#include <utility>

namespace whitted {

int minimum_samples(const Settings& settings) {
  const int grid = settings.aa_samples * settings.aa_samples;
  int least = settings.adaptive_min_samples;
  if (least == 0) {
    // Cycles' automatic minimum (scene/integrator.cpp get_adaptive_sampling); a threshold
    // of 0 never converges, so its minimum does not matter.
    const float t = settings.noise_threshold;
    least = t > 0.0f ? static_cast<int>(std::ceil(16.0f / std::pow(t, 0.3f))) : grid;
  }
  return std::min(std::max(4, least), grid);
}

namespace {

// Noise-driven sampling's passes: rounds whose ends are the checks, a sample per round
// when progressive.
std::vector<Pass> rounds(const Settings& settings, std::vector<Pass> passes) {
  constexpr int kStep = 16;  // Cycles' adaptive_step
  const int grid = settings.aa_samples * settings.aa_samples;
  int check = ((minimum_samples(settings) + 1) | (kStep - 1)) + 1;
  for (int first = 0; first < grid;) {
    const int end = settings.progressive ? first + 1 : std::min(check, grid);
    const bool converge = end == check && end < grid;
    passes.push_back(Pass{Pass::Kind::kRound, 1, first, end, converge});
    if (end == check) check += kStep;
    first = end;
  }
  return passes;
}

}  // namespace

std::vector<Pass> make_schedule(const Settings& settings) {
  const int n = settings.aa_samples;
  if (settings.adaptive_sampling && !settings.progressive) return rounds(settings, {});
  if (!settings.progressive) {
    const int samples = settings.aa_mode == AntiAliasing::kAdaptive ? 4 : n * n;
    return {Pass{Pass::Kind::kPixels, 1, 0, samples}};
  }
  std::vector<Pass> passes;
  for (int size = settings.start_pixel_size; size >= 2; size /= 2) {
    passes.push_back(Pass{Pass::Kind::kPreview, size, 0, 0});
  }
  if (settings.adaptive_sampling) return rounds(settings, std::move(passes));
  for (int k = 0; k < n * n; ++k) passes.push_back(Pass{Pass::Kind::kSample, 1, k, k + 1});
  return passes;
}

std::vector<Tile> make_tiles(const Settings& settings) {
  const int ts = settings.tile_size;
  int xmin = 0, ymin = 0, xmax = 0, ymax = 0;
  settings.border_rect(&xmin, &ymin, &xmax, &ymax);
  // A probe keeps the tile in column c and row r when c + (n + 1) r is a multiple of
  // n^2: one tile in n^2, each row's shifted by n + 1 columns (coprime with n^2), so the
  // kept tiles visit every column and every row, off the frame's axes. The first tile
  // is always kept: a probe is never empty.
  const int64_t n = settings.probe_stride;
  std::vector<Tile> tiles;
  for (int y = ymin, row = 0; y < ymax; y += ts, ++row) {
    for (int x = xmin, column = 0; x < xmax; x += ts, ++column) {
      if ((column + (n + 1) * row) % (n * n) != 0) continue;
      tiles.push_back({x, y, std::min(ts, xmax - x), std::min(ts, ymax - y)});
    }
  }
  return tiles;
}

}  // namespace whitted
