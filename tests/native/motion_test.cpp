// Motion blur: a transform's motion over the shutter (TransformMotion) starts and ends at
// its samples, turns without shrinking, and blends as Embree does; a moving object
// is seen over the shutter; nothing moving (or a zero-length motion) gives
// the still frame's pixels; tiles and threads change nothing.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "integrator/render.h"
#include "scene/motion.h"
#include "scene_builders.h"

namespace whitted {
namespace {

glm::mat4 turned(float angle, Vec3 at) {
  return glm::rotate(glm::translate(glm::mat4(1.0f), at), angle, Vec3(0.0f, 0.0f, 1.0f));
}

TEST(TransformMotion, StartsAndEndsAtItsSamplesAndTurnsWithoutShrinking) {
  const TransformMotion motion({turned(0.0f, Vec3(0.0f)), turned(1.5f, Vec3(2.0f, 0.0f, 0.0f))});
  EXPECT_TRUE(motion.moves());
  EXPECT_GT(motion.steps().size(), 20u);  // 86 degrees in steps of at most 4
  EXPECT_EQ(motion.at(0.0f), turned(0.0f, Vec3(0.0f)));
  EXPECT_EQ(motion.at(1.0f), turned(1.5f, Vec3(2.0f, 0.0f, 0.0f)));
  for (float t = 0.0f; t <= 1.0f; t += 0.013f) {
    const glm::mat4 m = motion.at(t);
    // Half way between steps the linear blend shrinks by 1 - cos(2 degrees) at most.
    EXPECT_NEAR(glm::length(Vec3(m[0])), 1.0f, 7e-4f) << t;
    EXPECT_NEAR(m[3].x, 2.0f * t, 1e-5f) << t;  // the translation blends linearly
    const float angle = std::atan2(m[0].y, m[0].x);
    EXPECT_NEAR(angle, 1.5f * t, 2e-3f) << t;  // the rotation along its arc
  }
}

TEST(TransformMotion, StillSamplesMakeNoMotion) {
  const glm::mat4 m = turned(0.3f, Vec3(1.0f, 2.0f, 3.0f));
  const TransformMotion still({m, m, m});
  EXPECT_FALSE(still.moves());
  EXPECT_EQ(still.steps().size(), 1u);
  EXPECT_EQ(still.at(0.7f), m);
}

Scene moving_blocker(const std::vector<glm::mat4>& motion) {
  Scene scene = testing::occluder_over_floor(2.0f);
  Instance blocker{"blocker", glm::mat4(1.0f), {"blocker"}};
  blocker.motion = motion;
  scene.set_instance("blocker", blocker);
  return scene;
}

Settings small(int threads, int tile) {
  Settings settings;
  settings.width = 29;
  settings.height = 23;
  settings.aa_samples = 3;
  settings.threads = threads;
  settings.tile_size = tile;
  return settings;
}

TEST(MotionBlur, NothingMovingGivesTheStillFramesPixels) {
  const std::vector<float> still = testing::render_pixels(moving_blocker({}), small(1, 64));
  const glm::mat4 at_rest(1.0f);
  EXPECT_TRUE(testing::render_pixels(moving_blocker({at_rest, at_rest, at_rest}), small(1, 64)) ==
              still);
}

TEST(MotionBlur, AMovingBlockerSpreadsItsShadowAndTilesAndThreadsChangeNothing) {
  const glm::mat4 away = glm::translate(glm::mat4(1.0f), Vec3(1.5f, 0.0f, 0.0f));
  const Scene scene = moving_blocker({glm::mat4(1.0f), away});
  const std::vector<float> still = testing::render_pixels(moving_blocker({}), small(1, 64));
  const std::vector<float> reference = testing::render_pixels(scene, small(1, 64));
  EXPECT_FALSE(reference == still);
  // The blocker (near the light, bright) covers the centre pixel at the shutter's
  // opening only; later the camera sees the floor there: a blend of the two, darker.
  const size_t centre = 4 * (11 * 29 + 14);
  EXPECT_LT(reference[centre], 0.9f * still[centre]);
  EXPECT_GT(reference[centre], 0.1f * still[centre]);
  for (auto [threads, tile] : {std::pair{2, 5}, std::pair{3, 16}}) {
    EXPECT_TRUE(testing::render_pixels(scene, small(threads, tile)) == reference) << threads;
  }
}

TEST(MotionBlur, AnObjectMovingThousandsOfUnitsStaysFinite) {
  const glm::mat4 far = glm::translate(glm::mat4(1.0f), Vec3(5000.0f, 0.0f, 0.0f));
  const std::vector<float> pixels =
      testing::render_pixels(moving_blocker({glm::mat4(1.0f), far}), small(2, 16));
  for (float v : pixels) ASSERT_TRUE(std::isfinite(v));
}

TEST(MotionBlur, AMovingCameraSweepsTheImage) {
  Scene scene = testing::occluder_over_floor(2.0f);
  const std::vector<float> still = testing::render_pixels(scene, small(1, 64));
  const glm::mat4 from = scene.camera.to_world;
  const glm::mat4 to = glm::translate(glm::mat4(1.0f), Vec3(1.0f, 0.0f, 0.0f)) * from;
  scene.camera.motion = std::make_shared<const TransformMotion>(std::vector<glm::mat4>{from, to});
  const std::vector<float> swept = testing::render_pixels(scene, small(1, 64));
  EXPECT_FALSE(swept == still);
  EXPECT_TRUE(testing::render_pixels(scene, small(2, 7)) == swept);
}

TEST(MotionBlur, ADeformingMeshIsSeenWhereTheRaysTimePutsIt) {
  Scene scene = testing::occluder_over_floor(2.0f);
  Mesh blocker = testing::quad(-0.5f, 0.5f, -0.5f, 0.5f, 1.0f);
  std::vector<float> moved = blocker.positions;
  for (size_t v = 0; v < blocker.vertex_count(); ++v) moved[3 * v] += 1.5f;  // along X
  const std::vector<float> still = testing::render_pixels(scene, small(1, 64));
  blocker.motion_positions = {blocker.positions, moved};
  scene.set_mesh("blocker", blocker);
  const std::vector<float> swept = testing::render_pixels(scene, small(1, 64));
  EXPECT_FALSE(swept == still);
  // The same as the blocker moved by its transform instead: the same surfaces at the
  // same times (to float rounding in the blends).
  const std::vector<float> moved_instance = testing::render_pixels(
      moving_blocker({glm::mat4(1.0f), glm::translate(glm::mat4(1.0f), Vec3(1.5f, 0.0f, 0.0f))}),
      small(1, 64));
  double largest = 0.0;
  for (size_t i = 0; i < swept.size(); ++i) {
    largest = std::max(largest, static_cast<double>(std::fabs(swept[i] - moved_instance[i])));
  }
  EXPECT_LT(largest, 1e-3);
  EXPECT_TRUE(testing::render_pixels(scene, small(3, 5)) == swept);
}

}  // namespace
}  // namespace whitted
