// Textures: bilinear lookup, extension modes, closest, and Blender's checker.
#include "scene/texture.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

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
