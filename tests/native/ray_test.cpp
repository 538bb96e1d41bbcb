// The ray-origin offset: rays leaving a surface never re-hit it, at any scale.
#include "core/ray.h"

#include <gtest/gtest.h>

#include <bit>
#include <random>
#include <vector>

#include "accel/embree.h"
#include "scene_builders.h"

namespace whitted {
namespace {

TEST(Ray, OffsetMovesToTheRequestedSideByItsErrorBound) {
  for (float magnitude : {0.0f, 1e-8f, 1e-3f, 1.0f, 1e3f, 1e8f}) {
    const Vec3 p(magnitude, -magnitude, 0.5f * magnitude);
    const Vec3 error = gamma(7) * glm::abs(p) + Vec3(1e-30f);
    const Vec3 n = glm::normalize(Vec3(1.0f, 2.0f, -3.0f));
    const Vec3 q = offset_ray_origin(p, error, n);
    EXPECT_GT(glm::dot(q - p, n), 0.0f) << magnitude;
    EXPECT_LT(glm::dot(offset_ray_origin(p, error, -n) - p, n), 0.0f) << magnitude;
    // A few ulps: small against the point's own magnitude (or tiny near zero).
    EXPECT_LE(glm::length(q - p), 1e-5f * magnitude + 1e-29f) << magnitude;
  }
}

// The origin's one-float step is std::nextafter's, without the library call.
TEST(Ray, NextFloatStepsAsNextafter) {
  const auto same = [](float a, float b) {
    return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b) ||
           (std::isnan(a) && std::isnan(b));
  };
  using limits = std::numeric_limits<float>;
  std::vector<float> xs = {0.0f,          1.0f,          limits::denorm_min(),
                           limits::min(), limits::max(), kInfinity};
  for (size_t i = 0, n = xs.size(); i < n; ++i) xs.push_back(-xs[i]);
  xs.push_back(limits::quiet_NaN());
  std::mt19937 rng(15);
  for (int i = 0; i < 100000; ++i) xs.push_back(std::bit_cast<float>(static_cast<uint32_t>(rng())));
  for (float x : xs) {
    EXPECT_TRUE(same(next_float_up(x), std::nextafter(x, kInfinity))) << x;
    EXPECT_TRUE(same(next_float_down(x), std::nextafter(x, -kInfinity))) << x;
  }
}

// Thousands of random triangles at magnitudes 1e-8..1e8 (pbrt-v4's test in spirit): rays
// spawned from a hit point in the reflection, refraction (straight through) and shadow
// directions never hit their own triangle again.
TEST(Ray, SpawnedRaysNeverReHitTheirOwnTriangle) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  auto device = std::make_shared<AccelDevice>();
  int self_hits = 0;
  int rays = 0;
  constexpr int kTriangles = 300;
  for (float scale = 1e-8f; scale <= 1.5e8f; scale *= 10.0f) {
    std::vector<float> p;
    std::vector<uint32_t> t;
    for (int i = 0; i < kTriangles; ++i) {
      // Triangles of size ~scale, scattered over ~100 * scale around an offset centre.
      const Vec3 centre = scale * (Vec3(unit(rng), unit(rng), unit(rng)) * 100.0f);
      for (int v = 0; v < 3; ++v) {
        for (int k = 0; k < 3; ++k) p.push_back(centre[k] + scale * unit(rng));
        t.push_back(static_cast<uint32_t>(3 * i + v));
      }
    }
    const Mesh mesh = make_mesh(p.data(), p.size() / 3, t.data(), kTriangles, nullptr, nullptr);
    const auto blas = std::make_shared<const MeshAccel>(device, mesh);
    const SceneAccel tlas(device, {{blas, glm::mat4(1.0f), kAllRayKinds}});
    for (uint32_t i = 0; i < kTriangles; ++i) {
      const Vec3 a = mesh.vertex(3 * i), b = mesh.vertex(3 * i + 1), c = mesh.vertex(3 * i + 2);
      Vec3 ng = glm::cross(b - a, c - a);
      if (!(glm::length(ng) > 0.0f)) continue;
      ng = glm::normalize(ng);
      float w1 = 0.5f * (unit(rng) + 1.0f), w2 = 0.5f * (unit(rng) + 1.0f);
      if (w1 + w2 > 1.0f) {
        w1 = 1.0f - w1;
        w2 = 1.0f - w2;
      }
      const Vec3 target = a + w1 * (b - a) + w2 * (c - a);
      const Vec3 origin = target + scale * (ng + 0.5f * Vec3(unit(rng), unit(rng), unit(rng)));
      const Ray ray{origin, glm::normalize(target - origin), 0.0f, kInfinity};
      Hit hit;
      if (!tlas.intersect(ray, &hit) || hit.primitive != i) continue;  // occluded by another
      // The hit point and its error bound as the integrator computes them.
      const float w0 = 1.0f - hit.u - hit.v;
      const Vec3 x = w0 * a + hit.u * b + hit.v * c;
      const Vec3 error(max_component(barycentric_error(a, b, c, w0, hit.u, hit.v)));
      const Vec3 facing = glm::dot(ray.direction, ng) < 0.0f ? ng : -ng;
      Vec3 light_dir = glm::normalize(facing + 0.9f * Vec3(unit(rng), unit(rng), unit(rng)));
      if (glm::dot(light_dir, facing) <= 0.0f) light_dir = facing;
      for (const Vec3& d : {reflect(ray.direction, facing), ray.direction, light_dir}) {
        Hit again;
        ++rays;
        if (tlas.intersect(spawn_ray(x, error, ng, 0.0f, d, kReflectionRay), &again) &&
            again.primitive == i) {
          ++self_hits;
        }
      }
    }
  }
  EXPECT_GT(rays, 10000);
  EXPECT_EQ(self_hits, 0);
}

}  // namespace
}  // namespace whitted
