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
#include <tuple>
#include <vector>

#include "core/aggregate.h"
#include "core/math.h"
#include "scene/microfacet.h"
#include "shader/program.h"

namespace whitted {

// The Whitted fields of a hit a material's program may drive (its `outputs`), defined
// here once: X(enumerator, name, components), components 3 for a colour or a normal, 1
// for a value. The bindings give this table to Python (whitted_native.MATERIAL_FIELDS),
// whose compiler emits a program's outputs in this order; a field that is also a
// MaterialParams member (all but the normals) has that member's name. The volume_* fields
// are the medium's (a heterogeneous medium: its program run at points inside the mesh,
// CompiledScene::medium); displacement, a world vector, is only a displacement's program's
// (scene/displace.h: run once per vertex, never at a hit); the others the surface's.
#define WHITTED_MATERIAL_FIELDS(X)                    \
  X(kDiffuseField, "diffuse", 3)                      \
  X(kSpecularField, "specular", 3)                    \
  X(kShininessField, "shininess", 1)                  \
  X(kReflectivityField, "reflectivity", 3)            \
  X(kTransmissivityField, "transmissivity", 3)        \
  X(kIorField, "ior", 1)                              \
  X(kEmissionField, "emission", 3)                    \
  X(kAlphaField, "alpha", 1)                          \
  X(kNormalField, "normal", 3)                        \
  X(kCoatSpecularField, "coat_specular", 1)           \
  X(kCoatReflectivityField, "coat_reflectivity", 1)   \
  X(kCoatShininessField, "coat_shininess", 1)         \
  X(kCoatIorField, "coat_ior", 1)                     \
  X(kCoatNormalField, "coat_normal", 3)               \
  X(kDiffuseRoughnessField, "diffuse_roughness", 1)   \
  X(kRoughnessField, "roughness", 1)                  \
  X(kCoatRoughnessField, "coat_roughness", 1)         \
  X(kAnisotropyField, "anisotropy", 1)                \
  X(kTangentField, "tangent", 3)                      \
  X(kSheenField, "sheen", 3)                          \
  X(kSheenRoughnessField, "sheen_roughness", 1)       \
  X(kLayerReflectivityField, "layer_reflectivity", 3) \
  X(kLayerIorField, "layer_ior", 1)                   \
  X(kVolumeAbsorptionField, "volume_absorption", 3)   \
  X(kVolumeScatteringField, "volume_scattering", 3)   \
  X(kVolumeAnisotropyField, "volume_anisotropy", 1)   \
  X(kVolumeEmissionField, "volume_emission", 3)       \
  X(kDisplacementField, "displacement", 3)

enum Field : uint32_t {
#define WHITTED_FIELD_ENUMERATOR(enumerator, name, components) enumerator,
  WHITTED_MATERIAL_FIELDS(WHITTED_FIELD_ENUMERATOR)
#undef WHITTED_FIELD_ENUMERATOR
      kFieldCount,
};

// Whether a field is the medium's (the volume_* fields, last in the table) rather than the
// surface's.
constexpr bool medium_field(size_t field) {
  return field >= kVolumeAbsorptionField && field < kFieldCount;
}

struct FieldInfo {
  std::string_view name;
  uint32_t components;
};
inline constexpr std::array<FieldInfo, kFieldCount> kFieldTable = {{
#define WHITTED_FIELD_INFO(enumerator, name, components) {name, components},
    WHITTED_MATERIAL_FIELDS(WHITTED_FIELD_INFO)
#undef WHITTED_FIELD_INFO
}};

// A material's outputs when no field is driven.
inline constexpr std::array<int32_t, kFieldCount> kNoOutputs = [] {
  std::array<int32_t, kFieldCount> none{};
  none.fill(-1);
  return none;
}();

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
};

// Which sides of an emissive mesh shadow feelers sample as a light (Cycles' Emission
// Sampling; scene/mesh_light.h): front is the side its faces' normals point to. A side
// not sampled still shows its emission to the rays that see it.
enum class EmissionSampling : uint32_t { kNone, kFront, kBack, kBoth };

