#include "scene/material.h"

#include <algorithm>
#include <map>

#include "bindings.h"

namespace whitted::python {
namespace {

// A program and the registers its fields come from, checked against each other.
void set_program(Material* material, std::shared_ptr<Program> program,
                 const std::map<std::string, int64_t>& outputs) {
  if (!program && !outputs.empty()) {
    throw std::invalid_argument("material outputs need a program");
  }
  for (const auto& [name, index] : outputs) {
    const auto* field = std::find(kFieldNames.begin(), kFieldNames.end(), name);
    if (field == kFieldNames.end()) {
      throw std::invalid_argument("'" + name + "' is not a material field");
    }
    if (index < 0 || static_cast<uint64_t>(index) >= program->register_count()) {
      throw std::invalid_argument("output '" + name + "' register " + std::to_string(index) +
                                  " out of range (" + std::to_string(program->register_count()) +
                                  " registers)");
    }
    material->outputs[static_cast<size_t>(field - kFieldNames.begin())] =
        static_cast<int32_t>(index);
  }
  material->program = std::move(program);
}

}  // namespace

void bind_material(py::module_& m) {
  py::class_<Material>(m, "Material", "Whitted parameters: Phong local term, sigma_r, sigma_t.")
      .def(
          py::init([](Vec3 diffuse, Vec3 specular, float shininess, float ambient,
                      Vec3 reflectivity, Vec3 transmissivity, float ior, Vec3 emission, float alpha,
                      std::string diffuse_texture, std::string alpha_texture,
                      std::shared_ptr<Program> program,
                      const std::map<std::string, int64_t>& outputs, float coat_specular,
                      float coat_reflectivity, float coat_shininess, float coat_ior,
                      bool valid_reflection) {
            Material out{diffuse,      specular,       shininess, ambient,
                         reflectivity, transmissivity, ior,       emission};
            for (const float v : {coat_specular, coat_reflectivity, coat_shininess, coat_ior}) {
              if (!std::isfinite(v)) throw std::invalid_argument("coat values must be finite");
            }
            if (coat_ior <= 0.0f) throw std::invalid_argument("coat_ior must be positive");
            out.coat_specular = coat_specular;
            out.coat_reflectivity = coat_reflectivity;
            out.coat_shininess = coat_shininess;
            out.coat_ior = coat_ior;
            out.valid_reflection = valid_reflection;
            if (!std::isfinite(alpha)) throw std::invalid_argument("alpha must be finite");
            out.alpha = std::clamp(alpha, 0.0f, 1.0f);
            out.diffuse_texture = std::move(diffuse_texture);
            out.alpha_texture = std::move(alpha_texture);
            for (const Vec3* v : {&diffuse, &specular, &reflectivity, &transmissivity, &emission}) {
              require_finite(*v, "material colours");
            }
            if (!std::isfinite(shininess) || !std::isfinite(ambient) || !std::isfinite(ior) ||
                ior <= 0.0f) {
              throw std::invalid_argument(
                  "material shininess, ambient and ior must be finite and ior positive");
            }
            set_program(&out, std::move(program), outputs);
            return out;
          }),
          py::arg("diffuse") = Vec3(0.8f), py::arg("specular") = Vec3(0.0f),
          py::arg("shininess") = 50.0f, py::arg("ambient") = 1.0f,
          py::arg("reflectivity") = Vec3(0.0f), py::arg("transmissivity") = Vec3(0.0f),
          py::arg("ior") = 1.5f, py::arg("emission") = Vec3(0.0f), py::arg("alpha") = 1.0f,
          py::arg("diffuse_texture") = "", py::arg("alpha_texture") = "",
          py::arg("program") = py::none(), py::arg("outputs") = std::map<std::string, int64_t>{},
          py::arg("coat_specular") = 0.0f, py::arg("coat_reflectivity") = 0.0f,
          py::arg("coat_shininess") = 1000.0f, py::arg("coat_ior") = 1.5f,
          py::arg("valid_reflection") = false,
          "program: a Program computing some fields per hit; outputs: field name -> register "
          "holding it after the program (diffuse, specular, shininess, reflectivity, "
          "transmissivity, ior, emission, alpha, normal, coat_specular, coat_reflectivity, "
          "coat_shininess, coat_ior, coat_normal); the other fields keep the constants given "
          "here. coat_*: a clear layer on top whose highlight and mirror weights are scaled by "
          "the dielectric Fresnel factor of coat_ior per hit; the rest lights the base.")
      .def_readwrite("diffuse", &Material::diffuse)
      .def_readwrite("specular", &Material::specular)
      .def_readwrite("shininess", &Material::shininess)
      .def_readwrite("ambient", &Material::ambient)
      .def_readwrite("reflectivity", &Material::reflectivity)
      .def_readwrite("transmissivity", &Material::transmissivity)
      .def_readwrite("ior", &Material::ior)
      .def_readwrite("emission", &Material::emission)
      .def_readwrite("alpha", &Material::alpha)
      .def_readwrite("coat_specular", &Material::coat_specular)
      .def_readwrite("coat_reflectivity", &Material::coat_reflectivity)
      .def_readwrite("coat_shininess", &Material::coat_shininess)
      .def_readwrite("coat_ior", &Material::coat_ior)
      .def_readwrite("valid_reflection", &Material::valid_reflection,
                     "Cycles 3.x: turn a program's normal so the view's mirror stays above "
                     "the surface.")
      .def_readwrite("priority", &Material::priority,
                     "Nested dielectrics: where two transmissive objects overlap, the higher "
                     "priority owns the overlap (ties: the one entered last).")
      .def_readwrite("diffuse_texture", &Material::diffuse_texture)
      .def_readwrite("alpha_texture", &Material::alpha_texture)
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
