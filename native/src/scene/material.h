// Whitted material parameters: Phong local term plus reflection and transmission weights.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/math.h"
#include "scene/microfacet.h"
#include "texture/program.h"

namespace whitted {

// The Whitted fields of a hit a material's program may drive (its `outputs`).
enum Field : uint32_t {
  kDiffuseField,
  kSpecularField,
  kShininessField,
  kReflectivityField,
  kTransmissivityField,
  kIorField,
  kEmissionField,
  kAlphaField,
  kNormalField,
  kCoatSpecularField,
  kCoatReflectivityField,
  kCoatShininessField,
  kCoatIorField,
  kCoatNormalField,
  kDiffuseRoughnessField,
  kRoughnessField,
  kCoatRoughnessField,
  kFieldCount,
};
inline constexpr std::array<std::string_view, kFieldCount> kFieldNames = {
    "diffuse",        "specular",      "shininess",         "reflectivity",
    "transmissivity", "ior",           "emission",          "alpha",
    "normal",         "coat_specular", "coat_reflectivity", "coat_shininess",
    "coat_ior",       "coat_normal",   "diffuse_roughness", "roughness",
    "coat_roughness"};

// How a diffuse lobe shaded with a program's normal (a normal map, a bump) fades where
// that normal leans towards a light the smooth surface turns away from: Cycles' bump
// shadowing term, which differs by Blender version (diffuse_shadowing).
enum class BumpShadowing : uint32_t {
  kNone,        // no fading: the normal is the interpolated one
  kSmoothSide,  // only light under the smooth surface is cut (Cycles 4.x+, bump map
                // correction off)
  kChiang,      // Chiang, Li & Burley 2019, "Taming the Shadow Terminator" (Cycles 3.x)
  kMicrofacet,  // Conty Estevez, Lecocq & Stein 2019, a GGX shadowing term from the
                // normal's tilt (Cycles 4.x+ with bump map correction on)
};

// The shape of the diffuse lobe kd/pi * E (l.n) * shape, by the BSDF it stands for.
enum class DiffuseModel : uint32_t {
  kLambert,          // shape 1: Lambert (Diffuse BSDF; Principled BSDF from Blender 4.0 on)
  kBurley,           // Burley's diffuse with retro-reflection (burley_diffuse): Cycles 3.x's
                     // Principled BSDF, whose roughness shapes it
  kOrenNayar,        // Oren-Nayar's rough diffuse in Fujii's form (oren_nayar_diffuse): a
                     // Diffuse BSDF of roughness above 0 (Blender 3.x)
  kOrenNayarEnergy,  // the same plus the multiple scattering Cycles 4.3+ adds to keep
                     // its energy (oren_nayar_multiscatter), also for the Principled
                     // BSDF's Diffuse Roughness
  kVelvet,           // Ashikhmin's velvet (velvet_diffuse): the Velvet BSDF (3.x) and the
                     // Sheen BSDF's Ashikhmin distribution (4.x+), its sigma the roughness
};

// Which sides of an emissive mesh shadow feelers sample as a light (Cycles' Emission
// Sampling; scene/mesh_light.h): front is the side its faces' normals point to. A side
// not sampled still shows its emission to the rays that see it.
enum class EmissionSampling : uint32_t { kNone, kFront, kBack, kBoth };

// A material as the exporter describes it. Material's constructor checks it; these
// defaults are a valid grey Lambertian material.
struct MaterialParams {
  Color diffuse{0.8f};       // albedo kd: the diffuse term is kd/pi * E
  Color specular{0.0f};      // ks of a normalised Phong lobe ks*(f+2)/(2pi)*(v.r)^f * E
  float shininess = 50.0f;   // Phong exponent f
  float ambient = 1.0f;      // ka: the ambient term is ka * Ia * kd
  Color reflectivity{0.0f};  // sigma_r before the Fresnel split (whitted.cpp)
  // Blender's roughness of the reflection lobe: 0 (below 0.02) a mirror, as Whitted's;
  // above, the GGX lobe of alpha = roughness^2 (scene/microfacet.h), whose rays are
  // glossy and whose highlight lamps give of its colour, `reflectivity`. In [0, 1].
  float roughness = 0.0f;
  // Cycles' Multiscatter GGX: the lobe keeps the energy its facets pass between them
  // (ggx_multiscatter_scale); false: GGX's single scattering.
  bool multiscatter = false;
  // How the lobe's masking and shadowing combine (Cycles 3.x: separable).
  Masking masking = Masking::kCorrelated;
  Color transmissivity{0.0f};  // sigma_t before the Fresnel split
  float ior = 1.5f;            // index of refraction inside the surface (outside: 1)
  Color emission{0.0f};        // radiance added as is
  // Which sides of the meshes it covers light the scene (scene/mesh_light.h).
  EmissionSampling emission_sampling = EmissionSampling::kBoth;
  float alpha = 1.0f;      // coverage: 1 opaque, 0 invisible (cut-outs)
  int32_t priority = 0;    // nested dielectrics: the higher owns overlaps (medium.h)
  int32_t pass_index = 0;  // Blender's material Pass Index (the IndexMA pass)
  // The coat: a clear dielectric layer over everything above. At a hit it reflects its
  // weights times the dielectric Fresnel factor of coat_ior at its own normal, and what
  // lies beneath receives the rest (whitted.cpp, Coat).
  float coat_specular = 0.0f;      // weight of its normalised Phong highlight
  float coat_reflectivity = 0.0f;  // weight of its mirror reflection
  float coat_shininess = 1000.0f;  // Phong exponent of its highlight
  float coat_ior = 1.5f;           // index of refraction of the coat (outside: 1)
  // Blender's roughness of the coat's reflection: as `roughness` for the base, a mirror
  // up to 0.02, above it the GGX lobe of its mirror weight (glossy rays, GGX highlights).
  float coat_roughness = 0.0f;
  // Whether what the coat reflects is taken from the light the layers beneath receive
  // (Cycles 4.0 on); false: the coat is added on top of them, as Cycles 3.x's Principled
  // BSDF adds its specular and Clearcoat lobes to its diffuse one.
  bool coat_layered = true;
  // Cycles 3.x: the shading normal (a program's, or the interpolated one) is turned
  // towards the geometric normal just enough that the view's mirror direction stays
  // above the surface, for every lobe (its ensure_valid_reflection; 4.x+ does so for
  // specular lobes only, and Whitted then not at all).
  bool valid_reflection = false;
  BumpShadowing bump_shadowing = BumpShadowing::kNone;  // for a program's normal
  DiffuseModel diffuse_model = DiffuseModel::kLambert;
  float diffuse_roughness = 0.0f;  // what shapes a lobe other than kLambert, in [0, 1]
  std::string diffuse_texture{};   // multiplies `diffuse` by its RGB ("" for none)
  std::string alpha_texture{};     // multiplies `alpha` by its A ("" for none)
  // Fields a program computes per hit: the register holding each after the program, -1
  // for the constant above.
  std::shared_ptr<const Program> program{};
  std::array<int32_t, kFieldCount> outputs = {-1, -1, -1, -1, -1, -1, -1, -1, -1,
                                              -1, -1, -1, -1, -1, -1, -1, -1};
};

struct Material : MaterialParams {
  Material() = default;
  // Throws std::invalid_argument for what cannot be a material (a non-finite colour,
  // shininess, ambient, IOR, alpha or coat value; an IOR or coat IOR not above 0; outputs
  // without a program, or naming a register it does not have) and clamps alpha to [0, 1].
  explicit Material(const MaterialParams& params);

