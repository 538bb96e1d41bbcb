// Noise-driven (adaptive) sampling: the error estimate, the film's check and dilation,
// the schedule's rounds, and renders that stop where the noise
// is low, whatever the threads and tiles.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "integrator/film.h"
#include "integrator/render.h"
#include "integrator/sampler.h"
#include "integrator/schedule.h"
#include "scene_builders.h"

namespace whitted {
namespace {

using testing::add_object;
using testing::emitter;
using testing::quad;
using testing::run_to_end;
using testing::small_render;

TEST(NoiseError, RelativeAboveOneSqrtBelow) {
  // |0.3| + 0 + |0.3| over the sum 3.
  EXPECT_NEAR(noise_error(Color(1.0f), Color(1.3f, 1.0f, 0.7f)), 0.6f / (3.0f + 1e-4f), 1e-6f);
  // 0.1 over sqrt(0.25).
  EXPECT_NEAR(noise_error(Color(0.25f, 0.0f, 0.0f), Color(0.35f, 0.0f, 0.0f)),
              0.1f / (0.5f + 1e-4f), 1e-6f);
  EXPECT_EQ(noise_error(Color(0.0f), Color(0.0f)), 0.0f);
}

// A film whose pixels all took four equal samples, but `noisy`, which took 0, 0, 1, 1
// (samples 2 and 3 are its class A: core/sobol.h class_a).
Film four_samples(int width, int height, std::vector<std::pair<int, int>> noisy) {
  Film film(width, height, true, 0, 1, true);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const bool odd = std::find(noisy.begin(), noisy.end(), std::pair{x, y}) != noisy.end();
      for (int k = 0; k < 4; ++k) {
        film.add(x, y, Sample{Color(odd && k < 2 ? 0.0f : 1.0f), 1.0f}, 1.0f);
      }
    }
  }
  return film;
}

std::set<std::pair<int, int>> active(const Film& film) {
  std::set<std::pair<int, int>> out;
  for (int y = 0; y < film.height(); ++y) {
    for (int x = 0; x < film.width(); ++x) {
      if (film.active(x, y)) out.insert({x, y});
    }
  }
  return out;
}

TEST(FilmConverge, ANoisyPixelKeepsItsNeighboursActiveInsideTheArea) {
  Film film = four_samples(5, 4, {{2, 2}});
  EXPECT_EQ(active(film).size(), 20u);  // all active before the first check
  EXPECT_EQ(film.converge(0.01f, 0, 0, 5, 4), 9u);
  std::set<std::pair<int, int>> expected;
  for (int y = 1; y <= 3; ++y) {
    for (int x = 1; x <= 3; ++x) expected.insert({x, y});
  }
  EXPECT_EQ(active(film), expected);

  Film corner = four_samples(5, 4, {{0, 0}});
  EXPECT_EQ(corner.converge(0.01f, 0, 0, 5, 4), 4u);  // clipped at the image's corner
  EXPECT_EQ(active(corner), (std::set<std::pair<int, int>>{{0, 0}, {1, 0}, {0, 1}, {1, 1}}));
  // An area without the noisy pixel: its neighbours converge, pixels outside stay as
  // they were (active).
  EXPECT_EQ(corner.converge(0.01f, 1, 0, 4, 4), 0u);
  EXPECT_FALSE(corner.active(1, 0));
  EXPECT_TRUE(corner.active(0, 0));
}

