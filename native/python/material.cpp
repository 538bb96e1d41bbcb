#include "scene/material.h"

#include <algorithm>
#include <map>

#include "bindings.h"

namespace whitted::python {
namespace {

// Field name -> register as Material's outputs array (-1: the constant). Which registers
// the program has is Material's constructor's to check.
std::array<int32_t, kFieldCount> field_outputs(const std::map<std::string, int64_t>& outputs) {
  std::array<int32_t, kFieldCount> out;
  out.fill(-1);
  for (const auto& [name, index] : outputs) {
    const auto* field = std::find(kFieldNames.begin(), kFieldNames.end(), name);
    if (field == kFieldNames.end()) {
      throw std::invalid_argument("'" + name + "' is not a material field");
    }
    if (index < 0) {
      throw std::invalid_argument("output '" + name + "' register " + std::to_string(index) +
                                  " is negative");
    }
    // Beyond int32 is beyond any program's registers: the constructor says so.
    out[static_cast<size_t>(field - kFieldNames.begin())] =
        static_cast<int32_t>(std::min<int64_t>(index, INT32_MAX));
  }
  return out;
}

}  // namespace

void bind_material(py::module_& m) {
  const MaterialParams defaults;
  py::enum_<BumpShadowing>(m, "BumpShadowing",
                           "How a diffuse lobe under a program's normal fades towards the smooth "
                           "surface's horizon (Cycles' bump shadowing term, by Blender version).")
      .value("NONE", BumpShadowing::kNone)
      .value("SMOOTH_SIDE", BumpShadowing::kSmoothSide)
      .value("CHIANG", BumpShadowing::kChiang)
      .value("MICROFACET", BumpShadowing::kMicrofacet);
  py::enum_<Masking>(m, "Masking",
                     "How a glossy lobe's Smith masking and shadowing combine: CORRELATED "
                     "(height-correlated, Cycles 4.0 on) or SEPARABLE (G1_o G1_i, Cycles 3.x).")
      .value("CORRELATED", Masking::kCorrelated)
      .value("SEPARABLE", Masking::kSeparable);
  py::enum_<DiffuseModel>(m, "DiffuseModel",
                          "The shape of the diffuse lobe: LAMBERT; BURLEY (Burley's diffuse with "
                          "retro-reflection: Cycles 3.x's Principled BSDF), OREN_NAYAR (a rough "
                          "Diffuse BSDF) or OREN_NAYAR_ENERGY (with Cycles 4.3+'s multiple "
                          "scattering), shaped by diffuse_roughness.")
      .value("LAMBERT", DiffuseModel::kLambert)
      .value("BURLEY", DiffuseModel::kBurley)
      .value("OREN_NAYAR", DiffuseModel::kOrenNayar)
      .value("OREN_NAYAR_ENERGY", DiffuseModel::kOrenNayarEnergy)
      .value("VELVET", DiffuseModel::kVelvet);
  py::enum_<EmissionSampling>(m, "EmissionSampling",
                              "Which sides of an emissive mesh light the scene as a light "
                              "(Cycles' Emission Sampling): NONE, FRONT, BACK or BOTH.")
      .value("NONE", EmissionSampling::kNone)
      .value("FRONT", EmissionSampling::kFront)
      .value("BACK", EmissionSampling::kBack)
      .value("BOTH", EmissionSampling::kBoth);
  py::class_<Material>(m, "Material", "Whitted parameters: Phong local term, sigma_r, sigma_t.")
      .def(py::init([](Vec3 diffuse, Vec3 specular, float shininess, float ambient,
                       Vec3 reflectivity, Vec3 transmissivity, float ior, Vec3 emission,
                       float alpha, std::string diffuse_texture, std::string alpha_texture,
                       std::shared_ptr<Program> program,
                       const std::map<std::string, int64_t>& outputs, float coat_specular,
                       float coat_reflectivity, float coat_shininess, float coat_ior,
                       bool coat_layered, bool valid_reflection, BumpShadowing bump_shadowing,
                       DiffuseModel diffuse_model, float diffuse_roughness, int32_t pass_index,
                       float roughness, bool multiscatter, Masking masking, float coat_roughness,
                       EmissionSampling emission_sampling) {
             // Material's constructor checks the values (std::invalid_argument: ValueError).
             return Material(MaterialParams{.diffuse = diffuse,
                                            .specular = specular,
                                            .shininess = shininess,
                                            .ambient = ambient,
                                            .reflectivity = reflectivity,
                                            .roughness = roughness,
                                            .multiscatter = multiscatter,
                                            .masking = masking,
                                            .transmissivity = transmissivity,
                                            .ior = ior,
                                            .emission = emission,
                                            .emission_sampling = emission_sampling,
                                            .alpha = alpha,
                                            .pass_index = pass_index,
                                            .coat_specular = coat_specular,
                                            .coat_reflectivity = coat_reflectivity,
                                            .coat_shininess = coat_shininess,
                                            .coat_ior = coat_ior,
                                            .coat_roughness = coat_roughness,
                                            .coat_layered = coat_layered,
                                            .valid_reflection = valid_reflection,
                                            .bump_shadowing = bump_shadowing,
                                            .diffuse_model = diffuse_model,
                                            .diffuse_roughness = diffuse_roughness,
                                            .diffuse_texture = std::move(diffuse_texture),
                                            .alpha_texture = std::move(alpha_texture),
                                            .program = std::move(program),
                                            .outputs = field_outputs(outputs)});
           }),
           py::arg("diffuse") = defaults.diffuse, py::arg("specular") = defaults.specular,
           py::arg("shininess") = defaults.shininess, py::arg("ambient") = defaults.ambient,
           py::arg("reflectivity") = defaults.reflectivity,
           py::arg("transmissivity") = defaults.transmissivity, py::arg("ior") = defaults.ior,
           py::arg("emission") = defaults.emission, py::arg("alpha") = defaults.alpha,
           py::arg("diffuse_texture") = "", py::arg("alpha_texture") = "",
           py::arg("program") = py::none(), py::arg("outputs") = std::map<std::string, int64_t>{},
           py::arg("coat_specular") = defaults.coat_specular,
           py::arg("coat_reflectivity") = defaults.coat_reflectivity,
           py::arg("coat_shininess") = defaults.coat_shininess,
           py::arg("coat_ior") = defaults.coat_ior, py::arg("coat_layered") = defaults.coat_layered,
           py::arg("valid_reflection") = defaults.valid_reflection,
           py::arg("bump_shadowing") = defaults.bump_shadowing,
           py::arg("diffuse_model") = defaults.diffuse_model,
           py::arg("diffuse_roughness") = defaults.diffuse_roughness,
           py::arg("pass_index") = defaults.pass_index, py::arg("roughness") = defaults.roughness,
           py::arg("multiscatter") = defaults.multiscatter, py::arg("masking") = defaults.masking,
           py::arg("coat_roughness") = defaults.coat_roughness,
           py::arg("emission_sampling") = defaults.emission_sampling,
           "program: a Program computing some fields per hit; outputs: field name -> register "
           "holding it after the program (diffuse, specular, shininess, reflectivity, "
           "transmissivity, ior, emission, alpha, normal, coat_specular, coat_reflectivity, "
           "coat_shininess, coat_ior, coat_normal, diffuse_roughness, roughness); the other fields "
           "keep the constants given here. roughness: Blender's roughness of the reflection "
           "lobe (below 0.02 a mirror; above, GGX of alpha roughness^2, its rays glossy). coat_*: "
           "a clear layer on top whose highlight and mirror weights are scaled by "
           "the dielectric Fresnel factor of coat_ior per hit; the rest lights the base (with "
           "coat_layered; without it the coat is added on top, as Cycles 3.x does).")
      .def_readonly("diffuse", &Material::diffuse)
      .def_readonly("specular", &Material::specular)
      .def_readonly("shininess", &Material::shininess)
      .def_readonly("ambient", &Material::ambient)
      .def_readonly("reflectivity", &Material::reflectivity)
      .def_readonly("roughness", &Material::roughness)
      .def_readonly("masking", &Material::masking)
      .def_readonly("multiscatter", &Material::multiscatter,
                    "Cycles' Multiscatter GGX: the glossy lobe keeps the energy its facets "
                    "pass between them.")
      .def_readonly("transmissivity", &Material::transmissivity)
      .def_readonly("ior", &Material::ior)
      .def_readonly("emission", &Material::emission)
      .def_readonly("alpha", &Material::alpha)
      .def_readonly("emission_sampling", &Material::emission_sampling,
                    "Which sides of the meshes it covers light the scene as a light.")
      .def_readonly("coat_specular", &Material::coat_specular)
      .def_readonly("coat_reflectivity", &Material::coat_reflectivity)
      .def_readonly("coat_shininess", &Material::coat_shininess)
      .def_readonly("coat_ior", &Material::coat_ior)
      .def_readonly("coat_roughness", &Material::coat_roughness)
      .def_readonly("coat_layered", &Material::coat_layered)
      .def_readonly("valid_reflection", &Material::valid_reflection,
                    "Cycles 3.x: turn a program's normal so the view's mirror stays above "
                    "the surface.")
      .def_readonly("bump_shadowing", &Material::bump_shadowing)
      .def_readonly("diffuse_model", &Material::diffuse_model)
      .def_readonly("diffuse_roughness", &Material::diffuse_roughness)
      .def_readonly("priority", &Material::priority,
                    "Nested dielectrics: where two transmissive objects overlap, the higher "
                    "priority owns the overlap (ties: the one entered last).")
      .def_readonly("pass_index", &Material::pass_index,
                    "Blender's material Pass Index, for the IndexMA pass.")
      .def_readonly("diffuse_texture", &Material::diffuse_texture)
      .def_readonly("alpha_texture", &Material::alpha_texture)
      .def_property_readonly(
          "program", [](const Material& m) { return std::const_pointer_cast<Program>(m.program); })
      .def_property_readonly("outputs", [](const Material& m) {
        std::map<std::string, int32_t> out;
        for (size_t f = 0; f < kFieldCount; ++f) {
          if (m.outputs[f] >= 0) out[std::string(kFieldNames[f])] = m.outputs[f];
        }
        return out;
      });
}

}  // namespace whitted::python
