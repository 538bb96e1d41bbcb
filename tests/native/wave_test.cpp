// Tracing in waves (integrator/wave.h) against the recursion it reorders: the same rays,
// the same pixels up to the rounding of a different order of sums, and pixels that depend
// on neither threads nor tiles.
#include "integrator/wave.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <string>
#include <utility>

#include "integrator/render.h"
#include "scene_builders.h"

namespace whitted {
namespace {

using testing::add_object;
using testing::emitter;
using testing::quad;
using testing::run_to_end;
using testing::small_render;

// Every effect the wave defers or reorders: mirror and glass (children), a sized lamp
// (several feelers a hit) and a point lamp, a cut-out (layers within one ray), a rough
// metal (glossy children), an emissive panel (its feelers and their MIS weights), glass
// under glass (media carried by the deferred rays), glass shadows, and a fog box over a
// corner of the floor (segments of camera, mirror and glass rays, their feelers).
Scene every_effect() {
  Scene scene = testing::glass_and_mirror_scene();
  Material cutout;
  cutout.diffuse = Color(0.2f, 0.7f, 0.3f);
  cutout.alpha = 0.4f;
  // Half over the mirror: the mirror's children carry the cut-out's coverage.
  add_object(&scene, "cutout", quad(-3.5f, -1.5f, -1.0f, 1.0f, 0.9f), cutout);
  Material metal;
  metal.diffuse = Color(0.0f);
  metal.specular = Color(0.0f);
  metal.reflectivity = Color(0.9f, 0.8f, 0.6f);
  metal.roughness = 0.3f;
  add_object(&scene, "metal", quad(-1.5f, 0.5f, 1.5f, 3.0f, 0.2f), metal);
  add_object(&scene, "panel", quad(2.0f, 3.0f, 1.0f, 2.0f, 2.5f),
             emitter(Color(4.0f), EmissionSampling::kBoth));
  add_object(&scene, "inner glass", quad(-0.5f, 0.5f, -0.5f, 0.5f, 0.8f), testing::clear(1.33f));
  add_object(&scene, "fog", testing::box(Vec3(-4.0f, -4.0f, -0.5f), Vec3(0.0f, 0.0f, 1.5f)),
             testing::fog(Color(0.05f), Color(0.2f, 0.15f, 0.1f), 0.3f, Color(0.02f)));
  return scene;
}

struct Rendered {
  std::vector<float> pixels;
  std::vector<float> cost;
  RenderStats stats;
  std::array<std::vector<float>, kFilmPassCount> passes;  // those kept
};

Rendered render(const Scene& scene, Settings settings, bool waves) {
  settings.waves = waves;
  RenderJob job(scene, settings, scene.camera);
  run_to_end(job);
  Rendered out{job.film().pixels(), job.film().cost(), job.stats(), {}};
  for (size_t p = 0; p < kFilmPassCount; ++p) {
    const auto pass = static_cast<FilmPass>(p);
    if (job.film().has_pass(pass)) out.passes[p] = job.film().pass(pass);
  }
  return out;
}

// Each channel within a few float roundings of the recursion's: the wave adds
// factor * local term per ray, the recursion local + sigma * (local' + ...), so the two
// round differently (about 1e-7 relative per addition, a handful of additions deep).
void expect_close(const std::vector<float>& waves, const std::vector<float>& recursive) {
  ASSERT_EQ(waves.size(), recursive.size());
  size_t differ = 0;
  float worst = 0.0f;
  for (size_t i = 0; i < waves.size(); ++i) {
    const float scale = std::max(1.0f, std::fabs(recursive[i]));
    worst = std::max(worst, std::fabs(waves[i] - recursive[i]) / scale);
    differ += waves[i] != recursive[i] ? 1 : 0;
  }
  EXPECT_LE(worst, 1e-5f) << differ << " of " << waves.size() << " channels differ";
}

void expect_same_rays(const RayCounts& a, const RayCounts& b) {
  EXPECT_EQ(a.camera, b.camera);
  EXPECT_EQ(a.shadow, b.shadow);
  EXPECT_EQ(a.reflection, b.reflection);
  EXPECT_EQ(a.refraction, b.refraction);
  EXPECT_EQ(a.glossy, b.glossy);
  EXPECT_EQ(a.transparent, b.transparent);
  EXPECT_EQ(a.total_internal_reflections, b.total_internal_reflections);
  EXPECT_EQ(a.depth_limited, b.depth_limited);
  EXPECT_EQ(a.cutoff_skipped, b.cutoff_skipped);
  EXPECT_EQ(a.shadow_rays_skipped.backfacing, b.shadow_rays_skipped.backfacing);
  EXPECT_EQ(a.shadow_rays_skipped.unlit, b.shadow_rays_skipped.unlit);
  EXPECT_EQ(a.shadow_rays_skipped.cutoff, b.shadow_rays_skipped.cutoff);
}

TEST(Waves, GiveTheRecursionsPixelsRaysAndCostsUpToRounding) {
  const Scene scene = every_effect();
  for (const auto& [samples, mode] :
       {std::pair{1, AntiAliasing::kRegular}, std::pair{2, AntiAliasing::kJittered}}) {
    Settings settings = small_render(61, 43, samples, 2, 16);
    settings.aa_mode = mode;
    settings.glass_shadows = GlassShadows::kTinted;
    const Rendered waves = render(scene, settings, true);
    const Rendered recursive = render(scene, settings, false);
    EXPECT_TRUE(waves.stats.waves);
    EXPECT_FALSE(recursive.stats.waves);
    expect_close(waves.pixels, recursive.pixels);
    EXPECT_TRUE(waves.cost == recursive.cost) << "the Whitted Rays pass";
    expect_same_rays(waves.stats.rays, recursive.stats.rays);
    EXPECT_GT(waves.stats.wave_bytes, 0u);
  }
}

TEST(Waves, ProgressivePassesGiveTheRecursionsPixels) {
  const Scene scene = every_effect();
  Settings settings = small_render(40, 30, 2, 2, 16);
  settings.progressive = true;
  expect_close(render(scene, settings, true).pixels, render(scene, settings, false).pixels);
}

TEST(Waves, ThePixelsDependOnNeitherThreadsNorTiles) {
  const Scene scene = every_effect();
  for (const AntiAliasing mode : {AntiAliasing::kRegular, AntiAliasing::kAdaptive}) {
    Settings settings = small_render(67, 45, 2, 1, 64);
    settings.aa_mode = mode;
    const std::vector<float> reference = render(scene, settings, true).pixels;
    for (auto [threads, tile] : {std::pair{2, 7}, std::pair{3, 16}, std::pair{2, 1}}) {
      settings.threads = threads;
      settings.tile_size = tile;
      EXPECT_TRUE(render(scene, settings, true).pixels == reference)
          << threads << " threads, tile " << tile;
    }
  }
}

// Adaptive anti-aliasing traces a wave per depth of the subdivision (row_adaptive): the
// same squares split, so the same rays, and the same pixels up to rounding.
TEST(Waves, AdaptiveSubdivisionGivesTheRecursionsPixelsRaysAndCosts) {
  const Scene scene = every_effect();
  for (const int depth : {1, 3}) {
    Settings settings = small_render(61, 43, 1, 2, 16);
    settings.aa_mode = AntiAliasing::kAdaptive;
    settings.aa_depth = depth;
    settings.glass_shadows = GlassShadows::kTinted;
    const Rendered waves = render(scene, settings, true);
    const Rendered recursive = render(scene, settings, false);
    EXPECT_TRUE(waves.stats.waves);
    expect_close(waves.pixels, recursive.pixels);
    EXPECT_TRUE(waves.cost == recursive.cost) << "the Whitted Rays pass";
    expect_same_rays(waves.stats.rays, recursive.stats.rays);
    // The subdivision did split: more camera rays than the pixels' corners.
    EXPECT_GT(waves.stats.rays.camera, 4u * 61u * 43u) << "depth " << depth;
  }
}

// The passes of `bits`, rendered in waves and recursively with `base`'s settings, for whole
// pixels, adaptive subdivision and progressive samples: Combined within rounding, the
// same ray cost and rays, and each kept pass handed to check(pass, waves, recursive).
template <class Check>
void compare_passes(const Scene& scene, Settings base, uint32_t bits, const Check& check) {
  for (const AntiAliasing mode : {AntiAliasing::kRegular, AntiAliasing::kAdaptive}) {
    for (const bool progressive : {false, true}) {
      Settings settings = base;
      settings.aa_mode = mode;
      settings.aa_depth = 2;
      settings.progressive = progressive;
      settings.passes = bits;
      const Rendered waves = render(scene, settings, true);
      const Rendered recursive = render(scene, settings, false);
      EXPECT_TRUE(waves.stats.waves);
      EXPECT_FALSE(recursive.stats.waves);
      expect_close(waves.pixels, recursive.pixels);
      EXPECT_TRUE(waves.cost == recursive.cost);
      expect_same_rays(waves.stats.rays, recursive.stats.rays);
      for (size_t p = 0; p < kFilmPassCount; ++p) {
        if ((bits & pass_bit(static_cast<FilmPass>(p))) == 0) continue;
        SCOPED_TRACE(std::string(kFilmPassNames[p]) + (progressive ? ", progressive" : "") +
                     (mode == AntiAliasing::kAdaptive ? ", adaptive" : ""));
        ASSERT_FALSE(waves.passes[p].empty());
        check(static_cast<FilmPass>(p), waves.passes[p], recursive.passes[p]);
      }
    }
  }
}

// The data passes (Depth, Mist, Normal, ...) are the camera's surface's: the wave
// records them as the camera rays are traced, the same values as the recursion's.
TEST(Waves, DataPassesAreTheRecursions) {
  const std::vector<FilmPass> data = {
      FilmPass::kDepth, FilmPass::kMist,        FilmPass::kNormal,       FilmPass::kPosition,
      FilmPass::kUV,    FilmPass::kObjectIndex, FilmPass::kMaterialIndex};
  uint32_t bits = 0;
  for (const FilmPass pass : data) bits |= pass_bit(pass);
  ASSERT_EQ(bits, kDataPasses);
  compare_passes(every_effect(), small_render(41, 29, 2, 2, 16), bits,
                 [](FilmPass /*pass*/, const std::vector<float>& waves,
                    const std::vector<float>& recursive) { EXPECT_TRUE(waves == recursive); });
}

// The light passes, Contributions, Cut Weight and the denoising guides are traced in waves
// too: each queued ray and feeler takes along where its terms go (PassRecorder::resume,
// PassPath, FeelerPasses), so every pass is the recursion's up to rounding, and none is
// empty where the scene shows it.
TEST(Waves, LightPassesContributionsCutWeightAndGuidesAreTheRecursions) {
  Settings settings = small_render(41, 29, 2, 2, 16);
  settings.glass_shadows = GlassShadows::kTinted;
  settings.max_depth = 3;  // some rays cut by depth: Cut Weight is not all zero
  settings.contribution_depth = 2;
  const uint32_t bits = kLightPasses | pass_bit(FilmPass::kContributions) |
                        pass_bit(FilmPass::kCutWeight) | pass_bit(FilmPass::kDepth) | kGuidePasses;
  compare_passes(
      every_effect(), settings, bits,
      [](FilmPass pass, const std::vector<float>& waves, const std::vector<float>& recursive) {
        expect_close(waves, recursive);
        float sum = 0.0f;
        for (const float v : waves) sum += std::fabs(v);
        if (pass != FilmPass::kTransmissionDirect && pass != FilmPass::kVolumeIndirect) {
          EXPECT_GT(sum, 0.0f) << "the scene shows something in every pass but two";
        }
      });
}

TEST(Waves, CancelStopsPromptly) {
  const Scene scene = every_effect();
  Settings settings = small_render(1200, 900, 4, 2, 64);
  settings.waves = true;
  RenderJob job(scene, settings, scene.camera);
  job.start();
  job.cancel();
  const auto start = std::chrono::steady_clock::now();
  EXPECT_TRUE(job.wait(5.0));
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
  EXPECT_TRUE(job.stats().cancelled);
}

}  // namespace
}  // namespace whitted