TEST(FilmConverge, ComparesWithFiveTimesTheThreshold) {
  // Samples 0, 0, 1, 1: mean 0.5, class-A half (samples 2 and 3) 1: error 3 * 0.5 /
  // (3 * 0.5 + 1e-4).
  const auto noisy = [] {
    Film film(1, 1, true, 0, 1, true);
    for (float v : {0.0f, 0.0f, 1.0f, 1.0f}) film.add(0, 0, Sample{Color(v), 1.0f}, 1.0f);
    return film;
  };
  Film film = noisy();
  const float error = noise_error(Color(0.5f), Color(1.0f));
  EXPECT_NEAR(error, 1.5f / (1.5f + 1e-4f), 1e-6f);
  EXPECT_EQ(film.converge(error / kNoiseThresholdScale * 1.01f, 0, 0, 1, 1), 0u);
  Film again = noisy();
  EXPECT_EQ(again.converge(error / kNoiseThresholdScale * 0.99f, 0, 0, 1, 1), 1u);
  EXPECT_EQ(again.noise(0, 0), error);  // the estimate converge compares
}

TEST(FilmNoise, NaNWithoutAClassASample) {
  Film film(2, 1, true, 0, 1, true);
  EXPECT_TRUE(std::isnan(film.noise(0, 0)));
  film.add(0, 0, Sample{Color(1.0f), 1.0f}, 1.0f);
  EXPECT_TRUE(std::isnan(film.noise(0, 0)));
  film.add(0, 0, Sample{Color(1.0f), 1.0f}, 1.0f);
  EXPECT_TRUE(std::isnan(film.noise(0, 0)));  // samples 0 and 1 are class B
  film.add(0, 0, Sample{Color(1.0f), 1.0f}, 1.0f);
  EXPECT_EQ(film.noise(0, 0), 0.0f);  // three equal samples
  // Three: class A is the third alone, 0 against the mean 2 / 3.
  film.add(1, 0, Sample{Color(1.0f), 1.0f}, 1.0f);
  film.add(1, 0, Sample{Color(1.0f), 1.0f}, 1.0f);
  film.add(1, 0, Sample{Color(0.0f), 1.0f}, 1.0f);
  EXPECT_EQ(film.noise(1, 0), noise_error(Color(2.0f / 3.0f), Color(0.0f)));
}

TEST(RegularCell, EachPixelPermutesItsGridOnlyWithNoiseDrivenSampling) {
  Settings settings;
  settings.aa_samples = 5;
  for (int s = 0; s < 25; ++s) EXPECT_EQ(regular_cell(settings, 3, 4, s), s);
  settings.adaptive_sampling = true;
  std::set<std::vector<int>> orders;
  for (int x = 0; x < 4; ++x) {
    std::vector<int> order;
    for (int s = 0; s < 25; ++s) order.push_back(regular_cell(settings, x, 7, s));
    std::vector<int> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    for (int s = 0; s < 25; ++s) EXPECT_EQ(sorted[s], s);  // a permutation of the grid
    orders.insert(order);
  }
  EXPECT_EQ(orders.size(), 4u);  // each pixel its own
}

TEST(AdaptiveSchedule, MinimumAsCycles) {
  Settings settings;
  settings.aa_samples = 64;
  settings.noise_threshold = 0.01f;
  EXPECT_EQ(minimum_samples(settings), 64);
  settings.noise_threshold = 0.1f;
  EXPECT_EQ(minimum_samples(settings), 32);
  settings.noise_threshold = 0.001f;
  EXPECT_EQ(minimum_samples(settings), 128);
  settings.adaptive_min_samples = 2;
  EXPECT_EQ(minimum_samples(settings), 4);
  settings.adaptive_min_samples = 100;
  EXPECT_EQ(minimum_samples(settings), 100);
  settings.aa_samples = 3;
  EXPECT_EQ(minimum_samples(settings), 9);  // at most the grid
}

