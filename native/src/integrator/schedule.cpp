#include "integrator/schedule.h"

namespace whitted {

std::vector<Pass> make_schedule(const Settings& settings) {
  const int n = settings.aa_samples;
  if (!settings.progressive) {
    const int samples = settings.aa_mode == AntiAliasing::kAdaptive ? 4 : n * n;
    return {Pass{Pass::Kind::kPixels, 1, 0, samples}};
  }
  std::vector<Pass> passes;
  for (int size = settings.start_pixel_size; size >= 2; size /= 2) {
    passes.push_back(Pass{Pass::Kind::kPreview, size, 0, 0});
  }
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
