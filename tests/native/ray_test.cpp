// The ray-origin offset: rays leaving a surface never re-hit it, at any scale.
#include "core/ray.h"

#include <gtest/gtest.h>

#include <random>

#include "accel/embree.h"
#include "scene_builders.h"

namespace whitted {
namespace {

TEST(Ray, OffsetMovesToTheRequestedSideAtEveryMagnitude) {
  for (float magnitude : {0.0f, 1e-8f, 1e-3f, 1.0f, 1e3f, 1e8f}) {
    const Vec3 p(magnitude, -magnitude, 0.5f * magnitude);
    const Vec3 n = glm::normalize(Vec3(1.0f, 2.0f, -3.0f));
    const Vec3 q = offset_ray_origin(p, n);
    EXPECT_GT(glm::dot(q - p, n), 0.0f) << magnitude;
    EXPECT_LT(glm::dot(offset_ray_origin(p, -n) - p, n), 0.0f) << magnitude;
    // A few hundred ulps: small against the point's own magnitude.
    EXPECT_LT(glm::length(q - p), 1e-4f * std::max(magnitude, 1.0f)) << magnitude;
  }
}

// Random triangles at magnitudes 1e-4..1e5: rays spawned from a hit point in the
// reflection, refraction (through) and shadow directions never hit their own triangle.
TEST(Ray, SpawnedRaysNeverReHitTheirOwnTriangle) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  auto device = std::make_shared<AccelDevice>();
  int self_hits = 0;
  int rays = 0;
  for (float scale : {1e-4f, 1e-2f, 1.0f, 1e2f, 1e5f}) {
    for (int trial = 0; trial < 200; ++trial) {
      const Vec3 centre = scale * Vec3(unit(rng), unit(rng), unit(rng)) * 10.0f;
      float p[9];
      for (float& c : p) c = 0.0f;
      for (int v = 0; v < 3; ++v) {
        for (int k = 0; k < 3; ++k) p[3 * v + k] = centre[k] + scale * unit(rng);
      }
      const uint32_t t[] = {0, 1, 2};
      const Mesh mesh = make_mesh(p, 3, t, 1, nullptr, nullptr);
      const MeshAccel blas(device, mesh);
      const SceneAccel tlas(device, {{&blas, glm::mat4(1.0f), kAllRayKinds}});
      const Vec3 a = mesh.vertex(0), b = mesh.vertex(1), c = mesh.vertex(2);
      Vec3 ng = glm::cross(b - a, c - a);
      if (!(glm::length(ng) > 0.0f)) continue;
      ng = glm::normalize(ng);
      // A ray from outside towards a random interior point.
      float w1 = 0.5f * (unit(rng) + 1.0f), w2 = 0.5f * (unit(rng) + 1.0f);
      if (w1 + w2 > 1.0f) {
        w1 = 1.0f - w1;
        w2 = 1.0f - w2;
      }
      const Vec3 target = a + w1 * (b - a) + w2 * (c - a);
      const Vec3 origin = target + scale * ng + scale * 0.3f * Vec3(unit(rng), unit(rng), 0.0f);
      Ray ray{origin, glm::normalize(target - origin), 0.0f, kInfinity};
      Hit hit;
      if (!tlas.intersect(ray, &hit)) continue;
      const Vec3 x = (1.0f - hit.u - hit.v) * a + hit.u * b + hit.v * c;
      const Vec3 facing = glm::dot(ray.direction, ng) < 0.0f ? ng : -ng;
      const Vec3 reflected = reflect(ray.direction, facing);
      Vec3 light_dir = glm::normalize(facing + 0.9f * Vec3(unit(rng), unit(rng), unit(rng)));
      if (glm::dot(light_dir, facing) <= 0.0f) light_dir = facing;
      for (const Vec3& d : {reflected, ray.direction, light_dir}) {
        Hit again;
        ++rays;
        if (tlas.intersect(spawn_ray(x, ng, d, kReflectionRay), &again)) ++self_hits;
      }
    }
  }
  EXPECT_GT(rays, 2000);
  EXPECT_EQ(self_hits, 0);
}

}  // namespace
}  // namespace whitted
