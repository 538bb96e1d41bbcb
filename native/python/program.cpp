#include "shader/program.h"

#include <algorithm>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "bindings.h"
#include "shader/blackbody.h"
#include "shader/sky.h"

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
  // The op table (shader/ops.h), indexed by op code: (name, register operands, reads hit).
  py::list table;
  for (const OpInfo& op : kOpTable) {
    table.append(
        py::make_tuple(py::str(op.name.data(), op.name.size()), op.operands, op.reads_hit));
  }
  m.attr("OPS") = table;
  py::dict numbers;
  for (const OpNumber& number : kOpNumbers) {
    numbers[py::str(number.name.data(), number.name.size())] = number.value;
  }
  m.attr("OP_NUMBERS") = numbers;
  py::list tables;
  for (Op op : kTableOps) tables.append(static_cast<uint32_t>(op));
  m.attr("TABLE_OPS") = tables;
  // The ops whose mode is fields (kOpModes): op name -> ((field, shift, width, count,
  // Blender's identifiers or ()), ...), how the Python compiler packs their modes.
  py::dict op_modes;
  for (const OpMode& op_mode : kOpModes) {
    py::list fields;
    for (const ModeField& f : op_mode.fields) {
      py::list identifiers;
      for (std::string_view name : f.identifiers)
        identifiers.append(py::str(name.data(), name.size()));
      fields.append(py::make_tuple(py::str(f.name.data(), f.name.size()), f.shift, f.width, f.count,
                                   py::tuple(identifiers)));
    }
    const std::string_view op = kOpTable[static_cast<size_t>(op_mode.op)].name;
    op_modes[py::str(op.data(), op.size())] = py::tuple(fields);
  }
  m.attr("OP_MODES") = op_modes;
  m.def(
      "mode_fields",
      [](std::string_view op, uint32_t mode) {
        const auto* info = std::find_if(kOpTable.begin(), kOpTable.end(),
                                        [&](const OpInfo& i) { return i.name == op; });
        const auto fields = info == kOpTable.end()
                                ? std::span<const ModeField>{}
                                : mode_fields(static_cast<Op>(info - kOpTable.begin()));
        if (fields.empty()) throw py::value_error(std::string(op) + " has no mode fields");
        if (!valid_mode(fields, mode)) {
          throw py::value_error(std::to_string(mode) + " is not a mode of " + std::string(op));
        }
        py::dict out;
        for (const ModeField& f : fields) out[py::str(f.name.data(), f.name.size())] = f.in(mode);
        return out;
      },
      py::arg("op"), py::arg("mode"),
      "{field: value} of op's mode as the program's decoders read it (shader/ops.h ModeField); "
      "ValueError for an op without fields or a mode the program refuses.");

  m.def(
      "fold_op",
      [](uint32_t op, uint32_t mode, const std::vector<std::optional<glm::vec4>>& operands,
         std::vector<float> constants) {
        return Program::fold(op, mode, operands, std::move(constants));
      },
      py::arg("op"), py::arg("mode"), py::arg("operands"), py::arg("constants"),
      "The four floats of one op of constant operands (each a 4-sequence, or None: unused; "
      "`constants` its COLOR_RAMP or CURVE table), computed by the program's own code; None "
      "for an op that reads the hit. ValueError for an instruction a program would refuse.");

  m.def(
      "blackbody_rgb",
      [](float kelvin) {
        const Vec3 c = blackbody_rgb(kelvin);
        return py::make_tuple(c.x, c.y, c.z);
      },
      py::arg("kelvin"),
      "The linear Rec.709 colour (r, g, b) of a black body at `kelvin`, as Cycles' fit gives "
      "it (shader/blackbody.h; what op BLACKBODY computes, in float32): not clamped, a "
      "channel may be below 0.");
  m.def(
      "preetham_table",
      [](const std::array<float, 3>& sun, float turbidity) {
        const std::vector<float> t = sky::preetham_table(Vec3(sun[0], sun[1], sun[2]), turbidity);
        return py::array_t<float>(static_cast<py::ssize_t>(t.size()), t.data());
      },
      py::arg("sun"), py::arg("turbidity"),
      "The constants of op SKY's PREETHAM model (shader/sky.h): the Perez/Preetham sky of "
      "`turbidity` with the sun towards `sun` (unit, +Z up).");
  m.def(
      "hosek_wilkie_table",
      [](const std::array<float, 3>& sun, float turbidity, float ground_albedo) {
        const std::vector<float> t =
            sky::hosek_wilkie_table(Vec3(sun[0], sun[1], sun[2]), turbidity, ground_albedo);
        return py::array_t<float>(static_cast<py::ssize_t>(t.size()), t.data());
      },
      py::arg("sun"), py::arg("turbidity"), py::arg("ground_albedo"),
      "The constants of op SKY's HOSEK_WILKIE model (shader/sky.h): the Hosek/Wilkie sky of "
      "`turbidity` and `ground_albedo` with the sun towards `sun` (unit, +Z up).");
  m.def(
      "scattering_table",
      [](float sun_elevation, float sun_rotation, bool sun_disc, float sun_size,
         float sun_intensity, float altitude, float air_density, float dust_density,
         float ozone_density, std::string_view style, uint32_t columns, uint32_t rows) {
        if (style != "NISHITA" && style != "SINGLE_SCATTERING" && style != "MULTIPLE_SCATTERING") {
          throw py::value_error("style is NISHITA, SINGLE_SCATTERING or MULTIPLE_SCATTERING, not " +
                                std::string(style));
        }
        const sky::ScatteringParams params{sun_elevation,
                                           sun_rotation,
                                           sun_disc,
                                           sun_size,
                                           sun_intensity,
                                           altitude,
                                           air_density,
                                           dust_density,
                                           ozone_density,
                                           style == "NISHITA" ? sky::Style::kNishita
                                           : style == "SINGLE_SCATTERING"
                                               ? sky::Style::kSingleScattering
                                               : sky::Style::kMultipleScattering};
        std::vector<float> t;
        {
          py::gil_scoped_release release;
          t = sky::scattering_table(params, columns, rows);
        }
        return py::array_t<float>(static_cast<py::ssize_t>(t.size()), t.data());
      },
      py::arg("sun_elevation"), py::arg("sun_rotation"), py::arg("sun_disc"), py::arg("sun_size"),
      py::arg("sun_intensity"), py::arg("altitude"), py::arg("air_density"),
      py::arg("dust_density"), py::arg("ozone_density"), py::arg("style"),
      py::arg("columns") = sky::kScatteringColumns, py::arg("rows") = sky::kScatteringRows,
      "The constants of op SKY's SINGLE_SCATTERING model (shader/sky.h): Blender's Sky "
      "Texture parameters (radians, metres), the sky baked and its disc drawn as 3.x/4.x's "
      "NISHITA or 5.x's SINGLE_SCATTERING or MULTIPLE_SCATTERING; the sky tabulated at "
      "`columns` x `rows` texels (a hemisphere's).");
  m.def(
      "sun_direction",
      [](float elevation, float rotation) {
        const Vec3 d = sky::sun_direction(elevation, rotation);
        return py::make_tuple(d.x, d.y, d.z);
      },
      py::arg("elevation"), py::arg("rotation"),
      "The unit direction towards a sky's sun of Sun Elevation and Sun Rotation (radians), "
      "+Z up, rotation from +Y towards +X.");

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
      .def(
          "run",
          [](const Program& program, const std::map<uint32_t, glm::vec4>& inputs,
             const glm::vec3& incoming, const glm::vec3& normal, bool backfacing) {
            for (size_t slot = 0; slot < program.textures().size(); ++slot) {
              if (program.samples_image(slot)) {
                throw std::invalid_argument("run() samples no images: render the program");
              }
            }
            std::vector<glm::vec4> values;
            for (uint32_t mode : program.inputs()) {
              const auto found = inputs.find(mode);
              if (found == inputs.end()) {
                throw std::invalid_argument("input mode " + std::to_string(mode) + " is not given");
              }
              values.push_back(found->second);
            }
            ProgramHit hit;
            hit.inputs = values.data();
            hit.incoming = incoming;
            hit.normal = normal;
            hit.backfacing = backfacing;
            std::vector<glm::vec4> registers(Program::kMaxRegisters + 1);
            program.run(hit, registers.data());
            py::array_t<float> out(
                {static_cast<py::ssize_t>(program.register_count()), static_cast<py::ssize_t>(4)});
            auto view = out.mutable_unchecked<2>();
            for (size_t r = 0; r < program.register_count(); ++r) {
              for (int k = 0; k < 4; ++k) view(r, k) = registers[r][k];
            }
            return out;
          },
          py::arg("inputs"), py::arg("incoming") = glm::vec3(0.0f, 0.0f, 1.0f),
          py::arg("normal") = glm::vec3(0.0f, 0.0f, 1.0f), py::arg("backfacing") = false,
          "The register file (float32[R, 4]) after running the program on one hit: `inputs` "
          "maps each INPUT mode it reads to four floats; `incoming` and `normal` (unit) and "
          "`backfacing` are what FRESNEL and LAYER_WEIGHT read. For tests and debugging; a "
          "program that samples images is refused (ValueError).")
      .def_property_readonly("register_count", &Program::register_count,
                             "How many float4 registers it has (R).")
      .def_property_readonly("instruction_count", &Program::instruction_count,
                             "How many instructions it runs per hit.")
      .def_property_readonly("textures", &Program::textures,
                             "The scene texture names its IMAGE and ENVIRONMENT ops read, by "
                             "index.");
}

}  // namespace whitted::python
