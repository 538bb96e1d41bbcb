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
  std::vector<Tile> tiles;
  for (int y = ymin; y < ymax; y += ts) {
    for (int x = xmin; x < xmax; x += ts) {
      tiles.push_back({x, y, std::min(ts, xmax - x), std::min(ts, ymax - y)});
    }
  }
  return tiles;
}

}  // namespace whitted
