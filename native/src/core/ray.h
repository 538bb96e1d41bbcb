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
  // A shadow feeler is traced in two queries when some surfaces let light through: an
  // any-hit query against the instances whose materials are all opaque (the cheap common
  // case), then, if nothing opaque blocks it, a walk through the translucent ones. An
  // instance seen by shadow rays carries one of these two bits (Scene::compile).
  kOpaqueShadowRay = 1u << 4,
  kTranslucentShadowRay = 1u << 5,
  // The bounds of a volume (a mesh without a surface whose material encloses a medium:
  // integrator/volume.h): seen only by queries that carry this bit besides their kind,
  // in scenes with media, to enter and leave them.
  kVolumeBoundRay = 1u << 6,
  // A shadow catcher's feeler as if the catchers were alone in the scene
  // (integrator/catcher.h): seen only by the catchers that shadow rays see.
  kCatcherShadowRay = 1u << 7,
  // A camera ray where there is none: an image point outside a fisheye's circle. It
  // is traced as nothing (no instance's mask matches it) and shades as opaque black,
  // as Cycles shows it.
  kNoRay = 0,
};

struct Ray {
  Vec3 origin{0.0f};
  Vec3 direction{0.0f, 0.0f, -1.0f};  // unit length
  float t_min = 0.0f;
  float t_max = kInfinity;
  uint32_t kind = kAllRayKinds;  // one RayKind for traced rays
  // When in the shutter the ray travels, 0 (open) to 1 (closed): a camera sample's
  // time, kept by every ray of its tree (motion blur; 0 where nothing moves).
  float time = 0.0f;
};

// Rounding error bounds (Higham; pbrt-v4 util/float.h): n float operations in a row are
// off by at most gamma(n) relative.
inline constexpr float kMachineEpsilon = std::numeric_limits<float>::epsilon() * 0.5f;
inline constexpr float gamma(int n) {
  return (static_cast<float>(n) * kMachineEpsilon) /
         (1.0f - static_cast<float>(n) * kMachineEpsilon);
}

// Bound on the error of p = w0*p0 + w1*p1 + w2*p2 (pbrt-v4's triangle hit point).
inline Vec3 barycentric_error(const Vec3& p0, const Vec3& p1, const Vec3& p2, float w0, float w1,
                              float w2) {
  return gamma(7) * (glm::abs(w0 * p0) + glm::abs(w1 * p1) + glm::abs(w2 * p2));
}

// The float next to x towards +infinity or -infinity: std::nextafter(x, +-kInfinity) to
// the bit, without its library call (three per secondary ray): a finite float's neighbour
// is one step of its bit pattern (pbrt-v4 NextFloatUp / NextFloatDown). Infinities towards
// themselves and NaN stay as they are; both zeros step to the smallest subnormal.
inline float next_float_up(float x) {
  if (!(x < kInfinity)) return x;
  if (x == 0.0f) return std::numeric_limits<float>::denorm_min();
  const auto bits = std::bit_cast<uint32_t>(x);
  return std::bit_cast<float>(x > 0.0f ? bits + 1 : bits - 1);
}
inline float next_float_down(float x) {
  if (!(x > -kInfinity)) return x;
  if (x == 0.0f) return -std::numeric_limits<float>::denorm_min();
  const auto bits = std::bit_cast<uint32_t>(x);
  return std::bit_cast<float>(x > 0.0f ? bits - 1 : bits + 1);
}

// Moves a surface point off its surface along the geometric normal by just more than its
// rounding error bound, so a ray leaving it cannot re-hit the same surface whatever the
// scene's scale (pbrt-v4 OffsetRayOrigin). `n` points to the side the ray leaves towards.
inline Vec3 offset_ray_origin(const Vec3& p, const Vec3& error, const Vec3& n) {
  const float d = glm::dot(glm::abs(n), error);
  const Vec3 offset = d * n;
  Vec3 out = p + offset;
  // Round away from p so the offset survives the addition's own rounding.
  for (int i = 0; i < 3; ++i) {
    if (offset[i] > 0.0f) out[i] = next_float_up(out[i]);
    if (offset[i] < 0.0f) out[i] = next_float_down(out[i]);
  }
  return out;
}

// The one place secondary rays (reflection, refraction, shadow, and the continuation
// behind a cut-out) are made. `p` is a surface point with error bound `error`; `ng` is
// the unit geometric normal; the origin is pushed to the side of `ng` that `direction`
// leaves towards. `time` is the ray's that met the surface (a ray tree lives at one
// moment of the shutter). `t_max` bounds the ray (a shadow feeler stops before its light).
inline Ray spawn_ray(const Vec3& p, const Vec3& error, const Vec3& ng, float time,
                     const Vec3& direction, RayKind kind, float t_max = kInfinity) {
  const Vec3 side = glm::dot(direction, ng) >= 0.0f ? ng : -ng;
  return Ray{offset_ray_origin(p, error, side), direction, 0.0f, t_max, kind, time};
}

}  // namespace whitted
