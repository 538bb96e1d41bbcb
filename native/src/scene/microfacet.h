// The GGX microfacet lobe as Blender's BSDFs define it (Walter et al., "Microfacet Models
// for Refraction through Rough Surfaces", EGSR 2007): Blender's roughness r maps to
// alpha = r^2 (Cycles does the mapping when it sets up the closure; here the exporter
// sends alpha); Smith's height-correlated masking-shadowing, as Cycles evaluates it;
// directions drawn from the visible normals (Heitz, "Sampling the GGX Distribution of
// Visible Normals", JCGT 2018). One lobe serves lights and rays: a light sample reads
// its value (eval), a glossy ray is drawn from it (sample), so direct light and one
// specular bounce agree with Cycles'. Single scattering only (Cycles' Multiscatter GGX
// adds the energy the facets' inter-reflections keep; docs/SUPPORT.md says how much).
// Beside it, at the end, the GTR1 lobe of Blender 3.x's Clearcoat (CoatModel).
#pragma once

#include <cstdint>

#include "core/math.h"
#include "core/ray.h"

namespace whitted {

// Below this alpha (roughness 0.02, as the threshold) a lobe is a mirror: it is
// traced as one exact reflection and lights give it no highlight.
inline constexpr float kMirrorAlpha = 0.02f * 0.02f;

// An orthonormal frame about unit normal n: local (x, y, z) -> world x*t + y*b + z*n.
struct Frame {
  Vec3 t;
  Vec3 b;
  Vec3 n;

  explicit Frame(const Vec3& normal);
  // The frame whose x axis is `tangent` made perpendicular to n (Cycles'
  // make_orthonormals_tangent: b = n x tangent, normalised; t = b x n).
  Frame(const Vec3& normal, const Vec3& tangent);
  Vec3 to_local(const Vec3& v) const { return {glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)}; }
  Vec3 to_world(const Vec3& v) const { return v.x * t + v.y * b + v.z * n; }
};

// GGX's normal distribution D(m) for cos_m = n.m of the microfacet normal m.
float ggx_distribution(float cos_m, float alpha);

// Smith's Lambda for a direction at cos_theta to the normal: G1 = 1 / (1 + Lambda).
float ggx_lambda(float cos_theta, float alpha);

// A GGX lobe's shape: about unit normal n, of roughness alpha, or anisotropic: alpha_x
// along the tangent t and alpha_y along n x t (Cycles' MicrofacetBsdf alpha_x, alpha_y
// and T; brushed metal). An isotropic lobe's functions below compute exactly what they
// did before anisotropy came (its frame's tangent is arbitrary).
struct GgxLobe {
  Vec3 n;
  float alpha_x;
  float alpha_y;
  Vec3 t{0.0f};  // unit, perpendicular to n; unused when isotropic

  GgxLobe(const Vec3& normal, float alpha) : n(normal), alpha_x(alpha), alpha_y(alpha) {}
  // Anisotropic along `tangent` (any vector not parallel to n; it is made perpendicular
  // to n). A tangent parallel to n, zero or not finite gives the isotropic lobe of
  // alpha sqrt(alpha_x alpha_y).
  GgxLobe(const Vec3& normal, const Vec3& tangent, float ax, float ay);

  bool isotropic() const { return alpha_x == alpha_y; }
  // The round lobe's alpha, or the geometric mean of the two (0: a mirror).
  float alpha() const { return isotropic() ? alpha_x : std::sqrt(alpha_x * alpha_y); }
  Frame frame() const;
};

// Cycles' alpha_x and alpha_y of a lobe of alpha (roughness^2) and Anisotropy a (the
// Glossy and Anisotropic BSDFs'), a clamped to [-0.99, 0.99]: a > 0 narrows the lobe
// along the tangent (alpha (1 - a), alpha / (1 - a)), a < 0 widens it (alpha / (1 + a),
// alpha (1 + a)). Their geometric mean stays alpha. |a| <= 1e-4 is isotropic.
void ggx_anisotropic_alphas(float alpha, float anisotropy, float* ax, float* ay);

// How Smith's masking (of the view) and shadowing (of the light) combine into G2:
// height-correlated, 1 / (1 + Lambda_o + Lambda_i) (Cycles 4.0 on), or separable,
// G1_o * G1_i (Cycles 3.x).
enum class Masking { kCorrelated, kSeparable };

// The reflection lobe for view wo and light wi (unit, about the lobe's normal n) times
// cos(wi): f * cos_i = D * G2 / (4 cos_o), without Fresnel or colour; 0 below either
// horizon. A light sample of irradiance E (on a surface facing the light) adds
// colour * this * E.
float ggx_reflection(const GgxLobe& lobe, const Vec3& wo, const Vec3& wi,
                     Masking masking = Masking::kCorrelated);

// A direction drawn from the reflection lobe for view wo (about its normal n), from the
// two uniform numbers u1, u2 in [0, 1): wi = reflect(-wo, m) for m a visible normal.
// *weight receives lobe value / pdf = G2 / G1(wo), in [0, 1] (without Fresnel or
// colour). Returns false when wi falls below the surface (weight 0: the lobe's mass the
// single-scattering model loses).
bool ggx_sample_reflection(const GgxLobe& lobe, const Vec3& wo, float u1, float u2, Vec3* wi,
                           float* weight, Masking masking = Masking::kCorrelated);

