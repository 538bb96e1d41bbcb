// Vector helpers shared by every layer: reflection, refraction, Fresnel.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace whitted {

using Vec3 = glm::vec3;
using Color = glm::vec3;

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 1.0f / kPi;

inline float max_component(const Color& c) {
  return std::max({c.x, c.y, c.z});
}
inline float mean_component(const Color& c) {
  return (c.x + c.y + c.z) * (1.0f / 3.0f);
}
inline bool is_black(const Color& c) {
  return c.x <= 0.0f && c.y <= 0.0f && c.z <= 0.0f;
}
inline bool is_finite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
inline bool is_finite(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      if (!std::isfinite(m[c][r])) return false;
    }
  }
  return true;
}

// Mirror direction of incident direction u about unit normal n: r = u - 2(u.n)n.
inline Vec3 reflect(const Vec3& u, const Vec3& n) {
  return u - 2.0f * glm::dot(u, n) * n;
}

// Cycles' tangent at a shading point: `tangent` (world) made perpendicular to the unit
// normal n, cross(n, normalize(cross(t, n))), whichever side n faces; zero where t is zero
// or along n.
inline Vec3 tangent_across(const Vec3& tangent, const Vec3& n) {
  const Vec3 across = glm::cross(tangent, n);
  const float length = glm::length(across);
  if (!(length > 0.0f)) return Vec3(0.0f);
  return glm::cross(n, across / length);
}

// Refraction of unit incident direction u through a surface with unit normal n facing
// against u (dot(u, n) < 0). eta = eta_incident / eta_transmitted. Snell's law:
// eta1 sin(theta_i) = eta2 sin(theta_t). Returns false on total internal reflection.
inline bool refract(const Vec3& u, const Vec3& n, float eta, Vec3* t) {
  const float cos_i = std::min(1.0f, -glm::dot(u, n));
  const float sin2_t = eta * eta * std::max(0.0f, 1.0f - cos_i * cos_i);
  if (sin2_t >= 1.0f) return false;  // total internal reflection
  const float cos_t = std::sqrt(1.0f - sin2_t);
  *t = glm::normalize(eta * u + (eta * cos_i - cos_t) * n);
  return true;
}

// Schlick's approximation of dielectric reflectance; cos_i is measured on the incident side.
inline float fresnel_schlick(float cos_i, float eta) {
  // Beyond the critical angle all light reflects.
  const float sin2_t = eta * eta * std::max(0.0f, 1.0f - cos_i * cos_i);
  if (sin2_t >= 1.0f) return 1.0f;
  // Use the angle on the optically thinner side so the curve is right when leaving glass.
  const float c = eta > 1.0f ? std::sqrt(1.0f - sin2_t) : cos_i;
  const float r0 = (1.0f - eta) / (1.0f + eta);
  const float f0 = r0 * r0;
  const float m = 1.0f - std::clamp(c, 0.0f, 1.0f);
  return f0 + (1.0f - f0) * m * m * m * m * m;
}

// Exact unpolarised dielectric Fresnel reflectance; 1 on total internal reflection.
inline float fresnel_exact(float cos_i, float eta) {
  cos_i = std::clamp(cos_i, 0.0f, 1.0f);
  const float sin2_t = eta * eta * (1.0f - cos_i * cos_i);
  if (sin2_t >= 1.0f) return 1.0f;
  const float cos_t = std::sqrt(1.0f - sin2_t);
  // eta = n1/n2, so r_s = (n1 cos_i - n2 cos_t)/(n1 cos_i + n2 cos_t) divided through by n2.
  const float rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  const float rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5f * (rs * rs + rp * rp);
}

// A hash of three integers (a PCG-style integer mix): the one source of the numbers that
// place samples (jitter, glossy strata), so that an image depends only on its pixels'
// samples, never on tiles, threads or the scene's scale.
inline uint32_t hash3(uint32_t a, uint32_t b, uint32_t c) {
  uint32_t h = a * 0x8da6b343u ^ b * 0xd8163841u ^ c * 0xcb1ab31fu;
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
  return h;
}

// A permutation of 0 .. count-1 chosen by `seed`: a bijection of the smallest
// power-of-two range holding `count` (xor, odd multiply and xor-shift, each invertible
// within the range), walked until it lands below `count`; O(1) per element, so a pixel's
// sample k finds its partner without shuffling them all. Made once, it maps many indices
// without hashing the seed again.
class Permutation {
 public:
  Permutation(uint32_t count, uint32_t seed) : count_(count), mask_(count - 1) {
    for (int shift = 1; shift < 32; shift <<= 1) mask_ |= mask_ >> shift;
    key_ = hash3(seed, count, 0x5bd1e995u);
  }
  // Element `index` (< count).
  uint32_t operator()(uint32_t index) const {
    do {
      index ^= key_ & mask_;
      index = (index * 0x2c1b3c6du) & mask_;
      index ^= (index & mask_) >> 3;
      index = (index * (key_ | 1u)) & mask_;
      index ^= (index & mask_) >> 5;
      index = (index + (key_ >> 16)) & mask_;
    } while (index >= count_);
    return index;
  }

 private:
  uint32_t count_;
  uint32_t mask_;
  uint32_t key_ = 0;
};

// Element `index` of Permutation(count, seed), alone.
inline uint32_t permuted(uint32_t index, uint32_t count, uint32_t seed) {
  return Permutation(count, seed)(index);
}

// The top 24 bits of h as a float in [0, 1) (exact).
inline float unit_float(uint32_t h) {
  return static_cast<float>(h >> 8) * (1.0f / 16777216.0f);
}

// A point in stratum k of the n x n strata of [0, 1)^2, placed in its cell by a hash of
// `base`, k and `salt`: jittered strata, a new point for each base (the glossy rays' and
// emitter feelers' Strata where the camera samples are not Monte Carlo ones).
inline glm::vec2 jittered_stratum(uint32_t base, uint32_t salt, int k, int n) {
  const uint32_t h = hash3(base, static_cast<uint32_t>(k), salt);
  const float jitter_x = unit_float(h);
  const float jitter_y = unit_float(hash3(h, 0x7f4au, 0x85ebu));
  // Below 1: the sum of the last cell's index and a jitter near 1 may round up to n.
  constexpr float kBelowOne = 0x1.fffffep-1f;
  const auto side = static_cast<float>(n);
  return {std::min((static_cast<float>(k % n) + jitter_x) / side, kBelowOne),
          std::min((static_cast<float>(k / n) + jitter_y) / side, kBelowOne)};
}

// Shirley and Chiu's concentric map of (x, y) in [-1, 1]^2 to the unit disc, as polar
// (r, phi): equal areas stay equal (stratified squares give stratified disc points).
inline void concentric_disc(float x, float y, float* r, float* phi) {
  *r = 0.0f;
  *phi = 0.0f;
  if (x == 0.0f && y == 0.0f) return;
  if (std::fabs(x) > std::fabs(y)) {
    *r = x;
    *phi = 0.25f * kPi * (y / x);
  } else {
    *r = y;
    *phi = 0.5f * kPi - 0.25f * kPi * (x / y);
  }
}

inline float smoothstep01(float t) {
  t = std::clamp(t, 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

}  // namespace whitted
