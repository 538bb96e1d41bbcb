// The lobes the local term is made of, beside the Lambertian diffuse and the Phong
// highlight written where the kernel uses them (local.h light_terms): the diffuse
// lobes' shapes (Burley, Oren-Nayar), the sheen's (velvet) and the coat, a clear layer
// over the base; the microfacet lobes are scene/microfacet.h's.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/math.h"
#include "scene/microfacet.h"
#include "scene/scene.h"

namespace whitted {

// The shape of a kBurley diffuse lobe (Burley 2015, "Extending the Disney BRDF to a BSDF
// with Integrated Subsurface Scattering", as Cycles 3.x's Principled BSDF evaluates it):
// Lambert's lobe darkened where light arrives or leaves at grazing angles, by the Schlick
// weights F = (1 - cos)^5, plus a retro-reflection that grows with roughness r and with
// how close the light is to the view, R = r (1 + l.v):
//   (1 - F_l/2) (1 - F_v/2) + R (F_l + F_v + F_l F_v (R - 1)).
// cos_l = n.l, cos_v = n.v and l_dot_v = l.v, for unit vectors.
inline float burley_diffuse(float cos_l, float cos_v, float l_dot_v, float roughness) {
  const auto schlick_weight = [](float cosine) {
    const float m = std::clamp(1.0f - cosine, 0.0f, 1.0f);
    const float m2 = m * m;
    return m2 * m2 * m;
  };
  const float f_l = schlick_weight(cos_l);
  const float f_v = schlick_weight(cos_v);
  const float retro = roughness * (1.0f + l_dot_v);
  return (1.0f - 0.5f * f_l) * (1.0f - 0.5f * f_v) +
         retro * (f_l + f_v + f_l * f_v * (retro - 1.0f));
}

// The shape of the sheen lobe, relative to Lambert's: Ashikhmin's velvet distribution
// D = exp(-cot^2(h) / sigma^2) / (pi sigma^2 sin^4(h)) with the shadowing
// G = min(1, 2 (n.h)(n.v)/(v.h), 2 (n.h)(n.l)/(v.h)), whose f cos_l = D G / (4 cos_v), as
// Cycles evaluates its velvet closure (sigma at least 0.01). From cos_l = n.l, cos_v = n.v
// and l_dot_v = l.v: |l + v| = sqrt(2 + 2 l.v), n.h = (n.l + n.v)/|l + v|,
// v.h = (1 + l.v)/|l + v|. Returns pi f, what multiplies sheen/pi.
inline float velvet_sheen(float cos_l, float cos_v, float l_dot_v, float sigma) {
  if (cos_l <= 0.0f || cos_v <= 0.0f) return 0.0f;
  const float length = std::sqrt(std::max(2.0f + 2.0f * l_dot_v, 0.0f));
  if (!(length > 0.0f)) return 0.0f;
  const float cos_nh = (cos_l + cos_v) / length;
  const float cos_ho = std::fabs(1.0f + l_dot_v) / length;
  if (!(std::fabs(cos_nh) < 1.0f - 1e-5f && cos_ho > 1e-5f)) return 0.0f;
  const float ratio = std::max(cos_nh / cos_ho, 1e-5f);
  const float g = std::min(1.0f, 2.0f * std::min(ratio * cos_v, ratio * cos_l));
  const float sin2 = 1.0f - cos_nh * cos_nh;
  const float s = std::max(sigma, 0.01f);
  const float inv_s2 = 1.0f / (s * s);
  const float d = std::exp(-(cos_nh * cos_nh / sin2) * inv_s2) * inv_s2 * kInvPi / (sin2 * sin2);
  // f cos_l = D G / (4 cos_v); Lambert's is cos_l / pi.
  return kPi * 0.25f * d * g / (cos_v * cos_l);
}

// The shape of a kOrenNayar diffuse lobe (Fujii's "improved Oren-Nayar" form, as Cycles'
// Diffuse BSDF evaluates it, without the multiple-scattering term Cycles 4.3+ adds):
// pi (A + B s), A = 1 / (pi + (pi/2 - 2/3) r), B = r A, for roughness r, with
// s = l.v - (n.l)(n.v), divided by max(n.l, n.v) where positive. 1 at r = 0; rough
// surfaces are darker towards the light and brighter with the light behind the viewer.
// A, the Lambertian part of Fujii's lobe (B = r A), for roughness r.
inline float oren_nayar_a(float roughness) {
  return 1.0f / (kPi + (0.5f * kPi - 2.0f / 3.0f) * roughness);
}
inline float oren_nayar_diffuse(float cos_l, float cos_v, float l_dot_v, float roughness) {
  cos_l = std::max(cos_l, 0.0f);
  cos_v = std::max(cos_v, 0.0f);
  float s = l_dot_v - cos_l * cos_v;
  if (s > 0.0f) s /= std::max(cos_l, cos_v) + std::numeric_limits<float>::min();
  return kPi * (1.0f + roughness * s) * oren_nayar_a(roughness);
}

// kOrenNayarEnergy's multiple scattering, in the OpenPBR specification's form as Cycles
// 4.3+ evaluates it: the light the single-scattering lobe loses, E(cos) being its
// directional albedo, comes back as
//   kd * albedo^2 Eavg / (1 - Eavg) / (1 - albedo (1 - Eavg)) / pi * (1 - E(n.v)) (1 - E(n.l)),
// albedo = kd clamped to [0, 1] (Cycles multiplies by its closure weight kd too: one
// albedo more than the specification's; matched against Cycles 5.0 in
// tests/blender/test_surface_vs_cycles.py). Here, per channel:
// kd * oren_nayar_multiscatter(kd, r, n.v) * oren_nayar_loss(n.l, r).
// E(cos) = pi A + B G(cos), with G from the specification (its series near the horizon).
inline float oren_nayar_g(float cos_theta) {
  constexpr float kTwoThirds = 2.0f / 3.0f;
  if (cos_theta < 1e-6f) return (0.5f * kPi - kTwoThirds) - cos_theta;
  const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
  const float theta = std::acos(std::min(cos_theta, 1.0f));
  return sin_theta * (theta - kTwoThirds - sin_theta * cos_theta) +
         kTwoThirds * (sin_theta / cos_theta) * (1.0f - sin_theta * sin_theta * sin_theta);
}
// 1 - E(cos): what the single-scattering lobe does not reflect of light from that angle.
inline float oren_nayar_loss(float cos_theta, float roughness) {
  const float a = oren_nayar_a(roughness);
  return 1.0f - (kPi * a + roughness * a * oren_nayar_g(std::max(cos_theta, 0.0f)));
}
inline Color oren_nayar_multiscatter(const Color& kd, float roughness, float cos_v) {
  if (!(roughness > 0.0f)) return Color(0.0f);  // Lambert loses nothing (and Eavg = 1)
  const float a = oren_nayar_a(roughness);
  const float average = kPi * a + (2.0f * kPi - 5.6f) / 3.0f * roughness * a;  // Eavg
  const Color albedo = glm::clamp(kd, Color(0.0f), Color(1.0f));
  const Color ms = albedo * albedo * (average / (1.0f - average) / kPi) /
                   (Color(1.0f) - albedo * (1.0f - average));
  return ms * oren_nayar_loss(cos_v, roughness);
}

// The coat of a hit as the ray sees it: a clear layer over the base whose reflectance is
// its weights times the exact dielectric Fresnel factor of its IOR at its own normal; the
// base beneath receives the rest, 1 - cover, of the light.
struct Coat {
  float highlight = 0.0f;  // weight of its Phong highlight
  float mirror = 0.0f;     // weight of its mirror reflection
  float cover = 0.0f;      // highlight + mirror: the share it takes from the base
  float shininess = 1.0f;
  float alpha = 0.0f;                 // alpha of its mirror's lobe; 0: a mirror (microfacet.h)
  CoatModel model = CoatModel::kGgx;  // that lobe's distribution
  Vec3 normal{0.0f, 0.0f, 1.0f};      // facing the ray
  float eta = 1.0f;                   // 1 / its IOR
  float fresnel = 0.0f;               // its Fresnel factor at the view and its normal

