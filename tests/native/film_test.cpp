// The film: the mean of a pixel's samples, previews, and the display copies.
#include "integrator/film.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace whitted {
namespace {

TEST(Film, APixelShowsItsPreviewUntilItsFirstSampleThenTheMean) {
  Film film(3, 2, true);
  film.set(2, 1, Sample{Color(9.0f), 1.0f}, 7.0f, 1);
  const size_t i = 1 * 3 + 2;
  EXPECT_EQ(film.pixels()[4 * i], 9.0f);
  EXPECT_EQ(film.cost()[i], 7.0f);
  film.add(2, 1, Sample{Color(1.0f, 2.0f, 3.0f), 1.0f}, 2.0f);
  EXPECT_EQ(film.pixels()[4 * i], 1.0f);  // the preview is gone
  EXPECT_EQ(film.cost()[i], 2.0f);        // and so are its rays
  film.add(2, 1, Sample{Color(3.0f, 2.0f, 1.0f), 0.0f}, 3.0f);
  EXPECT_EQ(film.pixels()[4 * i + 0], 2.0f);
  EXPECT_EQ(film.pixels()[4 * i + 2], 2.0f);
  EXPECT_EQ(film.pixels()[4 * i + 3], 0.5f);
  EXPECT_EQ(film.cost()[i], 5.0f);
  EXPECT_EQ(film.pixels()[0], 0.0f);  // untouched pixels stay 0
}

// Sample by sample, the film sums in the order and with the weight a whole pixel's mean
// uses (CameraSampler::pixel), so the last value is that mean to the bit.
TEST(Film, TheMeanOfSamplesAddedOneByOneIsTheWholePixelsMeanToTheBit) {
  const float values[] = {0.1f, 0.7f, 1e-3f, 0.33f, 2.9f, 0.05f, 0.6f, 0.123f, 0.9f};
  Film film(1, 1, true);
  Sample sum{Color(0.0f), 0.0f};
  for (float v : values) {
    const Sample s{Color(v, v * 0.5f, v * 3.0f), v > 0.5f ? 1.0f : 0.25f};
    film.add(0, 0, s, 1.0f);
    sum.radiance += s.radiance;
    sum.alpha += s.alpha;
  }
  const float w = 1.0f / 9.0f;
  EXPECT_EQ(film.pixels()[0], sum.radiance.x * w);
  EXPECT_EQ(film.pixels()[1], sum.radiance.y * w);
  EXPECT_EQ(film.pixels()[2], sum.radiance.z * w);
  EXPECT_EQ(film.pixels()[3], sum.alpha * w);
}

// A round's samples added as one run: the sums, half sums, counts, costs and passes of
// adding them one at a time, to the bit.
TEST(Film, ARunOfSamplesIsAddingThemOneByOne) {
  const uint32_t passes = pass_bit(FilmPass::kDepth) | pass_bit(FilmPass::kDiffuseDirect) |
                          pass_bit(FilmPass::kDiffuseColor) | pass_bit(FilmPass::kSampleCount);
  Film one(2, 1, true, passes, 1, true);
  Film run(2, 1, true, passes, 1, true);
  std::vector<Sample> samples;
  std::vector<float> costs;
  std::vector<SampleRecord> records;
  for (int k = 0; k < 7; ++k) {
    const float v = 0.1f + 0.37f * static_cast<float>(k % 3);
    samples.push_back(Sample{Color(v, 2.0f * v, v * v), k == 2 ? 0.5f : 1.0f});
    costs.push_back(static_cast<float>(3 + k));
    SampleRecord r;
    r.depth = 4.0f + static_cast<float>(k);
    r.diffuse_direct = Color(v);
    r.diffuse_color = Color(0.5f + v);
    records.push_back(r);
  }
  one.set(1, 0, Sample{Color(9.0f), 1.0f}, 11.0f, 0);  // a preview the run replaces
  run.set(1, 0, Sample{Color(9.0f), 1.0f}, 11.0f, 0);
  for (int k = 0; k < 7; ++k) one.add(1, 0, samples[k], costs[k], &records[k]);
  run.add(1, 0, samples.data(), costs.data(), 3, records.data());
  run.add(1, 0, samples.data() + 3, costs.data() + 3, 4, records.data() + 3);
  EXPECT_EQ(run.pixels(), one.pixels());
  EXPECT_EQ(run.cost(), one.cost());
  EXPECT_EQ(run.samples(1, 0), 7u);
  EXPECT_EQ(run.noise(1, 0), one.noise(1, 0));
  for (FilmPass pass : {FilmPass::kDepth, FilmPass::kDiffuseDirect, FilmPass::kDiffuseColor,
                        FilmPass::kSampleCount}) {
    EXPECT_EQ(run.pass(pass), one.pass(pass)) << static_cast<int>(pass);
  }
  EXPECT_EQ(run.pass(FilmPass::kSampleCount)[1], 7.0f);
  EXPECT_EQ(run.pass(FilmPass::kDepth)[1], 4.0f);  // the first sample's
}

TEST(Film, TheDisplayImageFitsAHalfFloatTexture) {
  Film film(4, 1, false);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  film.set(0, 0, Sample{Color(nan, 1e6f, -1.0f), 0.5f}, 0.0f, 1);
  film.set(1, 0, Sample{Color(inf, 65000.0f, 0.25f), 1.0f}, 0.0f, 1);
  float out[16];
  film.display_image(out);
  EXPECT_EQ(out[0], 0.0f);
  EXPECT_EQ(out[1], 65000.0f);
  EXPECT_EQ(out[2], 0.0f);
  EXPECT_EQ(out[3], 0.5f);
  EXPECT_EQ(out[4], 65000.0f);
  EXPECT_EQ(out[5], 65000.0f);
  EXPECT_EQ(out[6], 0.25f);
  EXPECT_EQ(out[8], 0.0f);  // not rendered yet
}

TEST(Film, TheCostHeatMapRisesFromDarkBlueToYellow) {
  Film film(3, 1, false);
  film.set(0, 0, Sample{Color(0.0f), 1.0f}, 0.0f, 1);
  film.set(1, 0, Sample{Color(0.0f), 1.0f}, 5.0f, 1);
  film.set(2, 0, Sample{Color(0.0f), 1.0f}, 10.0f, 1);
  float out[12];
  film.display_cost(out);
  const auto luminance = [&](int p) {
    return 0.2126f * out[4 * p] + 0.7152f * out[4 * p + 1] + 0.0722f * out[4 * p + 2];
  };
  EXPECT_GT(out[2], out[0]);  // the least: blue above red
  EXPECT_LT(luminance(0), 0.05f);
  EXPECT_LT(luminance(0), luminance(1));
  EXPECT_LT(luminance(1), luminance(2));
  EXPECT_GT(out[8], 0.9f);  // the most: yellow
  EXPECT_GT(out[9], 0.7f);
  EXPECT_LT(out[10], 0.1f);
  for (int p = 0; p < 3; ++p) EXPECT_EQ(out[4 * p + 3], 1.0f);
}

}  // namespace
}  // namespace whitted