// The density, per unit solid angle, with which ggx_sample_reflection draws wi for view
// wo: the visible normals' density over the reflection's Jacobian, G1(wo) D(m) / (4 cos_o)
// for m the half vector; 0 below either horizon. What multiple importance sampling
// weighs a glossy ray against a light's feeler with (integrator/mis.h).
float ggx_reflection_pdf(const GgxLobe& lobe, const Vec3& wo, const Vec3& wi);

// A visible microfacet normal for view wo about unit normal n (Heitz 2018), from u1, u2
// in [0, 1): what ggx_sample_reflection mirrors the view about, and what a rough
// dielectric refracts it through. False when wo is below the surface.
bool ggx_sample_normal(const Vec3& n, const Vec3& wo, float alpha, float u1, float u2, Vec3* m);

// A refracted direction's weight, G2 / G1(wo) with the masking of the transmitted
// direction on the far side (cos_t = its cosine to n, negative): Walter et al.'s BTDF
// over the density of visible normals, the Fresnel factor and Jacobian aside.
float ggx_transmission_weight(float cos_o, float cos_t, float alpha, Masking masking);

// The energy the single-scattering lobe keeps: its directional albedo E for a view at
// cos_o to the normal (Fresnel 1), from a 32 x 32 table over (roughness, cos_o) made
// once from ggx_sample_reflection, read bilinearly; and E's cosine-weighted mean, E_avg.
// Roughness is Blender's (alpha = roughness^2).
float ggx_albedo(float cos_o, float roughness);
float ggx_average_albedo(float roughness);

// Multiple scattering between the facets, as an energy scale of the single-scattering
// lobe of colour `f` (Kulla & Conty 2017; the albedo scaling of Cycles 4.x's
// Multiscatter GGX): 1 + F_ms (1 - E) / E per channel, F_ms = f E_avg / (1 - f (1 -
// E_avg)). A white lobe then returns all the light that reaches it.
Color ggx_multiscatter_scale(const Color& f, float cos_o, float roughness);

// Which distribution a coat's rough lobe has: GGX's (the functions above; Blender 4.0
// on, where Coat is a GGX dielectric layer) or GTR1's (below; Blender 3.x's Clearcoat,
// as Cycles 3.x evaluates it). The material field coat_model.
enum class CoatModel : uint32_t { kGgx, kGtr1 };

// The GTR1 lobe, Cycles 3.x's clearcoat: the "generalized Trowbridge-Reitz" distribution
// of exponent 1 (Burley, "Physically Based Shading at Disney", SIGGRAPH 2012 course), a
// sharp core in long tails (the haze around a varnish's highlight):
//   D(m) = (a^2 - 1) / (pi ln(a^2) (1 + (a^2 - 1) cos_m^2)), 1/pi from a = 1 on,
// of alpha a = Clearcoat Roughness^2 (Cycles 3.x squares it when it sets up the closure;
// coat_of here). Its masking and shadowing are Smith's GGX G1 of a FIXED alpha 0.25,
// separable (G1_o G1_i), whatever the roughness, as Cycles 3.x evaluates the closure.
// Isotropic; single scattering (Cycles 3.x keeps no more energy for it).
float gtr1_distribution(float cos_m, float alpha);

// f * cos_i = D G1(wo) G1(wi) / (4 cos_o) about unit normal n, without Fresnel or
// colour; 0 below either horizon.
float gtr1_reflection(const Vec3& n, float alpha, const Vec3& wo, const Vec3& wi);

// A direction drawn from the GTR1 lobe for view wo: the half vector m of density
// D(m) cos_m (inverting its cumulative distribution, Burley 2012: cos_m^2 = (1 -
// a^(2 (1 - u1))) / (1 - a^2), azimuth 2 pi u2), wi = reflect(-wo, m). *weight
// receives f cos_i / pdf = G1(wo) G1(wi) (wo.m) / (cos_o cos_m). False when m faces
// away from the view or wi falls below the surface (weight 0).
bool gtr1_sample_reflection(const Vec3& n, float alpha, const Vec3& wo, float u1, float u2,
                            Vec3* wi, float* weight);

// The density, per unit solid angle, with which gtr1_sample_reflection draws wi:
// D(m) cos_m / (4 wo.m) for m the half vector; 0 below either horizon.
float gtr1_reflection_pdf(const Vec3& n, float alpha, const Vec3& wo, const Vec3& wi);

// A lobe of either model, as the coat's (`model`) and every other layer's (kGgx) rays
// and feelers take it: GGX's functions with `lobe` as is, or GTR1's about its normal,
// of its alpha() (masking: GGX's only; GTR1's is its own).
float lobe_reflection(CoatModel model, const GgxLobe& lobe, const Vec3& wo, const Vec3& wi,
                      Masking masking);
bool lobe_sample_reflection(CoatModel model, const GgxLobe& lobe, const Vec3& wo, float u1,
                            float u2, Vec3* wi, float* weight, Masking masking);
float lobe_reflection_pdf(CoatModel model, const GgxLobe& lobe, const Vec3& wo, const Vec3& wi);

}  // namespace whitted
