// Render passes (integrator/passes.*): the light passes and the per-depth contributions
// give back Combined, passes leave Combined as it was, the cut weight, the data passes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "integrator/render.h"
#include "scene_builders.h"

namespace whitted {
namespace {

using testing::glass_and_mirror_scene;

constexpr uint32_t kAllPasses = pass_bit(FilmPass::kCount) - 1;

Settings small(uint32_t passes) {
  Settings s;
  s.width = 40;
  s.height = 30;
  s.aa_samples = 2;
  s.threads = 2;
  s.tile_size = 16;
  s.passes = passes;
  s.max_depth = 4;
  return s;
}

// The largest |Combined - recombined| over the pixels' RGB.
float recombination_error(const Film& film) {
  const auto& p = [&film](FilmPass pass) -> const std::vector<float>& { return film.pass(pass); };
  float worst = 0.0f;
  for (size_t i = 0; i < film.pixels().size() / 4; ++i) {
    for (size_t c = 0; c < 3; ++c) {
      const size_t k = 3 * i + c;
      const float rebuilt =
          p(FilmPass::kDiffuseColor)[k] *
              (p(FilmPass::kDiffuseDirect)[k] + p(FilmPass::kDiffuseIndirect)[k]) +
          p(FilmPass::kGlossyColor)[k] *
              (p(FilmPass::kGlossyDirect)[k] + p(FilmPass::kGlossyIndirect)[k]) +
          p(FilmPass::kTransmissionColor)[k] *
              (p(FilmPass::kTransmissionDirect)[k] + p(FilmPass::kTransmissionIndirect)[k]) +
          p(FilmPass::kEmission)[k] + p(FilmPass::kEnvironment)[k];
      worst = std::max(worst, std::abs(rebuilt - film.pixels()[4 * i + c]));
    }
  }
  return worst;
}

TEST(Passes, LightPassesRecombineToCombined) {
  Scene scene = glass_and_mirror_scene();
  scene.set_background(Color(0.2f, 0.3f, 0.4f));
  for (const AntiAliasing mode : {AntiAliasing::kRegular, AntiAliasing::kAdaptive}) {
    Settings settings = small(kLightPasses);
    settings.aa_mode = mode;
    RenderJob job(scene, settings, scene.camera);
    testing::run_to_end(job);
    EXPECT_LT(recombination_error(job.film()), 1e-4f);
    // Every component is somewhere in the picture.
    for (const FilmPass pass :
         {FilmPass::kDiffuseDirect, FilmPass::kDiffuseIndirect, FilmPass::kGlossyDirect,
          FilmPass::kGlossyIndirect, FilmPass::kTransmissionIndirect, FilmPass::kEnvironment}) {
      const std::vector<float>& v = job.film().pass(pass);
      EXPECT_GT(*std::max_element(v.begin(), v.end()), 0.0f) << kFilmPassNames[size_t(pass)];
    }
  }
}

TEST(Passes, ProgressiveLastPassHasTheSamePasses) {
  const Scene scene = glass_and_mirror_scene();
  Settings settings = small(kAllPasses);
  RenderJob whole(scene, settings, scene.camera);
  testing::run_to_end(whole);
  settings.progressive = true;
  settings.packets = false;
  RenderJob progressive(scene, settings, scene.camera);
  testing::run_to_end(progressive);
  for (size_t p = 0; p < kFilmPassCount; ++p) {
    const auto pass = static_cast<FilmPass>(p);
    const std::vector<float>& a = whole.film().pass(pass);
    const std::vector<float>& b = progressive.film().pass(pass);
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) {
      ASSERT_NEAR(a[i], b[i], 1e-5f * std::max(1.0f, std::abs(a[i]))) << kFilmPassNames[p];
    }
  }
}

// Also the kernel compiled for the scene's set of effects (no passes) against the one
// reading them at run time (with passes): the same code, the same pixels and ray cost,
// traced recursively and in waves alike.
TEST(Passes, DoNotChangeCombined) {
  const Scene scene = glass_and_mirror_scene();
  for (const bool waves : {false, true}) {
    Settings without = small(0);
    without.waves = waves;
    Settings with_passes = small(kAllPasses);
    with_passes.waves = waves;
    RenderJob plain(scene, without, scene.camera);
    testing::run_to_end(plain);
    RenderJob with(scene, with_passes, scene.camera);
    testing::run_to_end(with);
    EXPECT_EQ(with.stats().waves, waves);
    EXPECT_TRUE(plain.film().pixels() == with.film().pixels()) << "waves " << waves;
    EXPECT_TRUE(plain.film().cost() == with.film().cost()) << "waves " << waves;
  }
}

TEST(Passes, EachGroupAloneGivesWhatEveryPassGives) {
  // The recorder fills only what the kept groups of passes read (passes.h): a group
  // kept alone has, bit for bit, the values it has among every pass. A high cutoff
  // stops the weaker rays (Cut Weight) and lets the mirror's through (the light passes).
  const Scene scene = glass_and_mirror_scene();
  Settings settings = small(kAllPasses);
  settings.cutoff = 0.3f;
  RenderJob every(scene, settings, scene.camera);
  testing::run_to_end(every);
  for (const uint32_t group :
       {pass_bit(FilmPass::kDepth), kDataPasses, kLightPasses, pass_bit(FilmPass::kContributions),
        pass_bit(FilmPass::kCutWeight)}) {
    settings.passes = group;
    RenderJob alone(scene, settings, scene.camera);
    testing::run_to_end(alone);
    for (size_t p = 0; p < kFilmPassCount; ++p) {
      const auto pass = static_cast<FilmPass>(p);
      if ((group & pass_bit(pass)) == 0) continue;
      EXPECT_TRUE(alone.film().pass(pass) == every.film().pass(pass)) << kFilmPassNames[p];
    }
  }
  for (const FilmPass pass : {FilmPass::kCutWeight, FilmPass::kGlossyIndirect}) {
    const std::vector<float>& v = every.film().pass(pass);
    EXPECT_GT(*std::max_element(v.begin(), v.end()), 0.0f) << kFilmPassNames[size_t(pass)];
  }
}

TEST(Passes, ContributionsSumToCombinedAndCutWeightGrowsAsDepthFalls) {
  const Scene scene = glass_and_mirror_scene();
  float previous_cut = -1.0f;
  for (const int max_depth : {8, 0}) {
    Settings settings = small(pass_bit(FilmPass::kContributions) | pass_bit(FilmPass::kCutWeight));
    settings.max_depth = max_depth;
    settings.cutoff = 0.0f;
    settings.contribution_depth = 2;
    RenderJob job(scene, settings, scene.camera);
    testing::run_to_end(job);
    const Film& film = job.film();
    ASSERT_EQ(film.pass_channels(FilmPass::kContributions), 9);
    const std::vector<float>& bins = film.pass(FilmPass::kContributions);
    float worst = 0.0f;
    for (size_t i = 0; i < film.pixels().size() / 4; ++i) {
      for (size_t c = 0; c < 3; ++c) {
        const float sum = bins[9 * i + c] + bins[9 * i + 3 + c] + bins[9 * i + 6 + c];
        worst = std::max(worst, std::abs(sum - film.pixels()[4 * i + c]));
      }
    }
    EXPECT_LT(worst, 1e-4f) << "max depth " << max_depth;
    double cut = 0.0;
    for (const float w : film.pass(FilmPass::kCutWeight)) {
      EXPECT_GE(w, 0.0f);
      EXPECT_LE(w, 1.0f + 1e-5f);
      cut += w;
    }
    if (max_depth == 8) {
      EXPECT_EQ(cut, 0.0);  // the pane's and the mirror's rays end at depth 1 or 2
    } else {
      EXPECT_GT(cut, previous_cut) << "max depth " << max_depth;
    }
    previous_cut = static_cast<float>(cut);
  }
}

TEST(Passes, DataPassesOfAPlaneSeenFromAbove) {
  Scene scene;
  Material m;
  testing::add_object(&scene, "floor", testing::quad(-10, 10, -10, 10, 0), m);
  scene.camera = testing::looking_down(Vec3(0.0f, 0.0f, 4.0f), 0.5f);
  Settings settings = small(pass_bit(FilmPass::kDepth) | pass_bit(FilmPass::kNormal) |
                            pass_bit(FilmPass::kPosition) | pass_bit(FilmPass::kMist));
  settings.mist_start = 1.0f;
  settings.mist_depth = 6.0f;
  settings.mist_falloff = 1.0f;
  settings.aa_samples = 1;  // mist is a mean of samples, position the first sample's
  RenderJob job(scene, settings, scene.camera);
  testing::run_to_end(job);
  const Film& film = job.film();
  for (size_t i = 0; i < film.pixels().size() / 4; ++i) {
    EXPECT_NEAR(film.pass(FilmPass::kDepth)[i], 4.0f, 1e-4f);
    EXPECT_NEAR(film.pass(FilmPass::kNormal)[3 * i + 2], 1.0f, 1e-5f);
    EXPECT_NEAR(film.pass(FilmPass::kPosition)[3 * i + 2], 0.0f, 1e-5f);
    const float x = film.pass(FilmPass::kPosition)[3 * i];
    const float y = film.pass(FilmPass::kPosition)[3 * i + 1];
    const float distance = std::sqrt(x * x + y * y + 16.0f);
    EXPECT_NEAR(film.pass(FilmPass::kMist)[i], (distance - 1.0f) / 6.0f, 1e-4f);
  }
}

}  // namespace
}  // namespace whitted
