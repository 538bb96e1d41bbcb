#include "scene/light.h"

#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "bindings.h"
#include "shader/program.h"

namespace whitted::python {

void bind_light(py::module_& m) {
  const LightParams defaults;
  py::enum_<LightType>(m, "LightType")
      .value("POINT", LightType::kPoint)
      .value("SPOT", LightType::kSpot)
      .value("SUN", LightType::kSun)
      .value("AREA", LightType::kArea);
  py::enum_<AreaShape>(m, "AreaShape")
      .value("RECTANGLE", AreaShape::kRectangle)
      .value("ELLIPSE", AreaShape::kEllipse);

  m.def(
      "lamp_program_refusal",
      [](const Program& program, LightType type, uint32_t output) -> std::optional<std::string> {
        std::string why = lamp_program_refusal(program, type, output);
        if (why.empty()) return std::nullopt;
        return why;
      },
      py::arg("program"), py::arg("type"), py::arg("output"),
      "Why `program` (its output in register `output`) cannot be the program of a lamp of "
      "`type`, or None where it can: the rule Light's constructor applies (scene/light.h).");
  py::class_<Light>(m, "Light",
                    "A lamp; checked on construction (ValueError for what cannot be one, "
                    "clamped where a nearest value is obvious), read-only afterwards.")
      .def(py::init([](LightType type, Vec3 color, Vec3 position, Vec3 direction, float spot_size,
                       float spot_blend, std::array<float, 2> size, Vec3 axis_u, Vec3 axis_v,
                       AreaShape shape, int samples, bool cast_shadows, float radius, float angle,
                       bool spot_cosine_falloff, float spread, bool diffuse, bool glossy,
                       std::array<bool, 3> visibility, int max_bounces, uint64_t light_sets,
                       uint64_t shadow_sets, std::shared_ptr<Program> program,
                       uint32_t program_output) {
             // Light's constructor checks the values (std::invalid_argument: ValueError).
             return Light(LightParams{.type = type,
                                      .color = color,
                                      .position = position,
                                      .direction = direction,
                                      .spot_size = spot_size,
                                      .spot_blend = spot_blend,
                                      .spot_cosine_falloff = spot_cosine_falloff,
                                      .size = {size[0], size[1]},
                                      .axis_u = axis_u,
                                      .axis_v = axis_v,
                                      .shape = shape,
                                      .radius = radius,
                                      .angle = angle,
                                      .spread = spread,
                                      .samples = samples,
                                      .cast_shadows = cast_shadows,
                                      .diffuse = diffuse,
                                      .glossy = glossy,
                                      .visibility = (visibility[0] ? kCameraRay : 0u) |
                                                    (visibility[1] ? kReflectionRay : 0u) |
                                                    (visibility[2] ? kRefractionRay : 0u),
                                      .max_bounces = max_bounces,
                                      .light_sets = light_sets,
                                      .shadow_sets = shadow_sets,
                                      .program = std::move(program),
                                      .program_output = program_output});
           }),
           py::arg("type") = defaults.type, py::arg("color") = defaults.color,
           py::arg("position") = defaults.position, py::arg("direction") = defaults.direction,
           py::arg("spot_size") = defaults.spot_size, py::arg("spot_blend") = defaults.spot_blend,
           py::arg("size") = std::array<float, 2>{defaults.size[0], defaults.size[1]},
           py::arg("axis_u") = defaults.axis_u, py::arg("axis_v") = defaults.axis_v,
           py::arg("shape") = defaults.shape, py::arg("samples") = defaults.samples,
           py::arg("cast_shadows") = defaults.cast_shadows, py::arg("radius") = defaults.radius,
           py::arg("angle") = defaults.angle,
           py::arg("spot_cosine_falloff") = defaults.spot_cosine_falloff,
           py::arg("spread") = defaults.spread, py::arg("diffuse") = defaults.diffuse,
           py::arg("glossy") = defaults.glossy,
           py::arg("visibility") = std::array<bool, 3>{false, true, true},
           py::arg("max_bounces") = defaults.max_bounces,
           py::arg("light_sets") = defaults.light_sets,
           py::arg("shadow_sets") = defaults.shadow_sets, py::arg("program") = nullptr,
           py::arg("program_output") = defaults.program_output,
           "spot_size: the spot's full cone angle in radians, in [0, pi]; spot_blend: the "
           "softness of its edge, in [0, 1]. size: an area's extents along axis_u and axis_v "
           "(world units), shape: RECTANGLE or ELLIPSE. visibility: whether camera, glossy "
           "(reflected) and transmission (refracted) rays see its shape. light_sets, shadow_sets: "
           "light "
           "linking, the receivers' light sets it lights and the blockers' shadow sets that "
           "cast its shadows, a bit per set (all: no linking). program: a Program whose "
           "register program_output (xyz) multiplies the colour at each point sampled on the "
           "lamp and where rays see it (its node tree; Light Falloff's ray length), or None.")
      .def_readonly("type", &Light::type,
                    "The kind of light: POINT, SPOT, SUN or AREA (a LightType).")
      .def_readonly("color", &Light::color,
                    "Its power, light colour included: W/sr for point and spot, W/m^2 for sun, "
                    "W/(m^2 sr) for area.")
      .def_readonly("position", &Light::position, "Its position in world space (unused by sun).")
      .def_readonly("direction", &Light::direction,
                    "The way its light travels (not zero): the spot's axis, the sun's rays, the "
                    "area's normal.")
      .def_readonly("samples", &Light::samples,
                    "Shadow feelers per axis of a sized light (samples x samples), 1 to 64.")
      .def_readonly("radius", &Light::radius,
                    "Point and spot: the radius of the sphere it is (0: a point, hard shadows).")
      .def_readonly(
          "angle", &Light::angle,
          "Sun: the full apex angle of its disc in radians, in [0, pi] (0: hard shadows).")
      .def_readonly("spread", &Light::spread,
                    "Area: the full angle its light spreads over in radians, in [0, pi] (pi: the "
                    "whole side).")
      .def_readonly(
          "spot_cosine_falloff", &Light::spot_cosine_falloff,
          "Spot: also weigh the cone's falloff by the cosine to the axis (Cycles before 4.0).")
      .def_readonly("cast_shadows", &Light::cast_shadows,
                    "Whether surfaces between it and a point shadow it.")
      .def_readonly("diffuse", &Light::diffuse,
                    "Whether it lights the diffuse terms (Cycles' Diffuse ray visibility).")
      .def_readonly("glossy", &Light::glossy,
                    "Whether it shows in the specular terms: highlights, coat, glossy lobes.")
      .def_property_readonly(
          "visibility",
          [](const Light& light) {
            return std::make_tuple((light.visibility & kCameraRay) != 0,
                                   (light.visibility & kReflectionRay) != 0,
                                   (light.visibility & kRefractionRay) != 0);
          },
          "Whether camera, glossy (reflected) and transmission (refracted) rays see its shape.")
      .def_readonly(
          "max_bounces", &Light::max_bounces,
          "It lights only surfaces reached after at most this many reflections or refractions.")
      .def_readonly("light_sets", &Light::light_sets,
                    "Light linking: a bit per light set of the receivers it lights (all bits: "
                    "every receiver).")
      .def_property_readonly(
          "has_program", [](const Light& light) { return light.program != nullptr; },
          "Whether a program (its node tree) multiplies its colour per feeler.")
      .def_readonly("shadow_sets", &Light::shadow_sets,
                    "Light linking: a bit per shadow set of the blockers that cast its shadows "
                    "(all bits: all).");
}

}  // namespace whitted::python
