#include "scene/material.h"

#include <algorithm>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <type_traits>

#include "bindings.h"

namespace whitted::python {
namespace {

// Field name -> register as Material's outputs array (-1: the constant). Which registers
// the program has is Material's constructor's to check.
std::array<int32_t, kFieldCount> field_outputs(const std::map<std::string, int64_t>& outputs) {
  std::array<int32_t, kFieldCount> out = kNoOutputs;
  for (const auto& [name, index] : outputs) {
    const auto* field = std::find_if(kFieldTable.begin(), kFieldTable.end(),
                                     [&](const FieldInfo& f) { return f.name == name; });
    if (field == kFieldTable.end()) {
      throw std::invalid_argument("'" + name + "' is not a material field");
    }
    if (index < 0) {
      throw std::invalid_argument("output '" + name + "' register " + std::to_string(index) +
                                  " is negative");
    }
    // Beyond int32 is beyond any program's registers: the constructor says so.
    out[static_cast<size_t>(field - kFieldTable.begin())] =
        static_cast<int32_t>(std::min<int64_t>(index, INT32_MAX));
  }
  return out;
}

// One parameter from Python: an enum also by its member's name (what the exporter
// writes), the program's outputs as {field name: register}. ValueError or TypeError
// naming the parameter for what cannot be it.
template <typename T>
T from_python(std::string_view name, py::handle value) {
  const std::string param(name);
  if constexpr (std::is_same_v<T, std::shared_ptr<const Program>>) {
    if (value.is_none()) return nullptr;
    if (!py::isinstance<Program>(value)) {
      throw py::type_error(param + ": expected a Program or None, got " +
                           py::str(py::type::handle_of(value)).cast<std::string>());
    }
    return value.cast<std::shared_ptr<Program>>();
  } else if constexpr (std::is_same_v<T, std::array<int32_t, kFieldCount>>) {
    return field_outputs(from_python<std::map<std::string, int64_t>>(name, value));
  } else if constexpr (std::is_enum_v<T>) {
    const py::object type = py::type::of(py::cast(T{}));  // its py::enum_
    if (py::isinstance(value, type)) return value.cast<T>();
    const py::dict members = type.attr("__members__");
    if (!py::isinstance<py::str>(value) || !members.contains(value)) {
      throw py::value_error(param + ": " + py::repr(value).cast<std::string>() + " is not a " +
                            type.attr("__name__").cast<std::string>() + " (" +
                            py::str(", ").attr("join")(members).cast<std::string>() + ")");
    }
    return members[value].cast<T>();
  } else {
    py::detail::make_caster<T> caster;
    if (!caster.load(value, true)) {
      throw py::type_error(param + ": expected " + py::detail::make_caster<T>::name.text +
                           ", got " + py::repr(value).cast<std::string>());
    }
    return py::detail::cast_op<T>(std::move(caster));
  }
}

// One parameter as Python sees it: enums as their members (by name in a default, as
// the constructor takes them), the outputs as {field name: register}.
template <typename T>
py::object to_python(const T& value) {
  if constexpr (std::is_same_v<T, std::shared_ptr<const Program>>) {
    return py::cast(std::const_pointer_cast<Program>(value));
  } else if constexpr (std::is_same_v<T, std::array<int32_t, kFieldCount>>) {
    py::dict out;
    for (size_t f = 0; f < kFieldCount; ++f) {
      if (value[f] >= 0) out[py::str(std::string(kFieldTable[f].name))] = value[f];
    }
    return std::move(out);
  } else {
    return py::cast(value);
  }
}

// A parameter's default as the constructor takes it (an enum by its member's name).
template <typename T>
py::object default_of(const T& value) {
  if constexpr (std::is_enum_v<T>) {
    return py::cast(value).attr("name");
  } else {
    return to_python(value);
  }
}

// The MaterialParams of keyword arguments named as kMaterialParams; TypeError for a
// keyword that is not one.
MaterialParams material_params(const py::kwargs& kwargs) {
  MaterialParams params;
  for (const auto& [key, value] : kwargs) {
    const auto name = key.cast<std::string>();
    const bool known = std::apply(
        [&](const auto&... param) {
          return ((param.name == name &&
                   (params.*param.member =
                        from_python<std::remove_cvref_t<decltype(params.*param.member)>>(param.name,
                                                                                         value),
                    true)) ||
                  ...);
        },
        kMaterialParams);
    if (!known)
      throw py::type_error("Material() got an unexpected keyword argument '" + name + "'");
  }
  return params;
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
  py::enum_<CoatModel>(m, "CoatModel",
                       "The distribution of a coat's rough lobe: GGX (Blender 4.0 on) or GTR1 "
                       "(Blender 3.x's Clearcoat, as Cycles 3.x: its masking of a fixed alpha "
                       "0.25).")
      .value("GGX", CoatModel::kGgx)
      .value("GTR1", CoatModel::kGtr1);
  py::enum_<DiffuseModel>(m, "DiffuseModel",
                          "The shape of the diffuse lobe: LAMBERT; BURLEY (Burley's diffuse with "
                          "retro-reflection: Cycles 3.x's Principled BSDF), OREN_NAYAR (a rough "
                          "Diffuse BSDF) or OREN_NAYAR_ENERGY (with Cycles 4.3+'s multiple "
                          "scattering), shaped by diffuse_roughness.")
      .value("LAMBERT", DiffuseModel::kLambert)
      .value("BURLEY", DiffuseModel::kBurley)
      .value("OREN_NAYAR", DiffuseModel::kOrenNayar)
      .value("OREN_NAYAR_ENERGY", DiffuseModel::kOrenNayarEnergy);
  py::enum_<EmissionSampling>(m, "EmissionSampling",
                              "Which sides of an emissive mesh light the scene as a light "
                              "(Cycles' Emission Sampling): NONE, FRONT, BACK or BOTH.")
      .value("NONE", EmissionSampling::kNone)
      .value("FRONT", EmissionSampling::kFront)
      .value("BACK", EmissionSampling::kBack)
      .value("BOTH", EmissionSampling::kBoth);
  py::class_<Material> material(
      m, "Material",
      "Whitted parameters: Phong local term, sigma_r, sigma_t, a coat (scene/material.h "
      "MaterialParams). Keywords: the names of MATERIAL_PARAMS, each defaulting to its "
      "default there (enums also by their members' names). program: a Program computing "
      "some fields per hit; outputs: MATERIAL_FIELDS name -> register holding it after the "
      "program; the other fields keep the constants given. ValueError for a value that "
      "cannot be a material, TypeError for an unknown keyword or a value of the wrong type, "
      "each naming the parameter.");
  material.def(py::init([](const py::kwargs& kwargs) {
    // Material's constructor checks the values (std::invalid_argument: ValueError).
    return Material(material_params(kwargs));
  }));
  // The tables Python builds on (the exporter's data class, its program's outputs):
  // (name, default) per parameter, (name, components) per field a program may drive.
  py::list params;
  std::apply(
      [&](const auto&... param) {
        (material.def_property_readonly(
             std::string(param.name).c_str(),
             [member = param.member](const Material& mat) { return to_python(mat.*member); },
             std::string(param.doc).c_str()),
         ...);
        (params.append(py::make_tuple(std::string(param.name), default_of(defaults.*param.member))),
         ...);
      },
      kMaterialParams);
  m.attr("MATERIAL_PARAMS") = py::tuple(params);
  py::list fields;
  for (const FieldInfo& field : kFieldTable) {
    fields.append(py::make_tuple(std::string(field.name), field.components));
  }
  m.attr("MATERIAL_FIELDS") = py::tuple(fields);
}

}  // namespace whitted::python