// A material as the exporter describes it. Material's constructor checks it; these
// defaults are a valid grey Lambertian material.
struct MaterialParams {
  // What each member means, its unit and range: its doc in kMaterialParams below.
  Color diffuse{0.8f};
  Color specular{0.0f};
  float shininess = 50.0f;
  float ambient = 1.0f;
  Color reflectivity{0.0f};   // split by Fresnel in split.h
  float roughness = 0.0f;     // GGX of alpha = roughness^2: scene/microfacet.h
  float anisotropy = 0.0f;    // along the program's tangent: ggx_anisotropic_alphas
  bool multiscatter = false;  // ggx_multiscatter_scale
  Masking masking = Masking::kCorrelated;
  Color transmissivity{0.0f};
  float ior = 1.5f;
  Color emission{0.0f};
  EmissionSampling emission_sampling = EmissionSampling::kBoth;  // scene/mesh_light.h
  float alpha = 1.0f;
  bool surface = true;
  // The homogeneous medium its mesh encloses (integrator/volume.h): coefficients per
  // Blender unit of length (per metre at unit scale 1), RGB.
  Color volume_absorption{0.0f};
  Color volume_scattering{0.0f};
  float volume_anisotropy = 0.0f;
  Color volume_emission{0.0f};
  // Cycles' Material > Settings > Volume > Step Rate: a heterogeneous medium's step
  // along a ray is its object's (integrator/heterogeneous.h) times this.
  float volume_step_rate = 1.0f;
  int32_t priority = 0;  // medium.h
  int32_t pass_index = 0;
  // The coat (lobes.h, Coat): a clear dielectric layer over everything above.
  float coat_specular = 0.0f;
  float coat_reflectivity = 0.0f;
  float coat_shininess = 1000.0f;
  float coat_ior = 1.5f;
  float coat_roughness = 0.0f;
  CoatModel coat_model = CoatModel::kGgx;
  // The base's specular layer beneath the coat (lobes.h, layer_of): a clear dielectric
  // layer about the base's normal, of its roughness.
  Color layer_reflectivity{0.0f};
  float layer_ior = 1.5f;
  bool coat_layered = true;
  bool valid_reflection = false;  // Cycles 3.x's ensure_valid_reflection
  BumpShadowing bump_shadowing = BumpShadowing::kNone;
  DiffuseModel diffuse_model = DiffuseModel::kLambert;
  float diffuse_roughness = 0.0f;
  // The sheen lobe (lobes.h velvet_sheen): a lobe of its own beside the diffuse one.
  Color sheen{0.0f};
  float sheen_roughness = 0.0f;
  std::string diffuse_texture{};
  std::string alpha_texture{};
  std::shared_ptr<const Program> program{};
  std::array<int32_t, kFieldCount> outputs = kNoOutputs;  // -1: the constant
};

