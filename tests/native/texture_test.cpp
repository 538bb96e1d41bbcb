// Textures: bilinear lookup, extension modes, closest, and Blender's checker.
#include "scene/texture.h"

#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <stdexcept>
#include <utility>
#include <vector>

namespace whitted {
namespace {

// A 2x2 image whose red channel numbers the texels 0..3 (rows bottom to top).
Texture two_by_two(Extension extension, Interpolation interpolation) {
  const float rgba[] = {0, 0, 0, 1, 1, 0, 0, 1, 2, 0, 0, 1, 3, 0, 0, 0.5f};
  return Texture{TexCoord::kUV, make_image_texture(rgba, 2, 2, extension, interpolation)};
}

float red_at(const Texture& t, float u, float v) {
  TexturePoint p;
  p.uv = {u, v};
  return t.evaluate(p).x;
}

TEST(Texture, TexelCentresReturnTexelsAndBilinearBlendsBetween) {
  const Texture t = two_by_two(Extension::kExtend, Interpolation::kLinear);
  EXPECT_FLOAT_EQ(red_at(t, 0.25f, 0.25f), 0.0f);
  EXPECT_FLOAT_EQ(red_at(t, 0.75f, 0.25f), 1.0f);
  EXPECT_FLOAT_EQ(red_at(t, 0.25f, 0.75f), 2.0f);  // second row is the top one
  EXPECT_FLOAT_EQ(red_at(t, 0.5f, 0.5f), 1.5f);    // the mean of all four
  EXPECT_FLOAT_EQ(red_at(t, 0.5f, 0.25f), 0.5f);
}

TEST(Texture, ExtensionModes) {
  const Texture repeat = two_by_two(Extension::kRepeat, Interpolation::kClosest);
  EXPECT_FLOAT_EQ(red_at(repeat, 1.25f, 0.25f), 0.0f);
  EXPECT_FLOAT_EQ(red_at(repeat, -0.25f, 0.25f), 1.0f);
  const Texture extend = two_by_two(Extension::kExtend, Interpolation::kClosest);
  EXPECT_FLOAT_EQ(red_at(extend, 5.0f, 0.25f), 1.0f);
  const Texture clip = two_by_two(Extension::kClip, Interpolation::kLinear);
  TexturePoint outside;
  outside.uv = {1.5f, 0.5f};
  EXPECT_EQ(clip.evaluate(outside), glm::vec4(0.0f));
  // Repeat blends across the seam: between texel 1 and texel 0 of the next copy.
  const Texture wrap = two_by_two(Extension::kRepeat, Interpolation::kLinear);
  EXPECT_FLOAT_EQ(red_at(wrap, 1.0f, 0.25f), 0.5f);
}

TEST(Texture, NonFiniteInputStaysFinite) {
  const float rgba[] = {std::nanf(""), 1, 1, 1};
  const Texture t{TexCoord::kUV,
                  make_image_texture(rgba, 1, 1, Extension::kRepeat, Interpolation::kLinear)};
  EXPECT_FLOAT_EQ(red_at(t, 0.5f, 0.5f), 0.0f);
  EXPECT_FLOAT_EQ(red_at(t, std::nanf(""), 0.5f), 0.0f);
  EXPECT_FLOAT_EQ(red_at(t, 1e30f, 0.5f), 0.0f);
  EXPECT_THROW(make_image_texture(rgba, 0, 1, Extension::kRepeat, Interpolation::kLinear),
               std::invalid_argument);
}

// Cycles' tile of a uv: 1001 + trunc(u) + 10 trunc(v), uv made relative to the tile.
TEST(Texture, UdimPointFindsTheTileAndItsFraction) {
  const auto at = [](float u, float v) { return udim_point({u, v}); };
  EXPECT_EQ(at(0.25f, 0.5f).tile, 1001);
  EXPECT_EQ(at(0.25f, 0.5f).uv, glm::vec2(0.25f, 0.5f));
  EXPECT_EQ(at(1.0f, 0.0f).tile, 1002);  // a border belongs to the tile it starts
  EXPECT_EQ(at(1.0f, 0.0f).uv, glm::vec2(0.0f, 0.0f));
  EXPECT_EQ(at(2.75f, 1.25f).tile, 1013);
  EXPECT_EQ(at(2.75f, 1.25f).uv, glm::vec2(0.75f, 0.25f));
  EXPECT_EQ(at(9.5f, 99.5f).tile, 2000);  // the last tile Blender makes
  // Truncation, as Cycles: just below 0 is still the first column, left negative.
  EXPECT_EQ(at(-0.25f, 0.5f).tile, 1001);
  EXPECT_EQ(at(-0.25f, 0.5f).uv, glm::vec2(-0.25f, 0.5f));
  EXPECT_EQ(at(0.5f, -0.5f).tile, 1001);
  // No tile: beyond the tenth column, below -1, past row 99, not a number.
  EXPECT_EQ(at(10.0f, 0.5f).tile, 0);
  EXPECT_EQ(at(-1.0f, 0.5f).tile, 0);
  EXPECT_EQ(at(0.5f, 100.0f).tile, 0);
  EXPECT_EQ(at(std::nanf(""), 0.5f).tile, 0);
  EXPECT_EQ(at(0.5f, 1e30f).tile, 0);
}

// A UDIM image of tiles 1001 (red 1), 1002 (red 2) and 1011 (red 3), each 1 x 1.
Texture three_tiles(Extension extension) {
  std::vector<ImageTile> tiles;
  const int numbers[] = {1011, 1001, 1002};  // given out of order: sorted when made
  for (const int number : numbers) {
    const float red = number == 1001 ? 1.0f : number == 1002 ? 2.0f : 3.0f;
    const float rgba[] = {red, 0, 0, 1};
    tiles.push_back(make_image_tile(number, rgba, 1, 1));
  }
  return Texture{TexCoord::kUV,
                 make_udim_texture(std::move(tiles), extension, Interpolation::kLinear)};
}

TEST(Texture, UdimImageSamplesEachTileAndMagentaWhereItHasNone) {
  const Texture t = three_tiles(Extension::kRepeat);
  EXPECT_FLOAT_EQ(red_at(t, 0.5f, 0.5f), 1.0f);
  EXPECT_FLOAT_EQ(red_at(t, 1.5f, 0.5f), 2.0f);
  EXPECT_FLOAT_EQ(red_at(t, 0.5f, 1.5f), 3.0f);
  EXPECT_FLOAT_EQ(red_at(t, -0.5f, 0.5f), 1.0f);  // the first column, repeated
  TexturePoint missing;
  missing.uv = {2.5f, 0.5f};  // tile 1003, which the image does not have
  EXPECT_EQ(t.evaluate(missing), kMissingImage);
  missing.uv = {12.0f, 0.5f};
  EXPECT_EQ(t.evaluate(missing), kMissingImage);
  // Box projection and environments show the first tile (by number) anywhere.
  const auto& image = std::get<ImageTexture>(t.source);
  EXPECT_FLOAT_EQ(sample_first_tile(image, {2.5f, 0.5f}).x, 1.0f);
  // Clip applies within the tile: the first column's negative u is outside it.
  const Texture clip = three_tiles(Extension::kClip);
  EXPECT_EQ(clip.evaluate(TexturePoint{{-0.5f, 0.5f}, {}, {}}), glm::vec4(0.0f));
  EXPECT_FLOAT_EQ(red_at(clip, 1.5f, 0.5f), 2.0f);
}

TEST(Texture, UdimTileNumbersAreChecked) {
  const float rgba[] = {1, 1, 1, 1};
  const auto tiles = [&](std::initializer_list<int> numbers) {
    std::vector<ImageTile> made;
    for (const int n : numbers) made.push_back(make_image_tile(n, rgba, 1, 1));
    return made;
  };
  const auto make = [](std::vector<ImageTile> t) {
    return make_udim_texture(std::move(t), Extension::kRepeat, Interpolation::kLinear);
  };
  EXPECT_THROW(make(tiles({})), std::invalid_argument);
  EXPECT_THROW(make(tiles({1000})), std::invalid_argument);
  EXPECT_THROW(make(tiles({2001})), std::invalid_argument);
  EXPECT_THROW(make(tiles({1001, 1002, 1001})), std::invalid_argument);
  EXPECT_NO_THROW(make(tiles({1001, 2000})));
}

// Blender's checker: cell (0,0,0) takes color1, its neighbours color2, with the z layer
// flipping the pattern (Cycles svm_checker).
TEST(Texture, CheckerMatchesBlendersPattern) {
  const Texture t{TexCoord::kGenerated, CheckerTexture{Color(1.0f), Color(0.0f), 2.0f}};
  const auto at = [&](float x, float y, float z) {
    TexturePoint p;
    p.generated = {x, y, z};
    return t.evaluate(p).x;
  };
  // Scale 2: cells are 0.5 wide. z in [0, 0.5) is cell 0 (even).
  EXPECT_EQ(at(0.25f, 0.25f, 0.25f), 0.0f);  // xi == yi, zi even: (true == false) -> color2
  EXPECT_EQ(at(0.75f, 0.25f, 0.25f), 1.0f);
  EXPECT_EQ(at(0.25f, 0.25f, 0.75f), 1.0f);  // odd z layer flips it
  EXPECT_EQ(at(-0.25f, 0.25f, 0.25f), 1.0f);
}

}  // namespace
}  // namespace whitted
