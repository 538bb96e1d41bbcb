// Owen-scrambled Sobol points (core/sobol.h): nets in every power-of-two prefix, the index
// shuffle's blocks, decorrelated dimensions, their error on a smooth integrand, the
// class-A half; and a soft shadow rendered with them against random draws.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <vector>

#include "core/sobol.h"
#include "scene_builders.h"

namespace whitted {
namespace {

using testing::add_object;
using testing::looking_down;
using testing::quad;
using testing::render_pixels;
using testing::small_render;

// Whether points 0 .. 2^m - 1 of sequence `seed` put one point in each elementary interval
// [a / 2^i, (a + 1) / 2^i) x [b / 2^j, (b + 1) / 2^j), i + j = m: a (0, m, 2)-net.
bool is_net(uint32_t seed, int m) {
  const uint32_t n = 1u << m;
  for (int i = 0; i <= m; ++i) {
    std::set<std::pair<uint32_t, uint32_t>> cells;
    for (uint32_t k = 0; k < n; ++k) {
      const glm::vec2 p = sobol_point(k, seed);
      cells.insert({static_cast<uint32_t>(std::ldexp(p.x, i)),
                    static_cast<uint32_t>(std::ldexp(p.y, m - i))});
    }
    if (cells.size() != n) return false;
  }
  return true;
}

TEST(Sobol, EveryPowerOfTwoPrefixIsANet) {
  for (uint32_t seed : {0u, 1u, 0x9e3779b9u, 12345u, hash3(3, 4, 5)}) {
    for (int m = 2; m <= 10; ++m) EXPECT_TRUE(is_net(seed, m)) << seed << " 2^" << m;
  }
}

TEST(Sobol, TheIndexShuffleMapsAlignedBlocksOntoAlignedBlocks) {
  for (uint32_t seed : {7u, 0xdeadbeefu}) {
    for (int k : {1, 2, 4, 8}) {
      const uint32_t size = 1u << k;
      for (uint32_t block : {0u, 1u, 37u}) {
        std::set<uint32_t> out;
        std::set<uint32_t> blocks;
        for (uint32_t j = 0; j < size; ++j) {
          const uint32_t s = owen_scramble(block * size + j, seed);
          out.insert(s);
          blocks.insert(s >> k);
        }
        EXPECT_EQ(out.size(), size);   // a bijection
        EXPECT_EQ(blocks.size(), 1u);  // onto one aligned block
      }
    }
  }
}

// Two dimensions of one pixel (two seeds) are not paired alike: were their indices shuffled
// the same way, which half of [0, 1) a point's x falls in would, for every point, agree
// between the two, or disagree for every point (the scrambles differ by a constant flip).
TEST(Sobol, TwoDimensionsOfAPixelAreNotPairedAlike) {
  int fixed = 0;
  for (uint32_t pixel = 0; pixel < 50; ++pixel) {
    const uint32_t a = hash3(pixel, 0, 0xf11du);
    const uint32_t b = hash3(pixel, 0, 0x1e45u);
    std::set<bool> agreements;
    for (uint32_t k = 0; k < 16; ++k) {
      agreements.insert((sobol_point(k, a).x < 0.5f) == (sobol_point(k, b).x < 0.5f));
    }
    if (agreements.size() == 1) ++fixed;
  }
  EXPECT_LE(fixed, 5);
}

// A smooth integrand's error at 256 points, RMS over 200 sequences, against 256
// independent uniform points' (a hash).
TEST(Sobol, ASmoothIntegrandErrsFarLessThanRandomPoints) {
  const auto f = [](glm::vec2 p) { return std::exp(p.x) * std::cos(p.y); };
  const double exact = (std::exp(1.0) - 1.0) * std::sin(1.0);
  double sobol = 0.0;
  double random = 0.0;
  constexpr int kSeeds = 200;
  constexpr uint32_t kPoints = 256;
  for (uint32_t seed = 0; seed < kSeeds; ++seed) {
    double s = 0.0;
    double r = 0.0;
    for (uint32_t k = 0; k < kPoints; ++k) {
      s += f(sobol_point(k, hash3(seed, 1, 2)));
      const uint32_t h = hash3(seed, k, 0x7a7du);
      r += f({unit_float(h), unit_float(hash3(h, 1, 2))});
    }
    sobol += std::pow(s / kPoints - exact, 2.0);
    random += std::pow(r / kPoints - exact, 2.0);
  }
  EXPECT_LT(std::sqrt(sobol / kSeeds), 0.2 * std::sqrt(random / kSeeds));
}

TEST(Sobol, ValueIsThePointsFirstCoordinate) {
  for (uint32_t k = 0; k < 64; ++k) EXPECT_EQ(sobol_value(k, 99u), sobol_point(k, 99u).x);
}

// Class A (Cycles' split for the noise estimate) is half of every aligned block of 4, and
// the class-A half of a power-of-two prefix of a pixel's film points is spread over the
// pixel: each half of it, along each axis, holds a quarter of the prefix.
TEST(Sobol, ClassAIsAWellSpreadHalf) {
  uint32_t counted = 0;
  for (uint32_t n = 0; n < 1000; ++n) {
    EXPECT_EQ(class_a_count(n), counted) << n;
    counted += class_a(n) ? 1 : 0;
  }
  for (uint32_t seed : {1u, 2u, hash3(10, 20, 0xf11du)}) {
    for (uint32_t n = 4; n <= 1024; n *= 2) {
      EXPECT_EQ(class_a_count(n), n / 2);
      uint32_t left = 0;
      uint32_t bottom = 0;
      for (uint32_t k = 0; k < n; ++k) {
        if (!class_a(k)) continue;
        const glm::vec2 p = sobol_point(k, seed);
        left += p.x < 0.5f ? 1 : 0;
        bottom += p.y < 0.5f ? 1 : 0;
      }
      EXPECT_EQ(left, n / 4) << seed << " " << n;
      EXPECT_EQ(bottom, n / 4) << seed << " " << n;
    }
  }
}

// A floor in the soft shadow of a blocker under a square lamp of one feeler, rendered with
// Monte Carlo camera samples: at 4 x 4 samples the Sobol draws (film point and feeler,
// each stratified over the pixel's samples) err against a 32 x 32-sample render far less
// than independent draws would. Independent draws' error at 16 samples is the 1-sample
// render's over 4 (one Sobol point alone is a uniform random one).
TEST(SobolRender, SoftShadowErrsLessThanRandomDrawsAtEqualSamples) {
  Scene scene;
  Material white;
  white.ambient = 0.0f;
  add_object(&scene, "floor", quad(-20, 20, -20, 20, 0), white);
  add_object(&scene, "blocker", quad(-0.5f, 0.5f, -0.5f, 0.5f, 1.0f), white);
  Light lamp;
  lamp.type = LightType::kArea;
  lamp.color = Color(20.0f);
  lamp.position = Vec3(0.0f, 0.0f, 2.0f);
  lamp.size[0] = lamp.size[1] = 1.5f;
  lamp.samples = 1;
  scene.set_light("lamp", lamp);
  scene.camera = looking_down(Vec3(0.0f, 0.0f, 5.0f), 0.5f);
  const auto rendered = [&](int n) {
    Settings settings = small_render(24, 24, n, 2, 8);
    settings.aa_mode = AntiAliasing::kJittered;
    return render_pixels(scene, settings);
  };
  const std::vector<float> reference = rendered(32);
  const auto rmse = [&](const std::vector<float>& pixels) {
    double sum = 0.0;
    for (size_t i = 0; i < pixels.size(); ++i) {
      if (i % 4 == 3) continue;  // alpha
      sum += std::pow(static_cast<double>(pixels[i]) - reference[i], 2.0);
    }
    return std::sqrt(sum / (0.75 * static_cast<double>(pixels.size())));
  };
  const double one = rmse(rendered(1));
  const double sixteen = rmse(rendered(4));
  EXPECT_GT(one, 0.01);  // the penumbra fills the view: a noisy single sample
  EXPECT_LT(sixteen, 0.5 * one / 4.0) << one << " " << sixteen;
}

}  // namespace
}  // namespace whitted
