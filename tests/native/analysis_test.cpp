// Simulate only the effects a scene calls for: the analysis, the rays it saves, and the
// images it leaves unchanged.
#include "integrator/analysis.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "integrator/render.h"
#include "scene_builders.h"

namespace whitted {
namespace {

using testing::add_object;
using testing::emitter;
using testing::looking_down;
using testing::quad;

Material diffuse(Color c) {
  Material m;
  m.diffuse = c;
  return m;
}

Scene diffuse_scene() {
  Scene scene;
  add_object(&scene, "floor", quad(-10, 10, -10, 10, 0), diffuse(Color(0.7f)));
  add_object(&scene, "box", quad(-1, 1, -1, 1, 1), diffuse(Color(0.3f, 0.5f, 0.2f)));
  Light light;
  light.color = Color(20.0f);
  light.position = Vec3(1.0f, 1.0f, 4.0f);
  scene.set_light("key", light);
  Light spot;
  spot.type = LightType::kSpot;
  spot.color = Color(30.0f);
  spot.position = Vec3(-3.0f, 0.0f, 3.0f);
  spot.spot_size = 0.4f;
  scene.set_light("spot", spot);
  scene.set_ambient(Color(0.1f));
  scene.camera = looking_down(Vec3(0.0f, 0.0f, 8.0f), 0.6f);
  return scene;
}

struct Result {
  std::vector<float> pixels;
  RenderStats stats;
};

// analysis false: the plain tracer (every effect on, a feeler to every light sample).
Result render(const Scene& scene, bool analysis, float cutoff = 1.0f / 255.0f) {
  Settings settings;
  settings.width = 48;
  settings.height = 48;
  settings.analysis = analysis;
  settings.feeler_pruning = analysis;
  settings.cutoff = cutoff;
  RenderJob job(scene, settings, scene.camera);
  testing::run_to_end(job);
  return {job.film().pixels(), job.stats()};
}

TEST(Analysis, DiffuseSceneTracesNoReflectionOrRefractionAndNamesWhy) {
  const Scene scene = diffuse_scene();
  const auto compiled = scene.compile();
  const Effects effects = analyse(*compiled, Settings{});
  EXPECT_FALSE(effects.has(kReflectionEffect));
  EXPECT_FALSE(effects.has(kRefractionEffect));
  EXPECT_FALSE(effects.has(kTranslucencyEffect));
  EXPECT_TRUE(effects.has(kShadowEffect));
  const EffectDecision refraction{"refraction", false, "no transmissive material"};
  EXPECT_NE(std::find(effects.decisions.begin(), effects.decisions.end(), refraction),
            effects.decisions.end());
  const Result r = render(scene, true);
  EXPECT_EQ(r.stats.rays.reflection, 0u);
  EXPECT_EQ(r.stats.rays.refraction, 0u);
}

TEST(Analysis, SkippingChangesNothingWhereNothingCouldShow) {
  const Scene scene = diffuse_scene();
  const Result pruned = render(scene, true, 0.0f);  // cutoff 0: only exact skips
  const Result plain = render(scene, false);
  EXPECT_EQ(pruned.pixels, plain.pixels);  // bit for bit
  // Plain: a feeler to every light from every point; neither traces a reflection or
  // refraction of coefficient zero.
  EXPECT_GT(plain.stats.rays.shadow, pruned.stats.rays.shadow);
  EXPECT_EQ(plain.stats.rays.reflection + plain.stats.rays.refraction, 0u);
  EXPECT_EQ(pruned.stats.rays.reflection + pruned.stats.rays.refraction, 0u);
  // The spot lights a small disc: most points get no feeler towards it.
  EXPECT_GT(pruned.stats.rays.shadow_rays_skipped.unlit, pruned.stats.rays.camera / 2);
}

TEST(Analysis, CutoffPrunesWithinItsBound) {
  Scene scene = diffuse_scene();
  Material mirror;
  mirror.diffuse = Color(0.05f);
  mirror.reflectivity = Color(0.6f);
  add_object(&scene, "mirror", quad(-3, -2, -3, 3, 0.5f), mirror);
  Material glass;
  glass.diffuse = Color(0.0f);
  glass.transmissivity = Color(0.9f);
  add_object(&scene, "glass", quad(1, 3, -2, 2, 2.0f), glass);
  const Result forced = render(scene, false, 0.0f);  // every ray traced
  uint64_t previous = 0;
  for (float cutoff : {0.1f, 1.0f / 255.0f, 1e-3f, 0.0f}) {
    const Result r = render(scene, true, cutoff);
    double worst = 0.0;
    for (size_t i = 0; i < r.pixels.size(); ++i) {
      worst = std::max(worst, std::fabs(double(r.pixels[i]) - forced.pixels[i]));
    }
    // Each pruned branch or feeler leaves out less than `cutoff` times what it would have
    // seen (radiance here stays below 4); a few may add up in one pixel.
    EXPECT_LE(worst, 16.0 * cutoff + 1e-5) << cutoff;
    EXPECT_GE(r.stats.rays.total(), previous) << cutoff;  // lower cutoff, never fewer rays
    previous = r.stats.rays.total();
  }
}

// Pruning judges a sized light as a whole: more soft-shadow samples never let more of
// its shadow be skipped (each feeler carries 1/n^2 of the light).
TEST(Analysis, MoreShadowSamplesNeverFadeTheShadow) {
  Scene scene = diffuse_scene();
  Light area;
  area.type = LightType::kArea;
  area.color = Color(0.4f);  // dim: a single feeler's share is far below the cutoff
  area.position = Vec3(0.0f, 0.0f, 3.0f);
  area.size[0] = area.size[1] = 2.0f;
  scene.remove_light("key");
  scene.remove_light("spot");
  for (int n : {1, 4, 8}) {
    area.samples = n;
    scene.set_light("area", area);
    const Result pruned = render(scene, true);
    const Result forced = render(scene, false);
    double worst = 0.0;
    for (size_t i = 0; i < pruned.pixels.size(); ++i) {
      worst = std::max(worst, std::fabs(double(pruned.pixels[i]) - forced.pixels[i]));
    }
    EXPECT_LE(worst, 1.0 / 255.0 + 1e-6) << n << "x" << n << " samples";
  }
}

TEST(Analysis, OneGlassObjectRefractsOnlyThroughIt) {
  Scene scene = diffuse_scene();
  Material glass;
  glass.diffuse = Color(0.0f);
  glass.transmissivity = Color(1.0f);
  add_object(&scene, "glass", quad(-0.2f, 0.2f, -0.2f, 0.2f, 2.0f), glass);
  const Result r = render(scene, true, 0.0f);
  // The glass square covers (0.4/6 / 1.2)^2 of the view at height 2 from the camera at 8:
  // only camera rays through it refract (two surfaces would be two; a quad is one).
  const double covered = std::pow(0.4 / 6.0 / (2.0 * 0.6), 2.0) * 48 * 48;
  EXPECT_NEAR(static_cast<double>(r.stats.rays.refraction), covered, 0.2 * covered + 8);
  EXPECT_GT(r.stats.rays.refraction, 0u);
}

TEST(Analysis, NothingToBlockMeansNoFeelers) {
  Scene scene;
  scene.set_mesh("floor", quad(-10, 10, -10, 10, 0));
  scene.set_material("white", diffuse(Color(0.8f)));
  scene.set_instance("floor", Instance{"floor",
                                       glm::mat4(1.0f),
                                       {"white"},
                                       kCameraRay | kReflectionRay | kRefractionRay,
                                       false});
  Light light;
  light.color = Color(5.0f);
  light.position = Vec3(0.0f, 0.0f, 3.0f);
  scene.set_light("key", light);
  scene.camera = looking_down(Vec3(0.0f, 0.0f, 8.0f), 0.6f);
  const Result r = render(scene, true);
  EXPECT_EQ(r.stats.rays.shadow, 0u);
  EXPECT_EQ(r.pixels, render(scene, false).pixels);
}

}  // namespace
}  // namespace whitted
