// The film's pixel filter (integrator/pixel_filter.h): samples placed by the filter's own
// density, and an edge rendered through it is the step convolved with the filter.
#include "integrator/pixel_filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "integrator/render.h"
#include "scene_builders.h"

namespace whitted {
namespace {

using testing::add_object;
using testing::emitter;
using testing::looking_down;
using testing::quad;

// Cycles' filters as its scene/film.cpp writes them (its width W being 3 w for the
// Gaussian and 2 w for Blackman-Harris), evaluated here from the formulas, not through
// PixelFilter, to check it against.
double cycles_filter(PixelFilterType type, double width, double v) {
  constexpr double kTwoPi = 6.283185307179586;
  switch (type) {
    case PixelFilterType::kBox:  // 1 pixel wide whatever the width (Cycles' sync)
      return std::fabs(v) <= 0.5 ? 1.0 : 0.0;
    case PixelFilterType::kGaussian: {
      const double w = 3.0 * width;
      if (std::fabs(v) > 0.5 * w) return 0.0;
      const double s = v * 6.0 / w;
      return std::exp(-2.0 * s * s);
    }
    case PixelFilterType::kBlackmanHarris: {
      const double w = 2.0 * width;
      if (std::fabs(v) > 0.5 * w) return 0.0;
      const double p = kTwoPi * (v / w + 0.5);
      return 0.35875 - 0.48829 * std::cos(p) + 0.14128 * std::cos(2.0 * p) -
             0.01168 * std::cos(3.0 * p);
    }
  }
  return 0.0;
}

// The share of the filter's mass at offsets of at least `from` (midpoint rule, fine).
double mass_beyond(PixelFilterType type, double width, double from) {
  constexpr int kSteps = 200000;
  const double r = 2.0 * width;  // beyond every support
  const double step = 2.0 * r / kSteps;
  double all = 0.0;
  double beyond = 0.0;
  for (int i = 0; i < kSteps; ++i) {
    const double v = -r + (i + 0.5) * step;
    const double f = cycles_filter(type, width, v);
    all += f;
    if (v >= from) beyond += f;
  }
  return beyond / all;
}

struct Case {
  PixelFilterType type;
  float width;
};

class PixelFilterCases : public ::testing::TestWithParam<Case> {};

TEST_P(PixelFilterCases, PlacesSamplesByTheFiltersDensity) {
  const Case c = GetParam();
  const PixelFilter filter(c.type, c.width);
  EXPECT_EQ(filter.position(0.5f), 0.5f);  // the centre, exactly
  // The share of samples (evenly spaced u) below each offset is the filter's mass there.
  constexpr int kSamples = 100000;
  std::vector<float> positions(kSamples);
  float last = -1e9f;
  for (int i = 0; i < kSamples; ++i) {
    positions[i] = filter.position((static_cast<float>(i) + 0.5f) / kSamples);
    EXPECT_GE(positions[i], last);  // monotone: strata stay strata
    last = positions[i];
    EXPECT_LE(std::fabs(positions[i] - 0.5f), filter.radius() + 1e-6f);
  }
  for (double offset : {-1.2, -0.7, -0.3, -0.1, 0.05, 0.25, 0.6, 1.1}) {
    int below = 0;
    for (float p : positions) below += p - 0.5f < offset ? 1 : 0;
    EXPECT_NEAR(static_cast<double>(below) / kSamples, 1.0 - mass_beyond(c.type, c.width, offset),
                1e-3)
        << "at offset " << offset;
  }
  // weight() is the formula, peak 1.
  for (double v : {0.0, 0.2, 0.45, 0.9, 1.4}) {
    EXPECT_NEAR(filter.weight(static_cast<float>(v)), cycles_filter(c.type, c.width, v), 1e-5);
  }
}

// A bright half plane x >= edge on black, seen square-on (40 pixels over [-1, 1], so
// pixel coordinates are linear in x): pixel x's value is the filter's mass at offsets
// beyond the edge's distance from the pixel's centre.
TEST_P(PixelFilterCases, AnEdgeIsTheStepConvolvedWithTheFilter) {
  const Case c = GetParam();
  const float edge = 0.0125f;  // pixel coordinate (edge + 1) / 0.05 = 20.25
  Scene scene;
  add_object(&scene, "half", quad(edge, 10.0f, -10.0f, 10.0f, 0.0f), emitter(Color(1.0f)));
  scene.set_background(Color(0.0f));
  scene.camera = looking_down(Vec3(0.0f, 0.0f, 1.0f), 1.0f);
  Settings settings = testing::small_render(40, 4, 32, 2, 8);
  settings.aa_mode = AntiAliasing::kJittered;
  settings.pixel_filter = c.type;
  settings.filter_width = c.width;
  const std::vector<float> pixels = testing::render_pixels(scene, settings);
  const double edge_pixel = (edge + 1.0) / 0.05;
  for (int x = 14; x < 27; ++x) {
    const double expected = mass_beyond(c.type, c.width, edge_pixel - (x + 0.5));
    EXPECT_NEAR(pixels[(1 * 40 + x) * 4], expected, 0.01) << "pixel " << x;
  }
}

INSTANTIATE_TEST_SUITE_P(Filters, PixelFilterCases,
                         ::testing::Values(Case{PixelFilterType::kBox, 1.0f},
                                           Case{PixelFilterType::kBox, 2.0f},
                                           Case{PixelFilterType::kGaussian, 1.5f},
                                           Case{PixelFilterType::kBlackmanHarris, 1.5f},
                                           Case{PixelFilterType::kBlackmanHarris, 0.7f}));

TEST(PixelFilter, TheBoxIsThePixelsSquareBitForBitWhateverTheWidth) {
  for (float width : {1.0f, 2.0f, 0.3f}) {
    const PixelFilter box(PixelFilterType::kBox, width);
    EXPECT_EQ(box.radius(), 0.5f);
    for (float u : {0.0f, 0.1f, 0.3333333f, 0.5f, 0.77f, 0.99999994f}) {
      EXPECT_EQ(box.position(u), u);
    }
  }
}

TEST(PixelFilter, AdaptiveAntiAliasingSamplesThePixelsSquare) {
  Settings settings;
  settings.aa_mode = AntiAliasing::kAdaptive;
  settings.pixel_filter = PixelFilterType::kBlackmanHarris;
  settings.filter_width = 1.5f;
  const PixelFilter filter(settings);
  EXPECT_EQ(filter.position(0.1f), 0.1f);
  EXPECT_EQ(filter.radius(), 0.5f);
}

}  // namespace
}  // namespace whitted