TEST(AdaptiveSchedule, RoundsEndAtTheChecks) {
  Settings settings;
  settings.adaptive_sampling = true;
  settings.aa_samples = 16;
  settings.noise_threshold = 0.01f;  // minimum 64: checks after 80, 96, ..., 240
  std::vector<Pass> passes = make_schedule(settings);
  ASSERT_EQ(passes.size(), 12u);
  int first = 0;
  for (size_t i = 0; i < passes.size(); ++i) {
    EXPECT_EQ(passes[i].kind, Pass::Kind::kRound);
    EXPECT_EQ(passes[i].sample, first);
    EXPECT_EQ(passes[i].samples, i == 0 ? 80 : 80 + 16 * static_cast<int>(i));
    EXPECT_EQ(passes[i].converge, i + 1 < passes.size());
    first = passes[i].samples;
  }
  EXPECT_EQ(first, 256);

  settings.progressive = true;  // previews, then a round per sample, the same checks
  passes = make_schedule(settings);
  ASSERT_EQ(passes.size(), 3u + 256u);
  int checks = 0;
  for (size_t i = 3; i < passes.size(); ++i) {
    EXPECT_EQ(passes[i].samples, passes[i].sample + 1);
    if (passes[i].converge) {
      ++checks;
      EXPECT_EQ((passes[i].samples - 80) % 16, 0);
    }
  }
  EXPECT_EQ(checks, 11);

  settings.progressive = false;
  settings.aa_samples = 8;  // the minimum is the grid: one round, no check
  passes = make_schedule(settings);
  ASSERT_EQ(passes.size(), 1u);
  EXPECT_EQ(passes[0].samples, 64);
  EXPECT_FALSE(passes[0].converge);
}

TEST(AdaptiveSettings, ThresholdAndMinimumAreBounded) {
  Settings settings;
  settings.noise_threshold = -0.1f;
  EXPECT_THROW(settings.validate(), std::invalid_argument);
  settings.noise_threshold = 0.5f;
  settings.adaptive_min_samples = 5000;
  EXPECT_THROW(settings.validate(), std::invalid_argument);
}

// The shadow of a blocker on a floor, seen in 32 x 24 pixels through a jittered 6 x 6
// grid (noise at the shadow's edges, none in the flat areas), checks after 16 and 32.
Settings edge_settings(int threads, int tile) {
  Settings settings = small_render(32, 24, 6, threads, tile);
  settings.aa_mode = AntiAliasing::kJittered;
  settings.adaptive_sampling = true;
  settings.noise_threshold = 0.01f;
  settings.adaptive_min_samples = 4;
  return settings;
}

struct Rendered {
  std::vector<float> pixels;
  std::vector<uint32_t> samples;
  RenderStats stats;
};

Rendered render(const Scene& scene, const Settings& settings) {
  RenderJob job(scene, settings, scene.camera);
  run_to_end(job);
  Rendered out{job.film().pixels(), {}, job.stats()};
  for (int y = 0; y < settings.height && settings.adaptive_sampling; ++y) {
    for (int x = 0; x < settings.width; ++x) out.samples.push_back(job.film().samples(x, y));
  }
  return out;
}

TEST(AdaptiveRender, FlatPixelsStopAtTheFirstCheckEdgesGoOn) {
  const Scene scene = testing::occluder_over_floor(0.5f);
  for (bool waves : {false, true}) {
    Settings settings = edge_settings(2, 8);
    settings.waves = waves;
    const Rendered r = render(scene, settings);
    EXPECT_EQ(r.stats.samples_min, 16u) << waves;
    EXPECT_EQ(r.stats.samples_max, 36u) << waves;
    EXPECT_GT(r.stats.samples_mean, 16.0) << waves;
    EXPECT_LT(r.stats.samples_mean, 30.0) << waves;
    // Whole rounds: 16 + 4 where a converged pixel's neighbour became noisy at the
    // second check (its samples changed its estimate), which makes it active again.
    for (uint32_t n : r.samples) EXPECT_TRUE(n == 16 || n == 20 || n == 32 || n == 36) << n;
    // The samples taken are those counted, no more.
    uint64_t total = 0;
    for (uint32_t n : r.samples) total += n;
    EXPECT_EQ(r.stats.samples, total) << waves;
  }
  // A flat image (an emitter filling the view): every pixel stops at the first check.
  Scene flat;
  add_object(&flat, "panel", quad(-20, 20, -20, 20, 0), emitter(Color(0.7f)));
  flat.camera = testing::looking_down(Vec3(0.0f, 0.0f, 5.0f), 0.5f);
  const Rendered r = render(flat, edge_settings(2, 8));
  EXPECT_EQ(r.stats.samples_max, 16u);
  EXPECT_EQ(r.stats.active_pixels, 0u);
  // A probe (the Estimate's: one tile in stride^2 traced) stops there too: the pixels it
  // skips are neither noisy nor keep their traced neighbours active.
  Settings probe = edge_settings(2, 2);
  probe.probe_stride = 3;
  const Rendered p = render(flat, probe);
  EXPECT_EQ(p.stats.samples_max, 16u);
  EXPECT_EQ(p.stats.active_pixels, 0u);
  size_t traced = 0;
  for (uint32_t n : p.samples) traced += n > 0 ? 1 : 0;
  EXPECT_GT(traced, 0u);
  EXPECT_LT(traced, p.samples.size() / 4);
}

