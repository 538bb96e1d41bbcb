// Blender 4.3's Gabor Texture as Cycles evaluates it (kernel/svm/gabor.h): sparse Gabor
// convolution noise (Lagae et al. 2009) with a fixed count of impulses per cell whose
// weights are +1 or -1 (Tavernier et al. 2019), summed as phasors so the phase and the
// intensity can be read too (Tricard et al. 2019). Written from the papers and that
// kernel's definitions; the hashes are the procedural textures' (procedural_detail.h), so
// the cells draw what Cycles' cells draw.
#include <cmath>

#include <glm/geometric.hpp>

#include "shader/ops.h"
#include "shader/procedural.h"
#include "shader/procedural_detail.h"

namespace whitted::procedural {
namespace {

using namespace detail;

constexpr int kImpulsesPerCell = 8;

float hash3(float x, float y, float z) {
  return unit(hash(bits(x), bits(y), bits(z)));
}
float hash4(float x, float y, float z, float w) {
  return unit(hash(bits(x), bits(y), bits(z), bits(w)));
}

// One impulse's kernel at squared distance d2 from its centre (a unit Gaussian of unit
// width, windowed by a Hann window so it ends smoothly at distance 1), as the phasor of
// `angle`: its sine part is the Gabor kernel, its cosine part the quadrature.
glm::vec2 kernel(float d2, float angle) {
  const float window = 0.5f + 0.5f * std::cos(kPi * d2);
  const float envelope = std::exp(-kPi * d2) * window;
  return envelope * glm::vec2(std::cos(angle), std::sin(angle));
}

// The impulses of cell `cell` at `p`, the point relative to that cell's corner.
glm::vec2 cell_2d(glm::vec2 cell, glm::vec2 p, float frequency, float isotropy, float base) {
  glm::vec2 sum(0.0f);
  for (int i = 0; i < kImpulsesPerCell; ++i) {
    const float k = static_cast<float>(i * 3);
    // Isotropic noise turns each impulse by up to half a turn about the base orientation.
    const float turn = (hash3(cell.x, cell.y, k) - 0.5f) * kPi;
    const float orientation = base + turn * isotropy;
    const glm::vec2 centre(hash3(cell.x, cell.y, k + 1.0f), hash3(k + 1.0f, cell.x, cell.y));
    const glm::vec2 d = p - centre;
    const float d2 = glm::dot(d, d);
    if (d2 >= 1.0f) continue;
    const float weight = hash3(cell.x, cell.y, k + 2.0f) < 0.5f ? -1.0f : 1.0f;
    const glm::vec2 along = frequency * glm::vec2(std::cos(orientation), std::sin(orientation));
    sum += weight * kernel(d2, 2.0f * kPi * glm::dot(d, along));
  }
  return sum;
}

// A 3D impulse's direction: the base direction, turned at random in inclination and
// azimuth by up to half a turn each where the noise is isotropic.
Vec3 direction_3d(const Vec3& base, float isotropy, const glm::vec4& seed) {
  if (isotropy == 0.0f) return base;
  float inclination = std::acos(base.z);
  float azimuth =
      (base.y < 0.0f ? -1.0f : 1.0f) * std::acos(base.x / glm::length(glm::vec2(base.x, base.y)));
  inclination += hash4(seed.x, seed.y, seed.z, seed.w) * kPi * isotropy;
  azimuth += hash4(seed.z, seed.x, seed.w, seed.y) * kPi * isotropy;
  return {std::sin(inclination) * std::cos(azimuth), std::sin(inclination) * std::sin(azimuth),
          std::cos(inclination)};
}

glm::vec2 cell_3d(const Vec3& cell, const Vec3& p, float frequency, float isotropy,
                  const Vec3& base) {
  glm::vec2 sum(0.0f);
  for (int i = 0; i < kImpulsesPerCell; ++i) {
    const float k = static_cast<float>(i * 3);
    const Vec3 direction = direction_3d(base, isotropy, glm::vec4(cell, k));
    const float k1 = k + 1.0f;
    const Vec3 centre(hash4(cell.x, cell.y, cell.z, k1), hash4(cell.z, cell.x, k1, cell.y),
                      hash4(k1, cell.z, cell.y, cell.x));
    const Vec3 d = p - centre;
    const float d2 = glm::dot(d, d);
    if (d2 >= 1.0f) continue;
    const float weight = hash4(cell.x, cell.y, cell.z, k + 2.0f) < 0.5f ? -1.0f : 1.0f;
    sum += weight * kernel(d2, 2.0f * kPi * glm::dot(d, frequency * direction));
  }
  return sum;
}

// The sum over the 3 x 3 (x 3) cells about the point's.
glm::vec2 noise_2d(glm::vec2 x, float frequency, float isotropy, float orientation) {
  const glm::vec2 corner = glm::floor(x);
  const glm::vec2 local = x - corner;
  glm::vec2 sum(0.0f);
  for (int j = -1; j <= 1; ++j) {
    for (int i = -1; i <= 1; ++i) {
      const glm::vec2 offset(static_cast<float>(i), static_cast<float>(j));
      sum += cell_2d(corner + offset, local - offset, frequency, isotropy, orientation);
    }
  }
  return sum;
}

glm::vec2 noise_3d(const Vec3& x, float frequency, float isotropy, const Vec3& direction) {
  const Vec3 corner = glm::floor(x);
  const Vec3 local = x - corner;
  glm::vec2 sum(0.0f);
  for (int k = -1; k <= 1; ++k) {
    for (int j = -1; j <= 1; ++j) {
      for (int i = -1; i <= 1; ++i) {
        const Vec3 offset(static_cast<float>(i), static_cast<float>(j), static_cast<float>(k));
        sum += cell_3d(corner + offset, local - offset, frequency, isotropy, direction);
      }
    }
  }
  return sum;
}

}  // namespace

glm::vec4 gabor_op(uint32_t mode, const glm::vec4& vector, const glm::vec4& scale,
                   const glm::vec4& frequency, const glm::vec4& anisotropy,
                   const glm::vec4& orientation) {
  const Vec3 x = Vec3(vector) * scale.x;
  const float isotropy = 1.0f - std::clamp(anisotropy.x, 0.0f, 1.0f);
  const float f = std::max(0.001f, frequency.x);
  // The spread of the summed impulses (the integral of a squared kernel, 1/4 in 2D and
  // 1/(4 sqrt 2) in 3D, times the impulses and their weights' second moment, 1/2).
  glm::vec2 phasor;
  float spread;
  if (mode_field::kGaborType.in(mode) == 0) {
    phasor = noise_2d(glm::vec2(x), f, isotropy, orientation.x);
    spread = std::sqrt(static_cast<float>(kImpulsesPerCell) * 0.5f * 0.25f);
  } else {
    phasor = noise_3d(x, f, isotropy, glm::normalize(Vec3(orientation)));
    spread = std::sqrt(static_cast<float>(kImpulsesPerCell) * 0.5f *
                       (1.0f / (4.0f * 1.41421356237309504880f)));
  }
  // Six spreads map the noise to [-1, 1], as Blender's node does.
  const float normalization = 6.0f * spread;
  switch (mode_field::kGaborOutput.in(mode)) {
    case 0:
      return glm::vec4((phasor.y / normalization) * 0.5f + 0.5f);
    case 1:
      return glm::vec4((std::atan2(phasor.y, phasor.x) + kPi) / (2.0f * kPi));
    default:
      return glm::vec4(glm::length(phasor) / normalization);
  }
}

}  // namespace whitted::procedural
