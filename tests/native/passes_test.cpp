// Render passes (integrator/passes.*): the light passes and the per-depth contributions
// give back Combined, passes leave Combined as it was, the cut weight, the data passes,
// the denoising guides through mirrors and glass.
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
          p(FilmPass::kVolumeDirect)[k] + p(FilmPass::kVolumeIndirect)[k] +
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

// The largest |Combined - the sum of the per-depth contributions| over the pixels' RGB, of
// a film keeping depths 0, 1 and 2+.
float contributions_error(const Film& film) {
  const std::vector<float>& bins = film.pass(FilmPass::kContributions);
  float worst = 0.0f;
  for (size_t i = 0; i < film.pixels().size() / 4; ++i) {
    for (size_t c = 0; c < 3; ++c) {
      const float sum = bins[9 * i + c] + bins[9 * i + 3 + c] + bins[9 * i + 6 + c];
      worst = std::max(worst, std::abs(sum - film.pixels()[4 * i + c]));
    }
  }
  return worst;
}

float largest(const Film& film, FilmPass pass) {
  const std::vector<float>& v = film.pass(pass);
  return *std::max_element(v.begin(), v.end());
}

// In fog: the light the media scatter towards the camera's rays is Volume Direct and their
// emission is Emission, as in Cycles; what the mirror's and the glass's rays meet in them
// feeds Glossy and Transmission Indirect; what lies behind fog is dimmed in its passes as
// in Combined. The light passes and the per-depth contributions give back Combined,
// recursively and in waves alike; Volume Indirect stays black (no light scatters twice).
TEST(Passes, FogsLightGoesToVolumeDirectAndItsEmissionToEmission) {
  for (const bool emits : {false, true}) {
    SCOPED_TRACE(emits ? "emitting fog" : "fog");
    const Scene scene = testing::foggy_glass_and_mirror_scene(
        Color(0.15f, 0.1f, 0.05f), emits ? Color(0.2f, 0.1f, 0.3f) : Color(0.0f));
    std::vector<float> volume_direct;
    for (const bool waves : {true, false}) {
      Settings settings = small(kLightPasses | pass_bit(FilmPass::kContributions));
      settings.contribution_depth = 2;
      settings.waves = waves;
      RenderJob job(scene, settings, scene.camera);
      testing::run_to_end(job);
      const Film& film = job.film();
      EXPECT_LT(recombination_error(film), 1e-4f) << (waves ? "waves" : "recursion");
      EXPECT_LT(contributions_error(film), 1e-4f) << (waves ? "waves" : "recursion");
      EXPECT_GT(largest(film, FilmPass::kVolumeDirect), 0.01f);
      EXPECT_EQ(largest(film, FilmPass::kVolumeIndirect), 0.0f);
      // Nothing else in the scene emits.
      if (emits) {
        EXPECT_GT(largest(film, FilmPass::kEmission), 0.01f);
      } else {
        EXPECT_EQ(largest(film, FilmPass::kEmission), 0.0f);
      }
      for (const FilmPass pass : {FilmPass::kGlossyIndirect, FilmPass::kTransmissionIndirect}) {
        EXPECT_GT(largest(film, pass), 0.0f) << kFilmPassNames[size_t(pass)];
      }
      if (volume_direct.empty()) {
        volume_direct = film.pass(FilmPass::kVolumeDirect);
      } else {
        EXPECT_EQ(film.pass(FilmPass::kVolumeDirect), volume_direct) << "waves and recursion";
      }
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
        pass_bit(FilmPass::kCutWeight), kGuidePasses}) {
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

Color pixel3(const Film& film, FilmPass pass, size_t i) {
  const std::vector<float>& v = film.pass(pass);
  return {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
}

void expect_near3(const Color& got, const Color& want, float tolerance, const char* what) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], tolerance) << what << " channel " << c;
}

