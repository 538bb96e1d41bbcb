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

TEST(Shutter, ABoxOrAFlatCurveDrawsEveryTimeAlike) {
  for (const Shutter& box : {Shutter(), Shutter({1.0f, 1.0f, 1.0f}, -1.0f),
                             Shutter({0.0f, 0.0f}, -1.0f), Shutter({2.0f}, -1.0f)}) {
    EXPECT_TRUE(box.box());
    for (float u : {0.0f, 0.3f, 0.999f}) EXPECT_EQ(box.time(u, 5, 10), u);
  }
}

TEST(Shutter, ACurveDrawsTimesInProportionToItsOpening) {
  // Opening linearly from shut to open: the cumulative opening is t^2, so the time of a
  // uniform u is sqrt(u).
  std::vector<float> ramp(256);
  for (size_t i = 0; i < ramp.size(); ++i) ramp[i] = static_cast<float>(i) / 255.0f;
  const Shutter opening(ramp, -1.0f);
  EXPECT_FALSE(opening.box());
  for (float u = 0.0f; u < 1.0f; u += 0.01f) {
    EXPECT_NEAR(opening.time(u, 0, 1), std::sqrt(u), 2e-3f) << u;
  }
  // Shut for the first half: no time is drawn there.
  const Shutter late({0.0f, 0.0f, 0.0f, 1.0f, 1.0f}, -1.0f);
  EXPECT_GE(late.time(0.0f, 0, 1), 0.5f);
  EXPECT_NEAR(late.time(0.5f, 0, 1), 0.8125f, 1e-6f);  // half of the open area is past 0.8125
}

TEST(Shutter, ARollingShutterReadsRowsFromTheTop) {
  const Shutter rolling({}, 0.0f);
  EXPECT_TRUE(rolling.rolling());
  // Row 0 is the bottom of 10 rows: read last; the top row first; u plays no part.
  EXPECT_NEAR(rolling.time(0.2f, 0, 10), 1.0f, 1e-6f);
  EXPECT_NEAR(rolling.time(0.7f, 9, 10), 0.1f, 1e-6f);
  // A Duration of 1 keeps the whole blur: every row over the whole shutter.
  EXPECT_NEAR(Shutter({}, 1.0f).time(0.3f, 0, 10), 0.3f, 1e-6f);
  // Between: (u - 0.5) d + (read - 0.5) (1 - d) + 0.5, as Cycles blends them.
  EXPECT_NEAR(Shutter({}, 0.25f).time(0.9f, 5, 10), 0.4f * 0.25f + 0.0f + 0.5f, 1e-6f);
}

Scene moving_blocker(const std::vector<glm::mat4>& motion) {
  Scene scene = testing::occluder_over_floor(2.0f);
  Instance blocker{"blocker", glm::mat4(1.0f), {"blocker"}};
  blocker.motion = motion;
  scene.set_instance("blocker", blocker);
  return scene;
}

Settings small(int threads, int tile) {
  return testing::small_render(29, 23, 3, threads, tile);
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