// MaterialParams' members by name and meaning, defined here once: the bindings take a
// material's parameters as keywords of these names and show them as its attributes,
// documented by `doc`, and give Python the names and defaults
// (whitted_native.MATERIAL_PARAMS), from which the exporter's data class is made. The
// static_assert below keeps it whole.
template <typename T>
struct MaterialParam {
  std::string_view name;
  T MaterialParams::*member;
  std::string_view doc;  // what it is, its unit and range: its Python docstring
};
template <typename T>
MaterialParam(std::string_view, T MaterialParams::*, std::string_view) -> MaterialParam<T>;
inline constexpr auto kMaterialParams = std::tuple{
    MaterialParam{
        "diffuse", &MaterialParams::diffuse,
        "Diffuse albedo kd (linear RGB): the diffuse term is kd/pi times the irradiance."},
    MaterialParam{
        "specular", &MaterialParams::specular,
        "Weight ks of the normalised Phong highlight ks*(f+2)/(2pi)*(v.r)^f that lamps give."},
    MaterialParam{"shininess", &MaterialParams::shininess,
                  "Phong exponent f of the highlight: higher is tighter."},
    MaterialParam{"ambient", &MaterialParams::ambient,
                  "Weight ka of the ambient term ka * ambient * diffuse."},
    MaterialParam{"reflectivity", &MaterialParams::reflectivity,
                  "Mirror (or glossy) reflection weight sigma_r (RGB), before the Fresnel split."},
    MaterialParam{"roughness", &MaterialParams::roughness,
                  "Blender roughness of the reflection in [0, 1] (clamped): below 0.02 a mirror, "
                  "above a GGX lobe of alpha = roughness^2 traced with glossy rays."},
    MaterialParam{"anisotropy", &MaterialParams::anisotropy,
                  "The reflection lobe's anisotropy in [-0.99, 0.99] (clamped), as the Glossy "
                  "BSDF's: above 0 narrower along the tangent field, below 0 wider; it needs "
                  "a program computing the tangent (without one the lobe is round)."},
    MaterialParam{"multiscatter", &MaterialParams::multiscatter,
                  "Cycles' Multiscatter GGX: the glossy lobe keeps the energy its facets pass "
                  "between them; False: single-scattering GGX."},
    MaterialParam{"masking", &MaterialParams::masking,
                  "How the glossy lobe's Smith masking and shadowing combine (a Masking)."},
    MaterialParam{"transmissivity", &MaterialParams::transmissivity,
                  "Refraction weight sigma_t (RGB), before the Fresnel split."},
    MaterialParam{"ior", &MaterialParams::ior,
                  "Index of refraction inside the surface (outside is 1); must be above 0."},
    MaterialParam{"emission", &MaterialParams::emission,
                  "Radiance (W/(m^2 sr), RGB) the surface adds as is."},
    MaterialParam{"emission_sampling", &MaterialParams::emission_sampling,
                  "Which sides of the meshes it covers are sampled as lights (an "
                  "EmissionSampling); a side not sampled still shows its emission."},
    MaterialParam{"alpha", &MaterialParams::alpha,
                  "Coverage in [0, 1] (clamped): 1 opaque, 0 invisible (cut-outs)."},
    MaterialParam{"surface", &MaterialParams::surface,
                  "False: no surface at all (Cycles' material whose output has a Volume and no "
                  "Surface): rays pass through it untouched and it casts no shadow. A mesh "
                  "whose every face has such a material stays in the scene, seen by no ray; "
                  "elsewhere its faces are cut-outs of alpha 0. It has no program or texture."},
    MaterialParam{"volume_absorption", &MaterialParams::volume_absorption,
                  "Absorption coefficient sigma_a (RGB, per Blender unit of length: per metre at "
                  "unit scale 1) of the homogeneous medium the mesh encloses; negative is 0."},
    MaterialParam{"volume_scattering", &MaterialParams::volume_scattering,
                  "Scattering coefficient sigma_s (RGB, per Blender unit of length) of that "
                  "medium, scattered once towards the camera (Henyey-Greenstein); negative is 0."},
    MaterialParam{"volume_anisotropy", &MaterialParams::volume_anisotropy,
                  "Henyey-Greenstein anisotropy g of that medium's scattering, clamped to "
                  "[-0.999, 0.999]: 0 isotropic, above 0 forwards."},
    MaterialParam{"volume_emission", &MaterialParams::volume_emission,
                  "Radiance the medium emits per Blender unit of length (W/(m^2 sr) per unit, "
                  "RGB); negative is 0."},
    MaterialParam{"volume_step_rate", &MaterialParams::volume_step_rate,
                  "Cycles' material Volume Step Rate (above 0): where a program drives the "
                  "medium, the marching step is its object's times this (and the render's)."},
    MaterialParam{"priority", &MaterialParams::priority,
                  "Nested dielectrics: where volumes overlap, the material of higher priority owns "
                  "the overlap."},
    MaterialParam{"pass_index", &MaterialParams::pass_index,
                  "Blender's material Pass Index, written to the IndexMA pass."},
    MaterialParam{"coat_specular", &MaterialParams::coat_specular,
                  "Weight of the coat's normalised Phong highlight."},
    MaterialParam{"coat_reflectivity", &MaterialParams::coat_reflectivity,
                  "Weight of the coat's mirror reflection (scaled by its Fresnel factor)."},
    MaterialParam{"coat_shininess", &MaterialParams::coat_shininess,
                  "Phong exponent of the coat's highlight."},
    MaterialParam{"coat_ior", &MaterialParams::coat_ior,
                  "Index of refraction of the coat (outside is 1); must be above 0."},
    MaterialParam{
        "coat_roughness", &MaterialParams::coat_roughness,
        "Blender roughness of the coat's reflection in [0, 1], as roughness is for the base."},
    MaterialParam{"coat_model", &MaterialParams::coat_model,
                  "The distribution of the coat's rough lobe (a CoatModel): GGX, or GTR1 as "
                  "Cycles 3.x's Clearcoat."},
    MaterialParam{"layer_reflectivity", &MaterialParams::layer_reflectivity,
                  "Weight (linear RGB) of a clear dielectric layer's mirror beneath the coat (a "
                  "Principled BSDF's specular layer under its coat), scaled by its Fresnel "
                  "factor; it follows the base's normal, roughness and anisotropy."},
    MaterialParam{"layer_ior", &MaterialParams::layer_ior,
                  "Index of refraction of that layer (outside is 1); must be above 0."},
    MaterialParam{"coat_layered", &MaterialParams::coat_layered,
                  "True: the layers beneath get only the light the coat lets through (Cycles 4.0 "
                  "on); False: the coat is added on top (Cycles 3.x)."},
    MaterialParam{"valid_reflection", &MaterialParams::valid_reflection,
                  "Cycles 3.x: turn the shading normal towards the geometric one so the mirror "
                  "direction of the view stays above the surface."},
    MaterialParam{"bump_shadowing", &MaterialParams::bump_shadowing,
                  "How a diffuse lobe under a program's normal fades (a BumpShadowing)."},
    MaterialParam{"diffuse_model", &MaterialParams::diffuse_model,
                  "The shape of the diffuse lobe (a DiffuseModel)."},
    MaterialParam{"diffuse_roughness", &MaterialParams::diffuse_roughness,
                  "Roughness in [0, 1] (clamped) shaping a diffuse_model other than LAMBERT."},
    MaterialParam{"sheen", &MaterialParams::sheen,
                  "Weight (linear RGB) of the sheen lobe: Ashikhmin's velvet (the Velvet BSDF, "
                  "the Sheen BSDF), a lobe of its own beside the diffuse one; negative is 0."},
    MaterialParam{"sheen_roughness", &MaterialParams::sheen_roughness,
                  "The velvet lobe's sigma in [0, 1] (clamped): higher spreads the sheen from "
                  "the grazing views."},
    MaterialParam{"diffuse_texture", &MaterialParams::diffuse_texture,
                  "Name of a scene texture whose RGB multiplies diffuse (empty: none)."},
    MaterialParam{"alpha_texture", &MaterialParams::alpha_texture,
                  "Name of a scene texture whose A multiplies alpha (empty: none)."},
    MaterialParam{"program", &MaterialParams::program,
                  "A Program computing some fields per hit, or None."},
    MaterialParam{"outputs", &MaterialParams::outputs,
                  "{field name (MATERIAL_FIELDS): register holding it after program}; the other "
                  "fields keep their constants."},
};
static_assert(aggregate_member_count<MaterialParams>() ==
                  std::tuple_size_v<decltype(kMaterialParams)>,
              "kMaterialParams must name every member of MaterialParams");

