#include "shader/program.h"

#include "bindings.h"

namespace whitted::python {
namespace {

template <size_t N>
py::list names(const std::array<std::string_view, N>& list) {
  py::list out;
  for (std::string_view name : list) out.append(py::str(name.data(), name.size()));
  return out;
}

}  // namespace

void bind_program(py::module_& m) {
  // The Python side maps Blender's operation identifiers to mode numbers through these
  // lists: Blender 3.4 and 5.0 order their enums differently.
  m.attr("MATH_OPS") = names(kMathOpNames);
  m.attr("VECTOR_MATH_OPS") = names(kVectorMathOpNames);
  m.attr("MIX_BLEND") = names(kMixBlendNames);

  py::class_<Program, std::shared_ptr<Program>>(
      m, "Program",
      "A shader program (docs/notes/shader_program.md): instructions over float4 registers "
      "that compute a material's fields, or the world's radiance, per hit.")
      .def(py::init(
               [](const py::array_t<uint32_t, py::array::c_style | py::array::forcecast>& code,
                  const py::array_t<float, py::array::c_style | py::array::forcecast>& registers,
                  const py::array_t<float, py::array::c_style | py::array::forcecast>& constants,
                  std::vector<std::string> textures) {
                 if (code.ndim() != 2 ||
                     code.shape(1) != static_cast<py::ssize_t>(Program::kColumns)) {
                   throw std::invalid_argument("code must have shape (K, 8)");
                 }
                 if (registers.ndim() != 2 || registers.shape(1) != 4) {
                   throw std::invalid_argument("registers must have shape (R, 4)");
                 }
                 if (constants.ndim() != 1)
                   throw std::invalid_argument("constants must have shape (C,)");
                 const float* c = constants.data();
                 return std::make_shared<Program>(
                     code.data(), static_cast<size_t>(code.shape(0)), registers.data(),
                     static_cast<size_t>(registers.shape(0)),
                     std::vector<float>(c, c + constants.shape(0)), std::move(textures));
               }),
           py::arg("code"), py::arg("registers"), py::arg("constants"),
           py::arg("textures") = std::vector<std::string>{},
           "code uint32[K, 8] rows (op, mode, out, a, b, c, d, e); registers float32[R, 4], "
           "every register's value before the first instruction; constants float32[C] (ramps, "
           "curves); textures: scene texture names, indexed by IMAGE/ENVIRONMENT's e. Checked "
           "here: ValueError names the first wrong instruction.")
      .def_property_readonly("register_count", &Program::register_count)
      .def_property_readonly("instruction_count", &Program::instruction_count)
      .def_property_readonly("textures", &Program::textures);
}

}  // namespace whitted::python
