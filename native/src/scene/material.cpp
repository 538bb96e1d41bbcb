#include "scene/material.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace whitted {

Material::Material(const MaterialParams& params) : MaterialParams(params) {
  for (const Color* c : {&diffuse, &specular, &reflectivity, &transmissivity, &emission}) {
    if (!is_finite(*c)) throw std::invalid_argument("material colours must be finite");
  }
  if (!std::isfinite(shininess) || !std::isfinite(ambient) || !std::isfinite(ior) || ior <= 0.0f) {
    throw std::invalid_argument(
        "material shininess, ambient and ior must be finite and ior positive");
  }
  if (!std::isfinite(alpha)) throw std::invalid_argument("alpha must be finite");
  for (const float v : {coat_specular, coat_reflectivity, coat_shininess, coat_ior}) {
    if (!std::isfinite(v)) throw std::invalid_argument("coat values must be finite");
  }
  if (coat_ior <= 0.0f) throw std::invalid_argument("coat_ior must be positive");
  if (!is_finite(layer_reflectivity) || !std::isfinite(layer_ior) || layer_ior <= 0.0f) {
    throw std::invalid_argument("layer_reflectivity must be finite and layer_ior positive");
  }
  layer_reflectivity = glm::max(layer_reflectivity, Color(0.0f));
  if (static_cast<uint32_t>(coat_model) > static_cast<uint32_t>(CoatModel::kGtr1)) {
    throw std::invalid_argument("coat_model is not a CoatModel");
  }
  if (static_cast<uint32_t>(diffuse_model) >
      static_cast<uint32_t>(DiffuseModel::kOrenNayarEnergy)) {
    throw std::invalid_argument("diffuse_model is not a DiffuseModel");
  }
  if (!std::isfinite(diffuse_roughness)) {
    throw std::invalid_argument("diffuse_roughness must be finite");
  }
  diffuse_roughness = std::clamp(diffuse_roughness, 0.0f, 1.0f);
  if (!is_finite(sheen) || !std::isfinite(sheen_roughness)) {
    throw std::invalid_argument("sheen and sheen_roughness must be finite");
  }
  sheen = glm::max(sheen, Color(0.0f));
  sheen_roughness = std::clamp(sheen_roughness, 0.0f, 1.0f);
  if (!std::isfinite(roughness)) throw std::invalid_argument("roughness must be finite");
  roughness = std::clamp(roughness, 0.0f, 1.0f);
  if (!std::isfinite(anisotropy)) throw std::invalid_argument("anisotropy must be finite");
  anisotropy = std::clamp(anisotropy, -0.99f, 0.99f);
  if (!std::isfinite(coat_roughness)) throw std::invalid_argument("coat_roughness must be finite");
  coat_roughness = std::clamp(coat_roughness, 0.0f, 1.0f);
  if (static_cast<uint32_t>(bump_shadowing) > static_cast<uint32_t>(BumpShadowing::kMicrofacet)) {
    throw std::invalid_argument("bump_shadowing is not a BumpShadowing");
  }
  alpha = std::clamp(alpha, 0.0f, 1.0f);
  for (Color* c : {&volume_absorption, &volume_scattering, &volume_emission}) {
    if (!is_finite(*c)) throw std::invalid_argument("volume coefficients must be finite");
    *c = glm::max(*c, Color(0.0f));
  }
  if (!std::isfinite(volume_anisotropy)) {
    throw std::invalid_argument("volume_anisotropy must be finite");
  }
  volume_anisotropy = std::clamp(volume_anisotropy, -0.999f, 0.999f);  // as Cycles' HG setup
  if (!(volume_step_rate > 0.0f) || !std::isfinite(volume_step_rate)) {
    throw std::invalid_argument("volume_step_rate must be finite and above 0");
  }
  if (!surface) {
    // Its program may drive the medium only.
    bool drives_surface = false;
    for (size_t f = 0; f < kFieldCount; ++f) {
      drives_surface |= outputs[f] >= 0 && !medium_field(f);
    }
    if (drives_surface || !diffuse_texture.empty() || !alpha_texture.empty()) {
      throw std::invalid_argument(
          "a material without a surface has no texture and no program driving its surface");
    }
    alpha = 0.0f;  // where it shares a mesh with surfaces, a cut-out (Scene::compile)
  }
  // Every output a register of the program that computes it.
  for (size_t f = 0; f < kFieldCount; ++f) {
    if (outputs[f] < 0) continue;
    if (!program) throw std::invalid_argument("material outputs need a program");
    if (static_cast<uint64_t>(outputs[f]) >= program->register_count()) {
      throw std::invalid_argument("output '" + std::string(kFieldTable[f].name) + "' register " +
                                  std::to_string(outputs[f]) + " out of range (" +
                                  std::to_string(program->register_count()) + " registers)");
    }
  }
}

float tilted_diffuse_shadowing(BumpShadowing model, const Vec3& smooth, const Vec3& n,
                               const Vec3& wi) {
  const float cos_si = glm::dot(smooth, wi);  // the light's height over the smooth surface
  const float cos_sn = glm::dot(smooth, n);   // how far the normal leans from it
  const float cos_ni = glm::dot(n, wi);
  if (model == BumpShadowing::kChiang) {
    // g is 1 where the tilted facet is no more lit than the smooth surface would be;
    // below that the cubic g + g^2 - g^3 takes the light smoothly to 0 at the smooth
    // surface's horizon (and beyond it, none).
    const float denominator = cos_ni * cos_sn;
    const float g = denominator != 0.0f ? cos_si / denominator : 0.0f;
    if (g >= 1.0f) return 1.0f;
    if (g < 0.0f) return 0.0f;
    return g + g * g - g * g * g;
  }
  // Light and normal on different sides of the smooth surface: none.
  if (cos_si * cos_sn * cos_ni < 0.0f) return 0.0f;
  if (model == BumpShadowing::kSmoothSide) return 1.0f;
  const float cos_i = std::fabs(cos_si), cos_d = std::fabs(cos_sn);
  if (cos_d >= 1.0f || cos_i >= 1.0f) return 1.0f;
  if (cos_i < 1e-6f) return 0.0f;
  // The tilt as the roughness of a GGX surface (alpha^2 = tan^2(tilt) / 8, at most 1), and
  // Smith's masking of that surface for light at the smooth surface's angle cos_i.
  const float alpha2 = std::clamp(0.125f * (1.0f / (cos_d * cos_d) - 1.0f), 0.0f, 1.0f);
  const float tan2_i = 1.0f / (cos_i * cos_i) - 1.0f;
  return 2.0f / (1.0f + std::sqrt(1.0f + alpha2 * tan2_i));
}

}  // namespace whitted