  // Indices into CompiledScene::textures, resolved by Scene::compile (-1: none).
  int32_t diffuse_texture_index = -1;
  int32_t alpha_texture_index = -1;
  // The program's images, resolved by Scene::compile.
  std::vector<const ImageTexture*> program_images;

  bool driven(Field field) const { return outputs[field] >= 0; }
  // Whether a hit may reflect or transmit: a program-driven weight may be non-zero.
  // Whether its reflection can be glossy: a lobe rougher than a mirror, or one a program
  // computes (glossy rays and GGX highlights: whitted.cpp).
  bool glossy() const {
    const bool base = (roughness * roughness >= kMirrorAlpha || driven(kRoughnessField)) &&
                      (!is_black(reflectivity) || driven(kReflectivityField) || transmissive());
    const bool coat =
        (coat_roughness * coat_roughness >= kMirrorAlpha || driven(kCoatRoughnessField)) &&
        (coat_reflectivity > 0.0f || driven(kCoatReflectivityField));
    return base || coat;
  }
  bool reflective() const {
    return !is_black(reflectivity) || driven(kReflectivityField) || coat_reflectivity > 0.0f ||
           driven(kCoatReflectivityField);
  }
  bool transmissive() const { return !is_black(transmissivity) || driven(kTransmissivityField); }
  // Lets some light through: transmission, or coverage below 1 (after compile, which
  // resolves the alpha texture).
  bool translucent() const { return transmissive() || cut_out(); }
  // Coverage below 1 somewhere: camera and shadow rays pass its holes.
  bool cut_out() const { return alpha < 1.0f || alpha_texture_index >= 0 || driven(kAlphaField); }
};

// The factor on the diffuse lobe for light from `wi` when it is shaded with normal `n`
// but the interpolated (smooth) normal is `smooth`, both unit and on the side the ray
// comes from, as Cycles applies it to every diffuse closure whose normal was changed.
// Inline for its common case (no fading: every hit of a constant material pays this per
// light), the tilted normal out of line.
float tilted_diffuse_shadowing(BumpShadowing model, const Vec3& smooth, const Vec3& n,
                               const Vec3& wi);
inline float diffuse_shadowing(BumpShadowing model, const Vec3& smooth, const Vec3& n,
                               const Vec3& wi) {
  if (model == BumpShadowing::kNone || n == smooth) return 1.0f;
  return tilted_diffuse_shadowing(model, smooth, n, wi);
}

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

// The shape of a kVelvet lobe, relative to Lambert's: Ashikhmin's velvet distribution
// D = exp(-cot^2(h) / sigma^2) / (pi sigma^2 sin^4(h)) with the shadowing
// G = min(1, 2 (n.h)(n.v)/(v.h), 2 (n.h)(n.l)/(v.h)), whose f cos_l = D G / (4 cos_v), as
// Cycles evaluates its velvet closure (sigma at least 0.01). From cos_l = n.l, cos_v = n.v
// and l_dot_v = l.v: |l + v| = sqrt(2 + 2 l.v), n.h = (n.l + n.v)/|l + v|,
// v.h = (1 + l.v)/|l + v|. Returns pi f / 1, what multiplies kd/pi.
inline float velvet_diffuse(float cos_l, float cos_v, float l_dot_v, float sigma) {
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

}  // namespace whitted
