// Rays and the one function that starts every secondary ray.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/math.h"

namespace whitted {

inline constexpr float kInfinity = std::numeric_limits<float>::infinity();

// What a ray is for, as a bit mask: an instance is seen only by the kinds of ray in its
// visibility mask (Blender's ray visibility: camera, shadow, glossy, transmission).
enum RayKind : uint32_t {
  kCameraRay = 1u << 0,
  kShadowRay = 1u << 1,
  kReflectionRay = 1u << 2,
  kRefractionRay = 1u << 3,
  kAllRayKinds = kCameraRay | kShadowRay | kReflectionRay | kRefractionRay,
};

struct Ray {
  Vec3 origin{0.0f};
  Vec3 direction{0.0f, 0.0f, -1.0f};  // unit length
  float t_min = 0.0f;
  float t_max = kInfinity;
  uint32_t kind = kAllRayKinds;  // one RayKind for traced rays
};

// Moves a surface point off its surface along the geometric normal by a few ulps of its
// own magnitude, so a ray leaving it cannot re-hit the same triangle whatever the scene's
// scale (Waechter & Binder, "A Fast and Robust Method for Avoiding Self-Intersection",
// Ray Tracing Gems ch. 6). `n` must point to the side the new ray leaves towards.
inline Vec3 offset_ray_origin(const Vec3& p, const Vec3& n) {
  constexpr float kOrigin = 1.0f / 32.0f;         // below this magnitude use a fixed offset
  constexpr float kFloatScale = 1.0f / 65536.0f;  // that fixed offset, relative to n
  constexpr float kIntScale = 256.0f;             // ulps moved, relative to n
  Vec3 out;
  for (int i = 0; i < 3; ++i) {
    if (std::fabs(p[i]) < kOrigin) {
      out[i] = p[i] + kFloatScale * n[i];  // near zero ulps are tiny: use a fixed step
      continue;
    }
    const int of_i = static_cast<int>(kIntScale * n[i]);
    const int32_t bits = std::bit_cast<int32_t>(p[i]);
    // Step away from zero for positive offsets on positive p (and vice versa). |p| >= 1/32
    // keeps the integer far from overflow.
    out[i] = std::bit_cast<float>(bits + ((p[i] < 0.0f) ? -of_i : of_i));
  }
  return out;
}

// The one place secondary rays (reflection, refraction, shadow, and the continuation
// behind a cut-out) are made. `ng` is the unit geometric normal; the origin is pushed to
// the side of `ng` that `direction` leaves towards. `t_max` bounds the ray (a shadow
// feeler stops before its light).
inline Ray spawn_ray(const Vec3& p, const Vec3& ng, const Vec3& direction, RayKind kind,
                     float t_max = kInfinity) {
  const Vec3 side = glm::dot(direction, ng) >= 0.0f ? ng : -ng;
  return Ray{offset_ray_origin(p, side), direction, 0.0f, t_max, kind};
}

}  // namespace whitted
