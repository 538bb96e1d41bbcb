// The pass schedule: what each pass of a render traces, over which pixels, in which tiles.
#pragma once

#include <algorithm>
#include <vector>

#include "integrator/settings.h"

namespace whitted {

// A rectangle of pixels; y counts from the bottom row.
struct Tile {
  int x, y, width, height;
};

struct Pass {
  enum class Kind {
    kPixels,   // each pixel whole: every sample at once, by the anti-aliasing mode
    kPreview,  // one camera ray at the centre of each block, shown over the block
    kSample,   // one sample of the grid added to every pixel
    // Noise-driven sampling: samples sample .. samples - 1 of each pixel (by index: every
    // power-of-two prefix stratified, sampler.h) added to every pixel still active
    // (Film::active)
    kRound,
  };
  Kind kind;
  int pixel_size;  // kPreview: the block's side; otherwise 1
  // kSample: which grid sample, row by row (i = sample % n, j = sample / n); kRound: the
  // round's first sample in the pixels' order
  int sample;
  // Camera samples of its own each pixel has once the pass is done (a preview is not
  // the pixel's own); adaptive: at least its four corners; kRound: at most, a pixel
  // stopped before has fewer.
  int samples;
  // kRound: the film's noise check (Film::converge) follows the pass.
  bool converge = false;
};

// Samples a pixel takes before noise-driven sampling first checks it: adaptive_min_samples,
// or 0's Cycles' max(4, ceil(16 / threshold^0.3)); at least 4, at most the grid.
int minimum_samples(const Settings& settings);

// The passes in order: one kPixels pass; or, progressive, the previews coarsest first
// (start_pixel_size down to 2), then one kSample pass per grid sample. Noise-driven
// (Settings::adaptive_sampling): kRound passes in place of kPixels and kSample, the
// checks as Cycles' (every 16 samples once past the minimum: after sample counts
// ((min + 1) | 15) + 1 + 16 i, below the grid): F12 one round per check, progressive a
// round per sample.
std::vector<Pass> make_schedule(const Settings& settings);

// The border rectangle cut into tiles of tile_size, row by row from the bottom. Every
// pass traces the same tiles, so a pixel belongs to one tile, and one worker, per pass.
std::vector<Tile> make_tiles(const Settings& settings);

// The preview blocks of side `size` that meet `tile`: aligned to the image's corner, not
// to the tile, so a preview does not depend on the tiling (a block that straddles tiles
// is traced by each, identically). Each block is clipped to `area` (the border); `visit`
// gets it and the part of it inside the tile, and returns false to stop.
template <typename Visit>
void for_each_block(const Tile& tile, int size, const Tile& area, Visit visit) {
  const int x_first = tile.x / size * size;
  const int y_first = tile.y / size * size;
  for (int y = y_first; y < tile.y + tile.height; y += size) {
    for (int x = x_first; x < tile.x + tile.width; x += size) {
      const int x0 = std::max(x, area.x);
      const int y0 = std::max(y, area.y);
      const int x1 = std::min(x + size, area.x + area.width);
      const int y1 = std::min(y + size, area.y + area.height);
      const int in_x0 = std::max(x0, tile.x);
      const int in_y0 = std::max(y0, tile.y);
      const int in_x1 = std::min(x1, tile.x + tile.width);
      const int in_y1 = std::min(y1, tile.y + tile.height);
      if (!visit(Tile{x0, y0, x1 - x0, y1 - y0},
                 Tile{in_x0, in_y0, in_x1 - in_x0, in_y1 - in_y0})) {
        return;
      }
    }
  }
}

}  // namespace whitted
