// The shadow catcher (integrator/catcher.h) against analytic values: a floor that catches
// shadows under a point lamp and a blocker of known coverage (a cut-out of alpha a lets
// 1 - a of the lamp through): the light left on the catcher is 1 - a, its alpha over a
// transparent film a, over an opaque one the world behind it times 1 - a.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <vector>

#include "integrator/analysis.h"
#include "integrator/render.h"
#include "scene_builders.h"

namespace whitted {
namespace {

using testing::add_object;
using testing::looking_down;
using testing::quad;

const Color kWorld(0.2f, 0.4f, 0.6f);

// A white floor at z = 0 (a catcher when `catcher`), a square blocker of alpha
// `blocker_alpha` at z = 1 unseen by the camera (its shadow is the square |x|,|y| < 4/3),
// a point lamp at z = 4 and the world kWorld.
Scene catcher_scene(bool catcher, float blocker_alpha, bool blocker_catches = false) {
  Scene scene;
  Material white;
  white.ambient = 0.0f;
  scene.set_mesh("floor", quad(-20, 20, -20, 20, 0));
  scene.set_material("floor", white);
  Instance floor{"floor", glm::mat4(1.0f), {"floor"}};
  floor.shadow_catcher = catcher;
  scene.set_instance("floor", floor);
  Material blocker = white;
  blocker.alpha = blocker_alpha;
  scene.set_mesh("blocker", quad(-1, 1, -1, 1, 1));
  scene.set_material("blocker", blocker);
  Instance over{"blocker", glm::mat4(1.0f), {"blocker"}, kShadowRay | kReflectionRay};
  over.shadow_catcher = blocker_catches;
  scene.set_instance("blocker", over);
  Light light;
  light.color = Color(10.0f);
  light.position = Vec3(0.0f, 0.0f, 4.0f);
  scene.set_light("light", light);
  scene.set_background(kWorld);
  return scene;
}

struct Traced {
  Color radiance;
  float alpha;
};

// A ray of `kind` straight down at (x, 0) from z = 3.
Traced down_at(const Scene& scene, float x, bool transparent, uint32_t kind = kCameraRay) {
  const auto compiled = scene.compile();
  Settings settings;
  settings.transparent_background = transparent;
  const WhittedIntegrator integrator(*compiled, settings);
  RayCounts counts;
  const Ray ray{Vec3(x, 0.0f, 3.0f), Vec3(0.0f, 0.0f, -1.0f), 0.0f, kInfinity, kind};
  Traced out{Color(0.0f), 1.0f};
  out.radiance = integrator.trace(ray, NodeState{}, &counts, &out.alpha);
  return out;
}

TEST(Catcher, ItsAlphaIsTheShadowsStrengthOverATransparentFilm) {
  for (float a : {1.0f, 0.75f, 0.25f}) {
    const Scene scene = catcher_scene(true, a);
    const Traced shadowed = down_at(scene, 0.0f, true);
    EXPECT_NEAR(shadowed.alpha, a, 1e-6f) << a;
    EXPECT_EQ(shadowed.radiance, Color(0.0f)) << a;
    const Traced lit = down_at(scene, 5.0f, true);  // outside the shadow
    EXPECT_EQ(lit.alpha, 0.0f) << a;
    EXPECT_EQ(lit.radiance, Color(0.0f)) << a;
  }
}

TEST(Catcher, OverAnOpaqueFilmItShowsTheWorldTimesTheLightLeft) {
  for (float a : {1.0f, 0.75f, 0.25f}) {
    const Scene scene = catcher_scene(true, a);
    const Traced shadowed = down_at(scene, 0.0f, false);
    EXPECT_EQ(shadowed.alpha, 1.0f);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(shadowed.radiance[c], kWorld[c] * (1.0f - a), 1e-6f);
    const Traced lit = down_at(scene, 5.0f, false);
    EXPECT_EQ(lit.alpha, 1.0f);
    EXPECT_EQ(lit.radiance, kWorld);
  }
}

TEST(Catcher, OtherRaysSeeItAsAnOrdinaryObject) {
  // A mirror's ray (any ray but the camera's) sees the floor shaded, shadow and all.
  const Scene catching = catcher_scene(true, 0.25f);
  const Scene ordinary = catcher_scene(false, 0.25f);
  for (float x : {0.0f, 5.0f}) {
    const Traced seen = down_at(catching, x, true, kReflectionRay);
    const Traced plain = down_at(ordinary, x, true, kReflectionRay);
    EXPECT_EQ(seen.radiance, plain.radiance) << x;
    EXPECT_GT(seen.radiance.x, 0.0f);
  }
  // And the camera sees an ordinary floor where nothing is a catcher.
  const Traced plain = down_at(ordinary, 0.0f, true);
  EXPECT_NEAR(plain.radiance.x, 0.8f / kPi * 10.0f / 16.0f * 0.75f, 1e-6f);
  EXPECT_EQ(plain.alpha, 1.0f);
}

TEST(Catcher, ACatchersShadowOnACatcherIsNoShadow) {
  // Cycles' second path sees the catchers alone: what they cast on each other is in
  // both of its sums, so no shadow shows.
  const Scene scene = catcher_scene(true, 1.0f, /*blocker_catches=*/true);
  const Traced under = down_at(scene, 0.0f, true);
  EXPECT_EQ(under.alpha, 0.0f);
}

TEST(Catcher, WavesAndTheRecursionRenderItAlike) {
  Scene scene = catcher_scene(true, 0.5f);
  scene.camera = looking_down(Vec3(0.0f, 0.0f, 5.0f), 3.0f);
  Settings settings = testing::small_render(24, 24, 2, 2, 8);
  settings.transparent_background = true;
  settings.waves = true;
  const std::vector<float> waves = testing::render_pixels(scene, settings);
  settings.waves = false;
  const std::vector<float> recursion = testing::render_pixels(scene, settings);
  EXPECT_EQ(waves, recursion);
  // Inside the shadow (the square |x|,|y| < 4/3 of the 6 x 6 window) alpha is 0.5.
  EXPECT_NEAR(waves[4 * (12 * 24 + 12) + 3], 0.5f, 1e-6f);
  EXPECT_EQ(waves[4 * (1 * 24 + 1) + 3], 0.0f);
}

// A render of the catcher scene from above, 24 x 24 over a 6 x 6 window (the shadow the
// square |x|,|y| < 4/3), with the Shadow Catcher pass kept.
std::unique_ptr<RenderJob> caught_render(float blocker_alpha, bool transparent,
                                         bool waves = false) {
  Scene scene = catcher_scene(true, blocker_alpha);
  scene.camera = looking_down(Vec3(0.0f, 0.0f, 5.0f), 3.0f);
  Settings settings = testing::small_render(24, 24, 2, 2, 8);
  settings.transparent_background = transparent;
  settings.waves = waves;
  settings.passes = pass_bit(FilmPass::kShadowCatcher);
  auto job = std::make_unique<RenderJob>(scene, settings, scene.camera);
  testing::run_to_end(*job);
  return job;
}

TEST(Catcher, ThePassIsTheLightLeftAndCombinedLeavesTheCatcherOut) {
  for (const bool transparent : {true, false}) {
    for (float a : {1.0f, 0.75f, 0.25f}) {
      const auto job = caught_render(a, transparent);
      const std::vector<float>& pass = job->film().pass(FilmPass::kShadowCatcher);
      const std::vector<float>& pixels = job->film().pixels();
      for (const size_t pixel : {size_t{12 * 24 + 12}, size_t{1 * 24 + 1}}) {
        const bool shadowed = pixel == 12 * 24 + 12;
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(pass[3 * pixel + c], shadowed ? 1.0f - a : 1.0f, 1e-6f) << a;
        }
        // Black and transparent over either film, as Cycles' Combined with the pass.
        for (int c = 0; c < 4; ++c) EXPECT_EQ(pixels[4 * pixel + c], 0.0f) << a;
      }
    }
  }
}

TEST(Catcher, ThePassIsTheSameInWavesAndTheRecursion) {
  const auto waves = caught_render(0.5f, true, true);
  const auto recursion = caught_render(0.5f, true, false);
  EXPECT_TRUE(waves->film().pass(FilmPass::kShadowCatcher) ==
              recursion->film().pass(FilmPass::kShadowCatcher));
  EXPECT_TRUE(waves->film().pixels() == recursion->film().pixels());
}

TEST(Catcher, ThePassOfAProgressiveRenderIsTheWholeRenders) {
  // The film sums the pass's seven floats sample by sample (Film::add) or takes a
  // pixel's mean record (Film::set): the same pass.
  Scene scene = catcher_scene(true, 0.5f);
  scene.camera = looking_down(Vec3(0.0f, 0.0f, 5.0f), 3.0f);
  Settings settings = testing::small_render(24, 24, 2, 2, 8);
  settings.passes = pass_bit(FilmPass::kShadowCatcher);
  RenderJob whole(scene, settings, scene.camera);
  testing::run_to_end(whole);
  settings.progressive = true;
  settings.packets = false;
  RenderJob progressive(scene, settings, scene.camera);
  testing::run_to_end(progressive);
  const std::vector<float>& a = whole.film().pass(FilmPass::kShadowCatcher);
  const std::vector<float>& b = progressive.film().pass(FilmPass::kShadowCatcher);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) ASSERT_NEAR(a[i], b[i], 1e-5f) << i;
  EXPECT_NEAR(b[3 * (12 * 24 + 12)], 0.5f, 1e-6f);
}

TEST(Catcher, TheAnalysisNamesIt) {
  const auto with = catcher_scene(true, 1.0f).compile();
  Settings settings;
  const Effects on = analyse(*with, settings);
  EXPECT_TRUE(on.has(kCatcherEffect));
  const auto without = catcher_scene(false, 1.0f).compile();
  const Effects off = analyse(*without, settings);
  EXPECT_FALSE(off.has(kCatcherEffect));
  const EffectDecision none{"shadow catcher", false, "no object is a shadow catcher"};
  EXPECT_NE(std::find(off.decisions.begin(), off.decisions.end(), none), off.decisions.end());
  settings.passes = pass_bit(FilmPass::kShadowCatcher);
  const Effects pass = analyse(*with, settings);
  const EffectDecision named{"shadow catcher", true,
                             "1 object: Combined leaves it out, the Shadow Catcher pass holds "
                             "the shadows cast on it"};
  EXPECT_NE(std::find(pass.decisions.begin(), pass.decisions.end(), named), pass.decisions.end());
}

}  // namespace
}  // namespace whitted
