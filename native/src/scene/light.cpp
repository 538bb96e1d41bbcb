#include "scene/light.h"

#include <cmath>

namespace whitted {
namespace {

// Cone falloff as Cycles defines it: zero outside the half angle, a smoothstep over the
// blend band inside it.
float spot_falloff(const Light& light, const Vec3& to_point) {
  const float c = glm::dot(glm::normalize(light.direction), to_point);
  const float c0 = std::cos(0.5f * light.spot_size);
  if (c <= c0) return 0.0f;
  const float band = (1.0f - c0) * light.spot_blend;
  return band > 0.0f ? smoothstep01((c - c0) / band) : 1.0f;
}

// Centre of stratum (i, j) of an n x n grid on the light's shape, in [-0.5, 0.5]^2.
void area_offset(const Light& light, int index, float* a, float* b) {
  const int n = light.samples;
  const float u = (static_cast<float>(index % n) + 0.5f) / static_cast<float>(n);
  const float v = (static_cast<float>(index / n) + 0.5f) / static_cast<float>(n);
  if (light.shape == AreaShape::kRectangle) {
    *a = u - 0.5f;
    *b = v - 0.5f;
    return;
  }
  // Shirley's concentric map keeps the strata equal in area on the disk.
  const float x = 2.0f * u - 1.0f;
  const float y = 2.0f * v - 1.0f;
  float r = 0.0f;
  float phi = 0.0f;
  if (x == 0.0f && y == 0.0f) {
    r = 0.0f;
  } else if (std::fabs(x) > std::fabs(y)) {
    r = x;
    phi = 0.25f * kPi * (y / x);
  } else {
    r = y;
    phi = 0.5f * kPi - 0.25f * kPi * (x / y);
  }
  *a = 0.5f * r * std::cos(phi);
  *b = 0.5f * r * std::sin(phi);
}

}  // namespace

LightSample sample_light(const Light& light, const Vec3& p, int index) {
  if (light.type == LightType::kSun) {
    return {-glm::normalize(light.direction), kInfinity, light.color};
  }
  Vec3 target = light.position;
  float area_weight = 1.0f;
  if (light.type == LightType::kArea) {
    float a = 0.0f;
    float b = 0.0f;
    area_offset(light, index, &a, &b);
    target += a * light.size[0] * light.axis_u + b * light.size[1] * light.axis_v;
    const float area =
        light.size[0] * light.size[1] * (light.shape == AreaShape::kEllipse ? 0.25f * kPi : 1.0f);
    area_weight = area / static_cast<float>(light.sample_count());
  }
  const Vec3 d = target - p;
  const float dist2 = glm::dot(d, d);
  const float dist = std::sqrt(dist2);
  if (!(dist > 0.0f)) return {Vec3(0.0f, 0.0f, 1.0f), 0.0f, Color(0.0f)};
  const Vec3 wi = d / dist;
  Color irradiance(0.0f);
  switch (light.type) {
    case LightType::kPoint:
      irradiance = light.color / dist2;  // E = I / r^2
      break;
    case LightType::kSpot:
      irradiance = light.color * (spot_falloff(light, -wi) / dist2);
      break;
    case LightType::kArea: {
      // A patch of area dA and radiance L gives E = L cos(theta_l) dA / r^2, one-sided.
      const float cos_l = glm::dot(glm::normalize(light.direction), -wi);
      if (cos_l > 0.0f) irradiance = light.color * (cos_l * area_weight / dist2);
      break;
    }
    case LightType::kSun:
      break;
  }
  return {wi, dist, irradiance};
}

}  // namespace whitted