TEST(AdaptiveRender, ThresholdZeroIsTheFixedCountRender) {
  const Scene scene = testing::glass_and_mirror_scene();
  for (bool waves : {false, true}) {
    Settings settings = edge_settings(2, 8);
    settings.waves = waves;
    settings.noise_threshold = 0.0f;
    const Rendered adaptive = render(scene, settings);
    EXPECT_EQ(adaptive.stats.samples_min, 36u);
    settings.adaptive_sampling = false;
    const Rendered fixed = render(scene, settings);
    ASSERT_EQ(adaptive.pixels.size(), fixed.pixels.size());
    for (size_t i = 0; i < fixed.pixels.size(); ++i) {
      // The same samples summed in another order.
      EXPECT_NEAR(adaptive.pixels[i], fixed.pixels[i], 1e-5f * std::max(1.0f, fixed.pixels[i]))
          << i << " waves " << waves;
    }
  }
}

TEST(AdaptiveRender, BitIdenticalForThreadsAndTiles) {
  const Scene scene = testing::glass_and_mirror_scene();
  for (bool waves : {false, true}) {
    Settings reference_settings = edge_settings(1, 32);
    reference_settings.waves = waves;
    const Rendered reference = render(scene, reference_settings);
    EXPECT_LT(reference.stats.samples_min, reference.stats.samples_max);
    for (int threads : {1, 2, 3}) {
      for (int tile : {1, 7, 32}) {
        Settings settings = edge_settings(threads, tile);
        settings.waves = waves;
        const Rendered r = render(scene, settings);
        EXPECT_EQ(r.pixels, reference.pixels) << threads << " " << tile << " " << waves;
        EXPECT_EQ(r.samples, reference.samples) << threads << " " << tile << " " << waves;
      }
    }
    Settings progressive = edge_settings(2, 7);  // a round per sample, the same checks
    progressive.waves = waves;
    progressive.progressive = true;
    const Rendered r = render(scene, progressive);
    EXPECT_EQ(r.samples, reference.samples) << waves;
    EXPECT_EQ(r.pixels, reference.pixels) << waves;
  }
}

// The camera samples the Sample Count pass shows, row by row.
std::vector<uint32_t> sample_count_pass(const RenderJob& job) {
  std::vector<uint32_t> out;
  for (float v : job.film().pass(FilmPass::kSampleCount)) out.push_back(static_cast<uint32_t>(v));
  return out;
}

