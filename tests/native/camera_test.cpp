// The camera's thin lens (depth of field): a pinhole ignores the aperture sample; with an
// aperture every ray of a film point passes the point the pinhole ray meets on the plane
// in focus, leaves the camera's plane within the aperture, and the aperture's shapes
// (disc, polygon, anamorphic) keep their bounds and centre.
#include <gtest/gtest.h>

#include <cmath>
#include <tuple>

#include <glm/gtc/matrix_transform.hpp>

#include "integrator/render.h"
#include "scene/camera.h"
#include "scene_builders.h"

namespace whitted {
namespace {

Camera tilted_camera(float radius) {
  Camera camera;
  camera.to_world = glm::translate(glm::mat4(1.0f), Vec3(0.5f, -3.0f, 1.0f)) *
                    glm::rotate(glm::mat4(1.0f), 1.2f, Vec3(1.0f, 0.0f, 0.0f));
  camera.window[0] = -0.6f;
  camera.window[1] = 0.6f;
  camera.window[2] = -0.4f;
  camera.window[3] = 0.4f;
  camera.lens.radius = radius;
  camera.lens.focus_distance = 2.5f;
  return camera;
}

TEST(Camera, APinholeIgnoresTheApertureSample) {
  const Camera camera = tilted_camera(0.0f);
  const Ray a = camera.generate_ray(0.3f, 0.7f, glm::vec2(0.1f, 0.9f));
  const Ray b = camera.generate_ray(0.3f, 0.7f);
  EXPECT_EQ(a.origin, b.origin);
  EXPECT_EQ(a.direction, b.direction);
  EXPECT_EQ(a.t_min, b.t_min);
}

TEST(Camera, EveryRayOfAFilmPointMeetsThePinholeRayOnThePlaneInFocus) {
  for (const Projection projection : {Projection::kPerspective, Projection::kOrthographic}) {
    for (const int blades : {0, 6}) {
      Camera camera = tilted_camera(0.05f);
      camera.projection = projection;
      camera.lens.blades = blades;
      Camera pinhole = camera;
      pinhole.lens.radius = 0.0f;
      const Vec3 back = glm::normalize(Vec3(camera.to_world[2]));
      const Ray centre = pinhole.generate_ray(0.3f, 0.7f);
      // The pinhole ray at depth focus_distance along the view axis.
      const float t = camera.lens.focus_distance / glm::dot(centre.direction, -back);
      const Vec3 focus = centre.origin + t * centre.direction;
      for (int i = 0; i < 16; ++i) {
        const glm::vec2 u((i % 4 + 0.37f) / 4.0f, (i / 4 + 0.61f) / 4.0f);
        const Ray ray = camera.generate_ray(0.3f, 0.7f, u);
        EXPECT_NEAR(glm::length(ray.direction), 1.0f, 1e-6f);
        // It leaves the camera's plane within the aperture of the pinhole ray's origin,
        const Vec3 offset = ray.origin - centre.origin;
        EXPECT_NEAR(glm::dot(offset, back), 0.0f, 1e-6f);
        EXPECT_LE(glm::length(offset), camera.lens.radius * (1.0f + 1e-5f));
        // and passes the pinhole ray's point on the plane in focus.
        const float s = glm::dot(focus - ray.origin, ray.direction);
        EXPECT_LT(glm::length(ray.origin + s * ray.direction - focus), 1e-5f)
            << "blades " << blades;
        // Clip distances stay depths along the view axis.
        EXPECT_NEAR(glm::dot(ray.t_min * ray.direction, -back), camera.clip_start, 1e-5f);
      }
    }
  }
}

TEST(Camera, TheAperturesShapesKeepTheirBoundsAndCentre) {
  for (const int blades : {0, 3, 5, 8}) {
    for (const float ratio : {1.0f, 2.0f}) {
      Lens lens;
      lens.radius = 1.0f;
      lens.blades = blades;
      lens.rotation = 0.3f;
      lens.ratio = ratio;
      glm::dvec2 sum(0.0);
      const int n = 120;  // a multiple of every blade count: each triangle its share
      float widest = 0.0f;
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          const glm::vec2 p = lens.aperture_point({(i + 0.5f) / n, (j + 0.5f) / n});
          EXPECT_LE(glm::length(glm::vec2(p.x * ratio, p.y)), 1.0f + 1e-5f);
          widest = std::max(widest, std::fabs(p.x));
          sum += glm::dvec2(p);
        }
      }
      // Uniform over a shape symmetric about its centre: the mean is the centre.
      EXPECT_NEAR(sum.x / (n * n), 0.0, 2e-3) << blades;
      EXPECT_NEAR(sum.y / (n * n), 0.0, 2e-3) << blades;
      EXPECT_LE(widest, 1.0f / ratio + 1e-5f);  // anamorphic: narrower by the ratio
      EXPECT_GT(widest, 0.8f / ratio);
    }
  }
}

// Cycles places a polygon's corners half a step either side of the rotation: at rotation
// 0 a square aperture (4 blades) has upright edges, at x = +-cos(45 degrees) of its
// radius, and a triangle has an edge facing +x at x = cos(60 degrees) = 0.5.
TEST(Camera, ThePolygonFacesAsCyclesTurnsIt) {
  for (const auto [blades, edge, far] :
       {std::tuple{4, 0.70711f, 0.70711f}, std::tuple{3, 0.5f, 1.0f}}) {
    Lens lens;
    lens.radius = 1.0f;
    lens.blades = blades;
    float right = -1.0f;
    float left = 1.0f;
    const int n = 96;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j <= n; ++j) {
        const glm::vec2 p = lens.aperture_point({(i + 0.5f) / n, static_cast<float>(j) / n});
        right = std::max(right, p.x);
        left = std::min(left, p.x);
      }
    }
    EXPECT_NEAR(right, edge, 1e-2f) << blades;  // an edge faces +x (to the grid of samples)
    EXPECT_NEAR(-left, far, 1e-2f) << blades;   // a corner (triangle) or edge (square) -x
  }
}

// Lens samples come from a hash of the pixel and the sample: the same pixels on any
// thread count and tile size.
TEST(Camera, DepthOfFieldDependsOnNeitherThreadsNorTiles) {
  Scene scene = testing::occluder_over_floor(2.0f);
  scene.camera = testing::looking_down(Vec3(0.3f, 0.2f, 3.0f), 1.0f);
  scene.camera.lens.radius = 0.2f;
  scene.camera.lens.focus_distance = 1.5f;
  Settings settings;
  settings.width = 33;
  settings.height = 21;
  settings.aa_samples = 3;
  settings.threads = 1;
  settings.tile_size = 64;
  const std::vector<float> reference = testing::render_pixels(scene, settings);
  Scene pinhole = scene;
  pinhole.camera.lens.radius = 0.0f;
  EXPECT_FALSE(testing::render_pixels(pinhole, settings) == reference);
  for (auto [threads, tile] : {std::pair{2, 5}, std::pair{3, 16}}) {
    settings.threads = threads;
    settings.tile_size = tile;
    EXPECT_TRUE(testing::render_pixels(scene, settings) == reference) << threads;
  }
}

}  // namespace
}  // namespace whitted