  // What its rough lobe's share becomes for a facet of normal m: the Fresnel factor
  // at the facet over the one at the layer's normal that `mirror` holds (a rough
  // dielectric reflects by its facets' Fresnel factors, lower at grazing views).
  float facet_scale(const Vec3& wo, const Vec3& m) const {
    if (!(fresnel > 0.0f)) return 0.0f;
    return fresnel_exact(std::max(0.0f, glm::dot(wo, m)), eta) / fresnel;
  }
};

// The share of the light a rough dielectric layer reflects, its albedo: the mean of
// the sampled weights (GGX's G2/G1) times the facet's Fresnel factor over 3 x 3 fixed
// samples of its lobe (Cycles takes it from tables; 1 - albedo reaches the layers
// beneath). Lower than the Fresnel factor at the layer's normal at grazing views, where
// that tends to 1.
float rough_layer_albedo(CoatModel model, const Vec3& n, const Vec3& wo, float alpha, float eta,
                         Masking masking);

// The coat of a hit seen from wo (geometric normal ng facing the ray; `entering`: the
// ray meets the surface's front), its rough lobe of distribution `model`.
Coat coat_of(const SurfaceParams& surface, const Vec3& wo, const Vec3& ng, bool entering,
             Masking masking, CoatModel model);

// The base's specular layer beneath the coat (SurfaceParams::layer_reflectivity), seen
// from wo: a clear layer about the base's shading normal ns (facing the ray), of the
// base's GGX alpha (0: a mirror), whose `mirror` is the Fresnel factor of its IOR at ns
// times the largest component of its weight (so `cover`, what it takes from the diffuse
// beneath, stays within 1); a weight of 0 is no layer.
Coat layer_of(const SurfaceParams& surface, const Vec3& wo, const Vec3& ns, float alpha,
              Masking masking);

// A rough coat's mirror lobe for light arriving from wi: its lobe (of its model)
// evaluated, times its weight and its facet's Fresnel factor; 0 for a sharp coat.
float coat_glossy(const Coat& coat, const Vec3& wo, const Vec3& wi, Masking masking);

// The coat's highlight for light arriving from wi, per unit irradiance: the normalised
// Phong lobe ks*(f+2)/(2pi)*(v.r)^f*(l.n) about the coat's normal, and a rough mirror's
// lobe (coat_glossy).
float coat_highlight(const Coat& coat, const Vec3& wo, const Vec3& wi, Masking masking);

}  // namespace whitted