TEST(SampleCountPass, EachPixelsCameraSamplesWithoutChangingTheImage) {
  const Scene scene = testing::occluder_over_floor(0.5f);
  for (bool waves : {false, true}) {
    Settings settings = edge_settings(2, 8);
    settings.waves = waves;
    const Rendered without = render(scene, settings);
    settings.passes = pass_bit(FilmPass::kSampleCount);
    RenderJob job(scene, settings, scene.camera);
    run_to_end(job);
    EXPECT_EQ(job.film().pixels(), without.pixels) << waves;  // the kernel records nothing
    const std::vector<uint32_t> counts = sample_count_pass(job);
    EXPECT_EQ(counts, without.samples) << waves;
    // Flat pixels show the minimum (the first check), the shadow's edges more.
    EXPECT_EQ(*std::min_element(counts.begin(), counts.end()), 16u) << waves;
    EXPECT_EQ(*std::max_element(counts.begin(), counts.end()), 36u) << waves;
    // Whole pixels: the grid, or Whitted's adaptive anti-aliasing's camera rays.
    for (AntiAliasing mode : {AntiAliasing::kJittered, AntiAliasing::kAdaptive}) {
      Settings fixed = settings;
      fixed.adaptive_sampling = false;
      fixed.aa_mode = mode;
      RenderJob whole(scene, fixed, scene.camera);
      run_to_end(whole);
      const std::vector<uint32_t> taken = sample_count_pass(whole);
      uint64_t total = 0;
      for (uint32_t n : taken) total += n;
      EXPECT_EQ(total, whole.stats().samples) << waves;
      const auto [low, high] = std::minmax_element(taken.begin(), taken.end());
      if (mode == AntiAliasing::kJittered) {
        EXPECT_EQ(*low, 36u);
        EXPECT_EQ(*high, 36u);
      } else {
        EXPECT_EQ(*low, 4u) << waves;  // the corners of a flat pixel
        EXPECT_GT(*high, 4u) << waves;
      }
    }
  }
}

TEST(NoiseStats, FinalEstimateFallsWithSamplesAndStoppedPixelsAreBelowTheLimit) {
  const Scene scene = testing::glass_and_mirror_scene();
  for (bool waves : {false, true}) {
    // Threshold 0: every pixel takes its whole grid; the estimate falls as it grows.
    std::vector<double> means;
    for (int n : {4, 8}) {
      Settings settings = edge_settings(2, 8);
      settings.waves = waves;
      settings.aa_samples = n;
      settings.noise_threshold = 0.0f;
      const Rendered r = render(scene, settings);
      ASSERT_TRUE(r.stats.noise.has_value());
      EXPECT_GT(r.stats.noise->max, r.stats.noise->mean);
      means.push_back(r.stats.noise->mean);
    }
    EXPECT_LT(means[1], 0.75 * means[0]) << waves;
    // A pixel that stopped at a check (16 or 32 samples; one at 20 was woken by a noisy
    // neighbour at the second check and took the last round unchecked) is below 5 x the
    // threshold.
    Settings settings = edge_settings(2, 8);
    settings.waves = waves;
    RenderJob job(scene, settings, scene.camera);
    run_to_end(job);
    double sum = 0.0;
    float most = 0.0f;
    for (int y = 0; y < settings.height; ++y) {
      for (int x = 0; x < settings.width; ++x) {
        const float error = job.film().noise(x, y);
        sum += error;
        most = std::max(most, error);
        const uint32_t taken = job.film().samples(x, y);
        if (taken == 16 || taken == 32) {
          EXPECT_LT(error, kNoiseThresholdScale * settings.noise_threshold);
        }
      }
    }
    const RenderStats stats = job.stats();
    ASSERT_TRUE(stats.noise.has_value());
    EXPECT_EQ(stats.noise->max, most);
    EXPECT_NEAR(stats.noise->mean, sum / (settings.width * settings.height), 1e-9);
    // Absent without noise-driven sampling.
    settings.adaptive_sampling = false;
    EXPECT_FALSE(render(scene, settings).stats.noise.has_value());
  }
}

TEST(AdaptiveSettings, TimeLimitIsBounded) {
  Settings settings;
  settings.time_limit = -1.0;
  EXPECT_THROW(settings.validate(), std::invalid_argument);
  settings.time_limit = 2e6;
  EXPECT_THROW(settings.validate(), std::invalid_argument);
  settings.time_limit = 0.5;
  EXPECT_NO_THROW(settings.validate());
}

