// What the procedural textures share inside shader/: the point type of every dimension,
// hashes of floats to [0, 1], and the interpolations Cycles' kernels use.
#pragma once

#include <bit>
#include <cstdint>

#include <glm/vec4.hpp>

#include "shader/procedural.h"

namespace whitted::procedural::detail {

template <int N>
using Point = glm::vec<N, float>;

// A hash in [0, 1] (both ends included, as Cycles' uint_to_float_incl).
inline float unit(uint32_t h) {
  return static_cast<float>(h) * (1.0f / static_cast<float>(0xFFFFFFFFu));
}
inline uint32_t bits(float x) {
  return std::bit_cast<uint32_t>(x);
}
inline float hash_to_float(float a) {
  return unit(hash(bits(a)));
}
inline float hash_to_float(float a, float b) {
  return unit(hash(bits(a), bits(b)));
}
inline float lerp(float a, float b, float t) {
  return a + t * (b - a);
}

// Cycles' smoothstep(0, 1, x).
inline float smoothstep(float x) {
  if (x < 0.0f) return 0.0f;
  if (x >= 1.0f) return 1.0f;
  return (3.0f - 2.0f * x) * (x * x);
}

}  // namespace whitted::procedural::detail
