#include "integrator/lobes.h"

namespace whitted {

float rough_layer_albedo(CoatModel model, const Vec3& n, const Vec3& wo, float alpha, float eta,
                         Masking masking) {
  constexpr int kSide = 3;
  float sum = 0.0f;
  for (int i = 0; i < kSide; ++i) {
    for (int j = 0; j < kSide; ++j) {
      Vec3 wi;
      float weight = 0.0f;
      if (!lobe_sample_reflection(model, GgxLobe(n, alpha), wo, (i + 0.5f) / kSide,
                                  (j + 0.5f) / kSide, &wi, &weight, masking)) {
        continue;
      }
      sum += weight * fresnel_exact(std::max(0.0f, glm::dot(wo, glm::normalize(wo + wi))), eta);
    }
  }
  return sum / (kSide * kSide);
}

Coat coat_of(const SurfaceParams& surface, const Vec3& wo, const Vec3& ng, bool entering,
             Masking masking, CoatModel model) {
  Coat coat;
  const float weight = surface.coat_specular + surface.coat_reflectivity;
  if (!(weight > 0.0f)) return coat;
  coat.normal = entering ? surface.coat_normal : -surface.coat_normal;
  if (glm::dot(coat.normal, ng) <= 0.0f) coat.normal = ng;  // as the base's normal
  coat.eta = 1.0f / surface.coat_ior;
  const float f = fresnel_exact(glm::dot(wo, coat.normal), coat.eta);
  coat.fresnel = f;
  const float scale = f / std::max(weight, 1.0f);  // weights beyond 1 cover all
  coat.highlight = std::max(surface.coat_specular, 0.0f) * scale;
  coat.mirror = std::max(surface.coat_reflectivity, 0.0f) * scale;
  coat.cover = coat.highlight + coat.mirror;
  coat.shininess = surface.coat_shininess;
  const float alpha = surface.coat_roughness * surface.coat_roughness;
  coat.alpha = alpha >= kMirrorAlpha && coat.mirror > 0.0f ? alpha : 0.0f;
  coat.model = model;
  if (coat.alpha > 0.0f && f > 0.0f) {
    // What the rough mirror takes from the base: its albedo, not its Fresnel factor.
    coat.cover =
        coat.highlight +
        coat.mirror * rough_layer_albedo(model, coat.normal, wo, coat.alpha, coat.eta, masking) / f;
  }
  return coat;
}

Coat layer_of(const SurfaceParams& surface, const Vec3& wo, const Vec3& ns, float alpha,
              Masking masking) {
  Coat layer;
  const float weight = std::min(max_component(surface.layer_reflectivity), 1.0f);
  if (!(weight > 0.0f)) return layer;
  layer.normal = ns;
  layer.eta = 1.0f / surface.layer_ior;
  layer.fresnel = fresnel_exact(glm::dot(wo, ns), layer.eta);
  layer.mirror = weight * layer.fresnel;
  layer.cover = layer.mirror;
  layer.alpha = alpha;
  if (alpha > 0.0f && layer.fresnel > 0.0f) {
    // What the rough layer takes from the diffuse beneath: its albedo (as the coat's).
    layer.cover = weight * rough_layer_albedo(CoatModel::kGgx, ns, wo, alpha, layer.eta, masking);
  }
  return layer;
}

float coat_glossy(const Coat& coat, const Vec3& wo, const Vec3& wi, Masking masking) {
  if (!(coat.alpha > 0.0f)) return 0.0f;
  const Vec3 half = wo + wi;
  const float length = glm::length(half);
  if (!(length > 0.0f)) return 0.0f;
  return coat.mirror * coat.facet_scale(wo, half / length) *
         lobe_reflection(coat.model, GgxLobe(coat.normal, coat.alpha), wo, wi, masking);
}

float coat_highlight(const Coat& coat, const Vec3& wo, const Vec3& wi, Masking masking) {
  const float glossy = coat_glossy(coat, wo, wi, masking);
  if (coat.highlight <= 0.0f) return glossy;
  const float cos_l = glm::dot(coat.normal, wi);
  if (cos_l <= 0.0f) return 0.0f;
  const float v_dot_r = std::max(0.0f, glm::dot(wo, reflect(-wi, coat.normal)));
  if (v_dot_r <= 0.0f && coat.shininess > 0.0f) return 0.0f;  // what powf's +0 makes of it
  return glossy + coat.highlight * (coat.shininess + 2.0f) * (0.5f * kInvPi) *
                      std::pow(v_dot_r, coat.shininess) * cos_l;
}

}  // namespace whitted
