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
// MaterialParams member (all but the normals) has that member's name.
#define WHITTED_MATERIAL_FIELDS(X)                  \
  X(kDiffuseField, "diffuse", 3)                    \
  X(kSpecularField, "specular", 3)                  \
  X(kShininessField, "shininess", 1)                \
  X(kReflectivityField, "reflectivity", 3)          \
  X(kTransmissivityField, "transmissivity", 3)      \
  X(kIorField, "ior", 1)                            \
  X(kEmissionField, "emission", 3)                  \
  X(kAlphaField, "alpha", 1)                        \
  X(kNormalField, "normal", 3)                      \
  X(kCoatSpecularField, "coat_specular", 1)         \
  X(kCoatReflectivityField, "coat_reflectivity", 1) \
  X(kCoatShininessField, "coat_shininess", 1)       \
  X(kCoatIorField, "coat_ior", 1)                   \
  X(kCoatNormalField, "coat_normal", 3)             \
  X(kDiffuseRoughnessField, "diffuse_roughness", 1) \
  X(kRoughnessField, "roughness", 1)                \
  X(kCoatRoughnessField, "coat_roughness", 1)

enum Field : uint32_t {
#define WHITTED_FIELD_ENUMERATOR(enumerator, name, components) enumerator,
  WHITTED_MATERIAL_FIELDS(WHITTED_FIELD_ENUMERATOR)
#undef WHITTED_FIELD_ENUMERATOR
      kFieldCount,
};

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
  Color reflectivity{0.0f};  // sigma_r before the Fresnel split (split.h)
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
  // lies beneath receives the rest (lobes.h, Coat).
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
  std::array<int32_t, kFieldCount> outputs = kNoOutputs;
};

// MaterialParams' members by name, defined here once: the bindings take a material's
// parameters as keywords of these names and show them as its attributes, and give
// Python the names and defaults (whitted_native.MATERIAL_PARAMS), from which the
// exporter's data class is made. The static_assert below keeps it whole.
template <typename T>
struct MaterialParam {
  std::string_view name;
  T MaterialParams::*member;
};
template <typename T>
MaterialParam(std::string_view, T MaterialParams::*) -> MaterialParam<T>;
inline constexpr auto kMaterialParams = std::tuple{
    MaterialParam{"diffuse", &MaterialParams::diffuse},
    MaterialParam{"specular", &MaterialParams::specular},
    MaterialParam{"shininess", &MaterialParams::shininess},
    MaterialParam{"ambient", &MaterialParams::ambient},
    MaterialParam{"reflectivity", &MaterialParams::reflectivity},
    MaterialParam{"roughness", &MaterialParams::roughness},
    MaterialParam{"multiscatter", &MaterialParams::multiscatter},
    MaterialParam{"masking", &MaterialParams::masking},
    MaterialParam{"transmissivity", &MaterialParams::transmissivity},
    MaterialParam{"ior", &MaterialParams::ior},
    MaterialParam{"emission", &MaterialParams::emission},
    MaterialParam{"emission_sampling", &MaterialParams::emission_sampling},
    MaterialParam{"alpha", &MaterialParams::alpha},
    MaterialParam{"priority", &MaterialParams::priority},
    MaterialParam{"pass_index", &MaterialParams::pass_index},
    MaterialParam{"coat_specular", &MaterialParams::coat_specular},
    MaterialParam{"coat_reflectivity", &MaterialParams::coat_reflectivity},
    MaterialParam{"coat_shininess", &MaterialParams::coat_shininess},
    MaterialParam{"coat_ior", &MaterialParams::coat_ior},
    MaterialParam{"coat_roughness", &MaterialParams::coat_roughness},
    MaterialParam{"coat_layered", &MaterialParams::coat_layered},
    MaterialParam{"valid_reflection", &MaterialParams::valid_reflection},
    MaterialParam{"bump_shadowing", &MaterialParams::bump_shadowing},
    MaterialParam{"diffuse_model", &MaterialParams::diffuse_model},
    MaterialParam{"diffuse_roughness", &MaterialParams::diffuse_roughness},
    MaterialParam{"diffuse_texture", &MaterialParams::diffuse_texture},
    MaterialParam{"alpha_texture", &MaterialParams::alpha_texture},
    MaterialParam{"program", &MaterialParams::program},
    MaterialParam{"outputs", &MaterialParams::outputs},
};
static_assert(aggregate_member_count<MaterialParams>() ==
                  std::tuple_size_v<decltype(kMaterialParams)>,
              "kMaterialParams must name every member of MaterialParams");

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
  // computes (glossy rays and GGX highlights: integrator/glossy.h, local.h).
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

}  // namespace whitted