TEST(TimeLimit, AnExpiredLimitTracesTheFirstRoundOnly) {
  const Scene scene = testing::occluder_over_floor(0.5f);
  for (bool waves : {false, true}) {
    Settings settings = edge_settings(2, 8);
    settings.waves = waves;
    settings.time_limit = 1e-9;
    RenderJob job(scene, settings, scene.camera);
    run_to_end(job);
    const RenderStats stats = job.stats();
    EXPECT_TRUE(stats.time_limited);
    EXPECT_EQ(stats.rounds, 1);
    EXPECT_EQ(stats.samples_min, 16u);  // the first check's count, every pixel
    EXPECT_EQ(stats.samples_max, 16u);
    EXPECT_EQ(stats.samples, 16u * 32u * 24u);
    EXPECT_FALSE(stats.cancelled);
    EXPECT_EQ(job.progress(), 1.0f);
    EXPECT_EQ(stats.pixels, 32u * 24u);  // every tile reported finished
    size_t tiles = 0;
    for (const Tile& t : job.take_finished_tiles()) tiles += t.width * t.height;
    EXPECT_EQ(tiles, 32u * 24u);
    // Each pixel shows the mean of its first 16 samples: where the render without a
    // limit stopped a pixel at the first check too, the two pixels are the same.
    Settings unlimited = settings;
    unlimited.time_limit = 0.0;
    const Rendered full = render(scene, unlimited);
    EXPECT_FALSE(full.stats.time_limited);
    EXPECT_EQ(full.stats.rounds, 3);
    size_t same = 0;
    for (size_t i = 0; i < full.samples.size(); ++i) {
      if (full.samples[i] != 16) continue;
      ++same;
      for (size_t c = 0; c < 4; ++c) {
        EXPECT_EQ(job.film().pixels()[4 * i + c], full.pixels[4 * i + c]) << i << " " << waves;
      }
    }
    EXPECT_GT(same, 32u * 24u / 2);
  }
}

TEST(TimeLimit, ProgressiveStopsAfterItsFirstRound) {
  const Scene scene = testing::occluder_over_floor(0.5f);
  Settings settings = edge_settings(2, 8);
  settings.progressive = true;
  settings.time_limit = 1e-9;
  const Rendered r = render(scene, settings);
  EXPECT_TRUE(r.stats.time_limited);
  EXPECT_EQ(r.stats.rounds, 1);  // a round per sample: one sample each
  EXPECT_EQ(r.stats.samples_max, 1u);
  EXPECT_EQ(r.stats.samples_min, 1u);
}

TEST(TimeLimit, ZeroOrUnreachedChangesNothingAndWithoutAdaptiveItIsIgnored) {
  const Scene scene = testing::glass_and_mirror_scene();
  for (bool waves : {false, true}) {
    Settings settings = edge_settings(2, 8);
    settings.waves = waves;
    const Rendered none = render(scene, settings);
    settings.time_limit = 1e6;
    const Rendered unreached = render(scene, settings);
    EXPECT_FALSE(unreached.stats.time_limited);
    EXPECT_EQ(unreached.stats.rounds, none.stats.rounds);
    EXPECT_EQ(unreached.pixels, none.pixels);
    EXPECT_EQ(unreached.samples, none.samples);
    // Without noise-driven sampling the limit is ignored.
    settings.adaptive_sampling = false;
    settings.time_limit = 0.0;
    const Rendered fixed = render(scene, settings);
    settings.time_limit = 1e-9;
    const Rendered limited = render(scene, settings);
    EXPECT_FALSE(limited.stats.time_limited);
    EXPECT_EQ(limited.stats.rounds, 0);
    EXPECT_EQ(limited.pixels, fixed.pixels);
  }
}

}  // namespace
}  // namespace whitted
