// The pass schedule: which passes a render runs, its tiles, and the preview blocks.
#include "integrator/schedule.h"

#include <gtest/gtest.h>

#include <map>
#include <stdexcept>
#include <tuple>

namespace whitted {
namespace {

TEST(Schedule, WithoutProgressiveOnePassRendersEachPixelWhole) {
  Settings settings;
  settings.aa_samples = 3;
  const std::vector<Pass> passes = make_schedule(settings);
  ASSERT_EQ(passes.size(), 1u);
  EXPECT_EQ(passes[0].kind, Pass::Kind::kPixels);
  EXPECT_EQ(passes[0].samples, 9);
  settings.aa_mode = AntiAliasing::kAdaptive;
  EXPECT_EQ(make_schedule(settings)[0].samples, 4);  // at least the corners
}

TEST(Schedule, ProgressivePreviewsCoarsestFirstThenOnePassPerSample) {
  Settings settings;
  settings.progressive = true;
  settings.start_pixel_size = 8;
  settings.aa_samples = 2;
  const std::vector<Pass> passes = make_schedule(settings);
  ASSERT_EQ(passes.size(), 3u + 4u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(passes[i].kind, Pass::Kind::kPreview);
    EXPECT_EQ(passes[i].pixel_size, 8 >> i);
    EXPECT_EQ(passes[i].samples, 0);
  }
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(passes[3 + k].kind, Pass::Kind::kSample);
    EXPECT_EQ(passes[3 + k].sample, k);
    EXPECT_EQ(passes[3 + k].samples, k + 1);
    EXPECT_EQ(passes[3 + k].pixel_size, 1);
  }
  settings.start_pixel_size = 1;  // no previews
  EXPECT_EQ(make_schedule(settings).size(), 4u);
}

TEST(Schedule, StartPixelSizeIsAPowerOfTwoUpTo64) {
  Settings settings;
  for (int size : {1, 2, 64}) {
    settings.start_pixel_size = size;
    EXPECT_NO_THROW(settings.validate()) << size;
  }
  for (int size : {0, 3, 12, 128}) {
    settings.start_pixel_size = size;
    EXPECT_THROW(settings.validate(), std::invalid_argument) << size;
  }
}

TEST(Schedule, TilesCoverTheBorderOnce) {
  Settings settings;
  settings.width = 70;
  settings.height = 33;
  settings.tile_size = 16;
  settings.border[0] = 5;
  settings.border[1] = 3;
  settings.border[2] = 61;
  settings.border[3] = 30;
  std::map<std::pair<int, int>, int> hits;
  for (const Tile& t : make_tiles(settings)) {
    for (int y = t.y; y < t.y + t.height; ++y) {
      for (int x = t.x; x < t.x + t.width; ++x) hits[{x, y}] += 1;
    }
  }
  EXPECT_EQ(hits.size(), 56u * 27u);
  for (const auto& [pixel, n] : hits) {
    EXPECT_EQ(n, 1);
    EXPECT_TRUE(pixel.first >= 5 && pixel.first < 61 && pixel.second >= 3 && pixel.second < 30);
  }
}

// A probe keeps one tile in n^2, the first among them, and visits every row and every
// column of tiles (not a grid aligned with the frame's axes).
TEST(Schedule, AProbeKeepsOneTileInStrideSquaredSpreadOverRowsAndColumns) {
  Settings settings;
  settings.width = 320;
  settings.height = 240;
  settings.tile_size = 8;  // 40 x 30 tiles
  settings.probe_stride = 4;
  EXPECT_NO_THROW(settings.validate());
  const std::vector<Tile> tiles = make_tiles(settings);
  EXPECT_NEAR(static_cast<double>(tiles.size()), 40.0 * 30.0 / 16.0, 2.0);
  EXPECT_EQ(tiles.front().x, 0);
  EXPECT_EQ(tiles.front().y, 0);
  std::map<int, int> columns, rows;
  for (const Tile& t : tiles) {
    columns[t.x / 8] += 1;
    rows[t.y / 8] += 1;
  }
  EXPECT_EQ(columns.size(), 40u);
  EXPECT_EQ(rows.size(), 30u);
  settings.probe_stride = 0;
  EXPECT_THROW(settings.validate(), std::invalid_argument);
  // A border smaller than the lattice still has its first tile.
  settings.probe_stride = 8;
  settings.border[0] = 100;
  settings.border[1] = 100;
  settings.border[2] = 104;
  settings.border[3] = 104;
  ASSERT_EQ(make_tiles(settings).size(), 1u);
}

// Whatever the tiling, every pixel of the border is covered once per preview pass, by
// the same block (clipped to the border), so previews do not depend on tiles.
TEST(Schedule, PreviewBlocksDoNotDependOnTheTiling) {
  Settings settings;
  settings.width = 45;
  settings.height = 29;
  settings.border[0] = 3;
  settings.border[1] = 1;
  settings.border[2] = 44;
  settings.border[3] = 29;
  const Tile area{3, 1, 41, 28};
  for (int size : {2, 8, 64}) {
    std::map<std::pair<int, int>, std::tuple<int, int, int, int>> reference;
    for (int tile_size : {1, 7, 16, 64}) {
      settings.tile_size = tile_size;
      std::map<std::pair<int, int>, std::tuple<int, int, int, int>> block_of;
      for (const Tile& tile : make_tiles(settings)) {
        for_each_block(tile, size, area, [&](const Tile& block, const Tile& inside) {
          EXPECT_GE(inside.x, tile.x);
          EXPECT_LE(inside.x + inside.width, tile.x + tile.width);
          EXPECT_GE(block.x, area.x);
          EXPECT_LE(block.x + block.width, area.x + area.width);
          EXPECT_LE(block.width, size);
          for (int y = inside.y; y < inside.y + inside.height; ++y) {
            for (int x = inside.x; x < inside.x + inside.width; ++x) {
              const auto [it, fresh] =
                  block_of.insert({{x, y}, {block.x, block.y, block.width, block.height}});
              EXPECT_TRUE(fresh) << "pixel " << x << "," << y << " covered twice";
            }
          }
          return true;
        });
      }
      EXPECT_EQ(block_of.size(), 41u * 28u);
      if (reference.empty()) reference = block_of;
      EXPECT_EQ(block_of, reference) << "block size " << size << ", tile " << tile_size;
    }
  }
}

}  // namespace
}  // namespace whitted
