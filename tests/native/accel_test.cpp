// Packet queries answer exactly as single-ray ones: the integrator traces shadow feelers
// in packets and its images must not depend on it.
#include "accel/embree.h"

#include <gtest/gtest.h>

#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "scene_builders.h"

namespace whitted {
namespace {

// A 2 x 2 square at z = 1 seen by shadow rays, and one beside it at x in [3, 5] seen only
// by camera rays; rays leave the plane z = 0 upwards. A ray is blocked exactly when it
// crosses z = 1 inside the first square before its t_max. Origins and targets keep away
// from the squares' edges, so the analytic answer is never a tie.
TEST(Accel, OcclusionPacketsAnswerAsSingleRays) {
  auto device = std::make_shared<AccelDevice>();
  const Mesh shadow_square = testing::quad(-1.0f, 1.0f, -1.0f, 1.0f, 1.0f);
  const Mesh camera_square = testing::quad(3.0f, 5.0f, -1.0f, 1.0f, 1.0f);
  const SceneAccel accel(
      device,
      {{std::make_shared<const MeshAccel>(device, shadow_square), glm::mat4(1.0f), kAllRayKinds},
       {std::make_shared<const MeshAccel>(device, camera_square), glm::mat4(1.0f), kCameraRay}});
  std::mt19937 rng(15);
  // Crossing points of z = 1 on a grid of cells, each offset from its cell's edges.
  std::uniform_int_distribution<int> cell_x(-4, 9);  // x from -2 to 5: both squares
  std::uniform_int_distribution<int> cell_y(-3, 2);  // y from -1.5 to 1.5
  std::uniform_real_distribution<float> inside(0.1f, 0.4f);
  std::uniform_real_distribution<float> origin(-3.0f, 6.0f);
  const auto crossing = [&](std::uniform_int_distribution<int>& cell) {
    return 0.5f * static_cast<float>(cell(rng)) + inside(rng);
  };
  int blocked_count = 0;
  int checked = 0;
  for (int round = 0; round < 400; ++round) {
    const int count = 1 + round % SceneAccel::kPacketSize;
    std::vector<Ray> rays(static_cast<size_t>(count));
    std::vector<uint8_t> expected(static_cast<size_t>(count));
    for (int i = 0; i < count; ++i) {
      const Vec3 from(origin(rng), origin(rng), 0.0f);
      const Vec3 through(crossing(cell_x), crossing(cell_y), 1.0f);
      const Vec3 d = glm::normalize(through - from);
      const float to_plane = 1.0f / d.z;
      // Half the feelers stop short of the plane; one in eight is a sun's, unbounded.
      const float t_max = i % 8 == 7 ? kInfinity : to_plane * (i % 2 == 0 ? 0.8f : 1.6f);
      const RayKind kind = i % 3 == 0 ? kCameraRay : kShadowRay;
      rays[static_cast<size_t>(i)] = Ray{from, d, 0.0f, t_max, kind};
      const bool in_square = std::abs(through.x) < 1.0f && std::abs(through.y) < 1.0f;
      const bool in_camera_square =
          through.x > 3.0f && through.x < 5.0f && std::abs(through.y) < 1.0f && kind == kCameraRay;
      expected[static_cast<size_t>(i)] = (in_square || in_camera_square) && to_plane < t_max;
    }
    // A ray Embree cannot take is unblocked either way (SceneAccel::occluded).
    if (round % 5 == 0) rays[0].origin.x = std::numeric_limits<float>::quiet_NaN();
    if (round % 5 == 0) expected[0] = 0;
    bool blocked[SceneAccel::kPacketSize];
    accel.occluded_packet(rays.data(), count, blocked);
    for (int i = 0; i < count; ++i) {
      const auto k = static_cast<size_t>(i);
      EXPECT_EQ(blocked[i], accel.occluded(rays[k])) << "round " << round << " lane " << i;
      EXPECT_EQ(blocked[i], expected[k] != 0) << "round " << round << " lane " << i;
      blocked_count += blocked[i] ? 1 : 0;
      ++checked;
    }
  }
  // Both answers are exercised.
  EXPECT_GT(blocked_count, checked / 10);
  EXPECT_LT(blocked_count, checked / 2);
}

}  // namespace
}  // namespace whitted
