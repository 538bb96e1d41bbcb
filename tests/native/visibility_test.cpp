// Ray visibility, holdout, cut-outs (alpha), transparent film and the render border.
#include <gtest/gtest.h>

#include "integrator/render.h"
#include "scene_builders.h"

namespace whitted {
namespace {

using testing::add_object;
using testing::emitter;
using testing::looking_down;
using testing::quad;

// A lit floor, a square blocker above it and a point light above both.
Scene blocker_scene(uint32_t blocker_visibility, float blocker_alpha = 1.0f) {
  Scene scene;
  Material white;
  white.ambient = 0.0f;
  add_object(&scene, "floor", quad(-20, 20, -20, 20, 0), white);
  Material blocker = emitter(Color(5.0f));
  blocker.alpha = blocker_alpha;
  scene.set_mesh("blocker", quad(-1, 1, -1, 1, 1));
  scene.set_material("blocker", blocker);
  scene.set_instance("blocker",
                     Instance{"blocker", glm::mat4(1.0f), {"blocker"}, blocker_visibility, false});
  Light light;
  light.color = Color(10.0f);
  light.position = Vec3(0.0f, 0.0f, 4.0f);
  scene.set_light("light", light);
  return scene;
}

float radiance_down_at(const Scene& scene, float x, float* alpha = nullptr) {
  const auto compiled = scene.compile();
  const WhittedIntegrator integrator(*compiled, Settings{});
  RayCounts counts;
  Ray ray{Vec3(x, 0.0f, 3.0f), Vec3(0.0f, 0.0f, -1.0f), 0.0f, kInfinity, kCameraRay};
  return integrator.trace(ray, NodeState{}, &counts, alpha).x;
}

const float kLitFloor = 0.8f / kPi * 10.0f / 16.0f;  // kd/pi * I / r^2 under the light

TEST(Visibility, InvisibleToCameraStillCastsAShadow) {
  const Scene scene = blocker_scene(kShadowRay | kReflectionRay | kRefractionRay);
  EXPECT_EQ(radiance_down_at(scene, 0.0f), 0.0f);  // floor in shadow, blocker unseen
}

TEST(Visibility, InvisibleToShadowsIsSeenButCastsNone) {
  const Scene scene = blocker_scene(kCameraRay | kReflectionRay | kRefractionRay);
  EXPECT_FLOAT_EQ(radiance_down_at(scene, 0.0f), 5.0f);  // the blocker's emission
  Scene no_blocker_seen = blocker_scene(kReflectionRay);
  EXPECT_NEAR(radiance_down_at(no_blocker_seen, 0.0f), kLitFloor, 1e-6f);
}

TEST(Visibility, CutOutMixesWhatIsBehindAndLetsLightThrough) {
  const Scene scene = blocker_scene(kAllRayKinds, 0.25f);
  float alpha = 0.0f;
  // A quarter of the blocker's emission, three quarters of the floor lit through it.
  const float expected = 0.25f * 5.0f + 0.75f * (0.75f * kLitFloor);
  EXPECT_NEAR(radiance_down_at(scene, 0.0f, &alpha), expected, 1e-5f);
  EXPECT_FLOAT_EQ(alpha, 1.0f);
}

TEST(Visibility, HoldoutGivesZeroAndAlphaZero) {
  Scene scene = blocker_scene(kAllRayKinds);
  scene.set_instance("blocker",
                     Instance{"blocker", glm::mat4(1.0f), {"blocker"}, kAllRayKinds, true});
  float alpha = 1.0f;
  EXPECT_EQ(radiance_down_at(scene, 0.0f, &alpha), 0.0f);
  EXPECT_EQ(alpha, 0.0f);
  EXPECT_GT(radiance_down_at(scene, 5.0f, &alpha), 0.0f);
  EXPECT_EQ(alpha, 1.0f);
}

TEST(Visibility, TransparentFilmAndBorder) {
  Scene scene = blocker_scene(kAllRayKinds);
  scene.camera = looking_down(Vec3(0.0f, 0.0f, 10.0f), 4.0f);  // sees past the floor's edge
  Settings settings;
  settings.width = 20;
  settings.height = 10;
  settings.transparent_background = true;
  settings.border[0] = 5;
  settings.border[1] = 2;
  settings.border[2] = 12;
  settings.border[3] = 7;
  RenderJob job(scene, settings, scene.camera);
  testing::run_to_end(job);
  const std::vector<float>& px = job.film().pixels();
  for (int y = 0; y < 10; ++y) {
    for (int x = 0; x < 20; ++x) {
      const bool inside = x >= 5 && x < 12 && y >= 2 && y < 7;
      const float a = px[4 * (y * 20 + x) + 3];
      EXPECT_EQ(a, inside ? 1.0f : 0.0f) << x << "," << y;  // the floor covers the border
    }
  }
  EXPECT_EQ(job.stats().rays.camera, 35u);
  settings.border[2] = 30;
  EXPECT_THROW(RenderJob(scene, settings, scene.camera), std::invalid_argument);
}

}  // namespace
}  // namespace whitted
