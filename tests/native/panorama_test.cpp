// Panoramic cameras: each projection's centre looks down the view axis, known image
// points map to known directions (Cycles' conventions: longitude grows to the right,
// latitude up), points outside a fisheye's circle have none (opaque black), the poles
// and the lens across the view axis stay finite, and panoramas render the same pixels on
// any threads and tiles.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include <glm/gtc/matrix_transform.hpp>

#include "core/math.h"
#include "integrator/render.h"
#include "scene/camera.h"
#include "scene/panorama.h"
#include "scene_builders.h"

namespace whitted {
namespace {

const Vec3 kForward(0.0f, 0.0f, -1.0f);
const Vec3 kUp(0.0f, 1.0f, 0.0f);
const Vec3 kLeft(-1.0f, 0.0f, 0.0f);

void expect_near(const Vec3& a, const Vec3& b) {
  EXPECT_NEAR(a.x, b.x, 1e-5f);
  EXPECT_NEAR(a.y, b.y, 1e-5f);
  EXPECT_NEAR(a.z, b.z, 1e-5f);
}

Vec3 direction(const Panorama& p, float u, float v) {
  Vec3 d(0.0f);
  EXPECT_TRUE(p.direction(u, v, &d)) << u << " " << v;
  EXPECT_NEAR(glm::length(d), 1.0f, 1e-5f);
  return d;
}

TEST(Panorama, EveryProjectionLooksDownTheViewAxisAtItsCentre) {
  for (PanoramaType type : {PanoramaType::kEquirectangular, PanoramaType::kEquiangularCubemapFace,
                            PanoramaType::kMirrorBall, PanoramaType::kFisheyeEquidistant,
                            PanoramaType::kFisheyeEquisolid, PanoramaType::kCentralCylindrical}) {
    Panorama p;
    p.type = type;
    expect_near(direction(p, 0.5f, 0.5f), kForward);
  }
}

TEST(Panorama, TheEquirectangularMapSpansLongitudeAndLatitude) {
  Panorama p;
  expect_near(direction(p, 0.25f, 0.5f), kLeft);  // longitude -90 degrees: left
  expect_near(direction(p, 0.75f, 0.5f), -kLeft);
  expect_near(direction(p, 0.0f, 0.5f), -kForward);  // the seam behind
  expect_near(direction(p, 0.3f, 1.0f), kUp);        // the whole top row: the pole
  expect_near(direction(p, 0.9f, 0.0f), -kUp);
  // Ranges: a quarter of longitude and the upper half of latitude.
  p.longitude_min = -0.25f * kPi;
  p.longitude_max = 0.25f * kPi;
  p.latitude_min = 0.0f;
  expect_near(direction(p, 0.5f, 0.0f), kForward);
  expect_near(direction(p, 0.0f, 0.0f), glm::normalize(kForward + kLeft));
}

TEST(Panorama, FisheyesMapTheirRadiusToTheAngleFromTheAxis) {
  Panorama p;
  p.type = PanoramaType::kFisheyeEquidistant;
  p.fisheye_fov = kPi;  // the rim is 90 degrees off the axis
  expect_near(direction(p, 1.0f, 0.5f), -kLeft);
  expect_near(direction(p, 0.5f, 1.0f), kUp);
  Vec3 d;
  EXPECT_FALSE(p.direction(0.99f, 0.99f, &d));  // outside the circle
  p.type = PanoramaType::kFisheyeEquisolid;
  p.fisheye_lens = 10.0f;
  p.fisheye_fov = kPi;
  p.sensor_width = p.sensor_height = 40.0f;
  // r = 2 f sin(theta / 2): 45 degrees at r = 20 sin(22.5 deg) mm from the centre.
  const float r = 20.0f * std::sin(kPi / 8.0f);
  const Vec3 at = direction(p, 0.5f, 0.5f + r / 40.0f);
  EXPECT_NEAR(std::acos(glm::dot(at, kForward)), 0.25f * kPi, 1e-5f);
  EXPECT_GT(at.y, 0.0f);
  EXPECT_FALSE(p.direction(0.5f, 0.5f + 20.0f * std::sin(kPi / 4.0f) / 40.0f + 0.01f, &d));
}

TEST(Panorama, TheMirrorBallShowsWhatIsBehindAtItsRim) {
  Panorama p;
  p.type = PanoramaType::kMirrorBall;
  Vec3 d;
  ASSERT_TRUE(p.direction(0.5f, 0.999f, &d));
  EXPECT_GT(glm::dot(d, -kForward), 0.9f);
  EXPECT_FALSE(p.direction(0.01f, 0.01f, &d));
}

TEST(Panorama, RaysOutsideTheProjectionSeeNothingAndThePolesStayFinite) {
  Camera camera;
  camera.projection = Projection::kPanoramic;
  camera.window[0] = camera.window[2] = 0.0f;
  camera.window[1] = camera.window[3] = 1.0f;
  camera.panorama.type = PanoramaType::kFisheyeEquidistant;
  EXPECT_EQ(camera.generate_ray(0.0f, 0.0f).kind, kNoRay);
  EXPECT_EQ(camera.generate_ray(0.5f, 0.5f).kind, kCameraRay);
  camera.panorama.type = PanoramaType::kEquirectangular;
  camera.lens.radius = 0.1f;
  camera.lens.focus_distance = 2.0f;
  // The centre (the lens's orienting axis itself) and the poles, every aperture corner.
  for (glm::vec2 point : {glm::vec2(0.5f), glm::vec2(0.3f, 1.0f), glm::vec2(0.7f, 0.0f)}) {
    for (glm::vec2 lens : {glm::vec2(0.0f), glm::vec2(1.0f), glm::vec2(0.2f, 0.9f)}) {
      const Ray ray = camera.generate_ray(point.x, point.y, lens);
      EXPECT_TRUE(is_finite(ray.origin) && is_finite(ray.direction));
      EXPECT_NEAR(glm::length(ray.direction), 1.0f, 1e-5f);
      EXPECT_LE(glm::length(ray.origin), 0.1f + 1e-6f);  // leaves the aperture
      // Every lens ray passes the pinhole ray's point at the focus distance.
      const Ray pinhole = camera.generate_ray(point.x, point.y, glm::vec2(0.5f));
      const Vec3 focus = pinhole.origin + 2.0f * pinhole.direction;
      const Vec3 to_focus = focus - ray.origin;
      EXPECT_NEAR(glm::length(glm::cross(to_focus, ray.direction)), 0.0f, 1e-5f);
    }
  }
}

TEST(Panorama, APanoramaDependsOnNeitherThreadsNorTiles) {
  Scene scene = testing::occluder_over_floor(2.0f);
  scene.camera = testing::looking_down(Vec3(0.3f, 0.2f, 3.0f), 1.0f);
  scene.camera.projection = Projection::kPanoramic;
  scene.camera.panorama.type = PanoramaType::kFisheyeEquisolid;
  scene.camera.window[0] = scene.camera.window[2] = 0.0f;
  scene.camera.window[1] = scene.camera.window[3] = 1.0f;
  scene.camera.lens.radius = 0.1f;
  scene.camera.lens.focus_distance = 2.5f;
  Settings settings;
  settings.width = 31;
  settings.height = 23;
  settings.aa_samples = 2;
  settings.threads = 1;
  settings.tile_size = 64;
  const std::vector<float> reference = testing::render_pixels(scene, settings);
  for (auto [threads, tile] : {std::pair{2, 5}, std::pair{3, 16}}) {
    settings.threads = threads;
    settings.tile_size = tile;
    EXPECT_TRUE(testing::render_pixels(scene, settings) == reference) << threads;
  }
}

TEST(Panorama, EveryImagePointComesBackFromItsDirection) {
  for (PanoramaType type : {PanoramaType::kEquirectangular, PanoramaType::kEquiangularCubemapFace,
                            PanoramaType::kMirrorBall, PanoramaType::kFisheyeEquidistant,
                            PanoramaType::kFisheyeEquisolid, PanoramaType::kFisheyeLensPolynomial,
                            PanoramaType::kCentralCylindrical}) {
    Panorama p;
    p.type = type;
    p.fisheye_fov = 3.0f;
    // Blender's default polynomial fisheye (a real lens's fit), radius in mm.
    const float k[5] = {-1.1735e-5f, -0.019588f, 1.0018e-5f, -2.7814e-6f, 0.0f};
    std::copy(k, k + 5, p.polynomial);
    for (glm::vec2 uv : {glm::vec2(0.3f, 0.6f), glm::vec2(0.55f, 0.45f), glm::vec2(0.7f, 0.2f)}) {
      Vec3 d;
      if (!p.direction(uv.x, uv.y, &d)) continue;  // outside a fisheye's circle
      const glm::vec2 back = p.image_point(d);
      EXPECT_NEAR(back.x, uv.x, 2e-4f) << static_cast<int>(type);
      EXPECT_NEAR(back.y, uv.y, 2e-4f) << static_cast<int>(type);
    }
  }
}

TEST(Permuted, IsAPermutationForEveryCountAndSeed) {
  for (uint32_t count : {1u, 2u, 3u, 4u, 9u, 16u, 25u, 100u, 255u, 256u, 257u}) {
    for (uint32_t seed : {0u, 1u, 77u, 0xdeadbeefu}) {
      std::set<uint32_t> seen;
      for (uint32_t i = 0; i < count; ++i) {
        const uint32_t p = permuted(i, count, seed);
        EXPECT_LT(p, count);
        seen.insert(p);
      }
      EXPECT_EQ(seen.size(), count) << count << " " << seed;
    }
  }
  // Different seeds give different orders (what decorrelates the lens from the pixel).
  int differ = 0;
  for (uint32_t i = 0; i < 16; ++i) differ += permuted(i, 16, 1) != permuted(i, 16, 2);
  EXPECT_GT(differ, 4);
}

}  // namespace
}  // namespace whitted
