#include "scene/light.h"

#include "bindings.h"

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

  py::class_<Light>(m, "Light",
                    "color is W/sr (point, spot), W/m^2 (sun) or W/(m^2 sr) (area), "
                    "light colour included; direction is the way light travels.")
      .def(py::init([](LightType type, Vec3 color, Vec3 position, Vec3 direction, float spot_size,
                       float spot_blend, std::array<float, 2> size, Vec3 axis_u, Vec3 axis_v,
                       AreaShape shape, int samples, bool cast_shadows, float radius, float angle,
                       bool spot_cosine_falloff, float spread, bool diffuse, bool glossy,
                       int max_bounces, uint64_t light_sets, uint64_t shadow_sets) {
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
                                      .max_bounces = max_bounces,
                                      .light_sets = light_sets,
                                      .shadow_sets = shadow_sets});
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
           py::arg("glossy") = defaults.glossy, py::arg("max_bounces") = defaults.max_bounces,
           py::arg("light_sets") = defaults.light_sets,
           py::arg("shadow_sets") = defaults.shadow_sets,
           "light_sets, shadow_sets: light linking, the receivers' light sets it lights and "
           "the blockers' shadow sets that cast its shadows, a bit per set (all: no linking).")
      .def_readonly("type", &Light::type)
      .def_readonly("color", &Light::color)
      .def_readonly("position", &Light::position)
      .def_readonly("direction", &Light::direction)
      .def_readonly("samples", &Light::samples)
      .def_readonly("radius", &Light::radius)
      .def_readonly("angle", &Light::angle)
      .def_readonly("spread", &Light::spread)
      .def_readonly("spot_cosine_falloff", &Light::spot_cosine_falloff)
      .def_readonly("cast_shadows", &Light::cast_shadows)
      .def_readonly("diffuse", &Light::diffuse)
      .def_readonly("glossy", &Light::glossy)
      .def_readonly("max_bounces", &Light::max_bounces)
      .def_readonly("light_sets", &Light::light_sets)
      .def_readonly("shadow_sets", &Light::shadow_sets);
}

}  // namespace whitted::python