struct Material : MaterialParams {
  Material() = default;
  // Throws std::invalid_argument for what cannot be a material (a non-finite colour,
  // shininess, ambient, IOR, alpha or coat value; an IOR or coat IOR not above 0; outputs
  // without a program, or naming a register it does not have; a program or texture on a
  // material without a surface, unless it drives only the medium's fields; a volume step
  // rate not above 0) and clamps alpha to [0, 1], 0 without a surface, the volume's
  // coefficients to at least 0 and its anisotropy to [-0.999, 0.999].
  explicit Material(const MaterialParams& params);

  // Indices into CompiledScene::textures, resolved by Scene::compile (-1: none).
  int32_t diffuse_texture_index = -1;
  int32_t alpha_texture_index = -1;
  // The program's images, resolved by Scene::compile.
  std::vector<const ImageTexture*> program_images;

  bool driven(Field field) const { return outputs[field] >= 0; }
  // Whether a hit may reflect or transmit: a program-driven weight may be non-zero.
  // Whether its reflection can be glossy: a lobe rougher than a mirror, or one a program
  // computes (glossy rays and GGX highlights: integrator/glossy.h, local.h).
  bool glossy() const {
    const bool base =
        (roughness * roughness >= kMirrorAlpha || driven(kRoughnessField)) &&
        (!is_black(reflectivity) || driven(kReflectivityField) || transmissive() || layered());
    const bool coat =
        (coat_roughness * coat_roughness >= kMirrorAlpha || driven(kCoatRoughnessField)) &&
        (coat_reflectivity > 0.0f || driven(kCoatReflectivityField));
    return base || coat;
  }
  bool reflective() const {
    return !is_black(reflectivity) || driven(kReflectivityField) || coat_reflectivity > 0.0f ||
           driven(kCoatReflectivityField) || layered();
  }
  // Whether it has a specular layer beneath its coat (layer_reflectivity).
  bool layered() const { return !is_black(layer_reflectivity) || driven(kLayerReflectivityField); }
  // Whether the mesh encloses a medium that absorbs, scatters or emits (a volume shader's
  // constant coefficients, integrator/volume.h, or a program's); a zero volume is none.
  bool participating() const {
    return !is_black(volume_absorption) || !is_black(volume_scattering) ||
           !is_black(volume_emission) || heterogeneous();
  }
  // Whether its medium emits somewhere: a positive constant emission (a channel of it)
  // or a program's (a glowing medium lights surfaces: integrator/lights.h).
  bool glows() const {
    const bool constant =
        volume_emission.x > 0.0f || volume_emission.y > 0.0f || volume_emission.z > 0.0f;
    return constant || driven(kVolumeEmissionField);
  }
  // Whether a program drives its medium (integrator/heterogeneous.h): its coefficients
  // vary from point to point.
  bool heterogeneous() const {
    for (size_t f = kVolumeAbsorptionField; f < kFieldCount; ++f) {
      if (outputs[f] >= 0) return true;
    }
    return false;
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

}  // namespace whitted