// Looking down on the plane z = 0: a mirror of tint T where y > 0, a diffuse quad of
// colour D (and a Phong ks) where y < 0; above the camera, at z = 8, a diffuse ceiling of
// colour A over x < 0, the world W (brighter than 1 in green) over x > 0. The guides
// follow the mirror: T * A and the ceiling's normal facing the ray where it shows the
// ceiling, T * W clamped and no normal where it shows the world; the quad writes its own.
// By the camera hit's Position pass, away from the borders.
TEST(Passes, DenoisingGuidesFollowAMirrorToWhatItShows) {
  const Color tint(0.9f, 0.6f, 0.3f);
  const Color ceiling(0.2f, 0.5f, 0.7f);
  const Color quad_kd(0.1f, 0.4f, 0.8f);
  const Color quad_ks(0.05f);
  const Color world(0.3f, 2.0f, 0.5f);
  Scene scene;
  Material mirror;
  mirror.diffuse = Color(0.0f);
  mirror.reflectivity = tint;
  testing::add_object(&scene, "mirror", testing::quad(-10, 10, 0, 10, 0), mirror);
  Material diffuse;
  diffuse.diffuse = quad_kd;
  diffuse.specular = quad_ks;
  testing::add_object(&scene, "quad", testing::quad(-10, 10, -10, 0, 0), diffuse);
  Material above;
  above.diffuse = ceiling;
  testing::add_object(&scene, "ceiling", testing::quad(-50, 0, -50, 50, 8), above);
  scene.set_background(world);
  scene.camera = testing::looking_down(Vec3(0.0f, 0.0f, 4.0f), 0.5f);
  for (const bool waves : {false, true}) {
    Settings settings =
        small(kGuidePasses | pass_bit(FilmPass::kPosition) | pass_bit(FilmPass::kNormal));
    settings.aa_samples = 1;
    settings.waves = waves;
    RenderJob job(scene, settings, scene.camera);
    testing::run_to_end(job);
    const Film& film = job.film();
    int seen[3] = {0, 0, 0};
    for (size_t i = 0; i < film.pixels().size() / 4; ++i) {
      const Color at = pixel3(film, FilmPass::kPosition, i);
      const Color albedo = pixel3(film, FilmPass::kDenoisingAlbedo, i);
      const Color normal = pixel3(film, FilmPass::kDenoisingNormal, i);
      if (std::abs(at.x) < 0.1f || std::abs(at.y) < 0.1f) continue;
      if (at.y < 0.0f) {
        expect_near3(albedo, quad_kd + quad_ks, 1e-5f, "diffuse albedo");
        expect_near3(normal, Color(0, 0, 1), 1e-6f, "diffuse normal");
        seen[0] += 1;
      } else if (at.x < 0.0f) {
        expect_near3(albedo, tint * ceiling, 1e-5f, "mirrored ceiling");
        expect_near3(normal, Color(0, 0, -1), 1e-6f, "mirrored ceiling's normal");
        // The Normal pass is the mirror's own.
        expect_near3(pixel3(film, FilmPass::kNormal, i), Color(0, 0, 1), 1e-6f, "mirror");
        seen[1] += 1;
      } else {
        expect_near3(albedo, tint * Color(0.3f, 1.0f, 0.5f), 1e-5f, "mirrored world");
        expect_near3(normal, Color(0.0f), 0.0f, "mirrored world's normal");
        seen[2] += 1;
      }
    }
    for (const int n : seen) EXPECT_GT(n, 50) << "waves " << waves;
  }
}

// Clear glass over a diffuse floor, under a diffuse ceiling: Whitted splits at the pane
// into its reflection (Fresnel's sigma_r, about 0.04 looking straight down) and its
// refraction (sigma_t); the guides are their weighted sum: sigma_r * ceiling + sigma_t *
// floor, the normal sigma_r / (sigma_r + sigma_t) of the ceiling's (facing down) and the
// rest of the floor's (facing up). A rough pane (frosted, GGX alpha above Cycles' 0.075)
// writes its own: its transmission colour and normal.
TEST(Passes, DenoisingGuidesSplitAtGlassByTheBranchesWeights) {
  const Color floor_kd(0.7f, 0.3f, 0.1f);
  const Color ceiling_kd(0.1f, 0.2f, 0.9f);
  Scene scene;
  Material floor;
  floor.diffuse = floor_kd;
  testing::add_object(&scene, "floor", testing::quad(-50, 50, -50, 50, -1), floor);
  Material ceiling;
  ceiling.diffuse = ceiling_kd;
  testing::add_object(&scene, "ceiling", testing::quad(-50, 50, -50, 50, 8), ceiling);
  Material glass = testing::clear(1.5f);
  testing::add_object(&scene, "glass", testing::quad(-50, 50, -50, 50, 0), glass);
  scene.camera = testing::looking_down(Vec3(0.0f, 0.0f, 4.0f), 0.01f);
  const float f = fresnel_exact(1.0f, 1.5f);  // the camera's rays are within 0.6 degrees
  for (const bool waves : {false, true}) {
    Settings settings = small(kGuidePasses);
    settings.cutoff = 0.0f;
    settings.waves = waves;
    RenderJob job(scene, settings, scene.camera);
    testing::run_to_end(job);
    for (size_t i = 0; i < job.film().pixels().size() / 4; ++i) {
      expect_near3(pixel3(job.film(), FilmPass::kDenoisingAlbedo, i),
                   f * ceiling_kd + (1.0f - f) * floor_kd, 1e-4f, "glass albedo");
      expect_near3(pixel3(job.film(), FilmPass::kDenoisingNormal, i),
                   Color(0.0f, 0.0f, 1.0f - 2.0f * f), 1e-4f, "glass normal");
    }
  }
  glass.roughness = 0.5f;  // alpha 0.25
  glass.transmissivity = Color(0.8f, 0.9f, 1.0f);
  scene.set_material("glass", glass);
  Settings settings = small(kGuidePasses);
  RenderJob job(scene, settings, scene.camera);
  testing::run_to_end(job);
  for (size_t i = 0; i < job.film().pixels().size() / 4; ++i) {
    // sigma_r + sigma_t: the pane's transmissivity, split by Fresnel.
    expect_near3(pixel3(job.film(), FilmPass::kDenoisingAlbedo, i), glass.transmissivity, 1e-4f,
                 "frosted albedo");
    expect_near3(pixel3(job.film(), FilmPass::kDenoisingNormal, i), Color(0, 0, 1), 1e-4f,
                 "frosted normal");
  }
}

}  // namespace
}  // namespace whitted
