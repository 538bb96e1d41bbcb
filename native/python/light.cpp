#include "scene/light.h"

#include "bindings.h"

namespace whitted::python {

void bind_light(py::module_& m) {
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
                       bool spot_cosine_falloff) {
             for (const Vec3* v : {&color, &position, &direction, &axis_u, &axis_v}) {
               require_finite(*v, "light colour, position and axes");
             }
             if (glm::length(direction) == 0.0f) {
               throw std::invalid_argument("light direction must not be zero");
             }
             if (samples < 1 || samples > 64) {
               throw std::invalid_argument("light samples must be between 1 and 64");
             }
             Light l;
             l.type = type;
             l.color = glm::max(color, Vec3(0.0f));  // negative power emits nothing
             l.position = position;
             l.direction = glm::normalize(direction);
             l.spot_size = std::clamp(spot_size, 0.0f, kPi);
             l.spot_blend = std::clamp(spot_blend, 0.0f, 1.0f);
             l.size[0] = std::max(0.0f, size[0]);
             l.size[1] = std::max(0.0f, size[1]);
             l.axis_u = axis_u;
             l.axis_v = axis_v;
             l.shape = shape;
             l.samples = samples;
             l.cast_shadows = cast_shadows;
             if (!std::isfinite(radius) || !std::isfinite(angle)) {
               throw std::invalid_argument("light radius and angle must be finite");
             }
             l.radius = std::max(0.0f, radius);
             l.angle = std::clamp(angle, 0.0f, kPi);
             l.spot_cosine_falloff = spot_cosine_falloff;
             return l;
           }),
           py::arg("type") = LightType::kPoint, py::arg("color") = Vec3(1.0f),
           py::arg("position") = Vec3(0.0f), py::arg("direction") = Vec3(0.0f, 0.0f, -1.0f),
           py::arg("spot_size") = 0.785398f, py::arg("spot_blend") = 0.15f,
           py::arg("size") = std::array<float, 2>{0.0f, 0.0f},
           py::arg("axis_u") = Vec3(1.0f, 0.0f, 0.0f), py::arg("axis_v") = Vec3(0.0f, 1.0f, 0.0f),
           py::arg("shape") = AreaShape::kRectangle, py::arg("samples") = 1,
           py::arg("cast_shadows") = true, py::arg("radius") = 0.0f, py::arg("angle") = 0.0f,
           py::arg("spot_cosine_falloff") = false)
      .def_readonly("type", &Light::type)
      .def_readonly("color", &Light::color)
      .def_readonly("position", &Light::position)
      .def_readonly("direction", &Light::direction)
      .def_readonly("samples", &Light::samples)
      .def_readonly("radius", &Light::radius)
      .def_readonly("angle", &Light::angle)
      .def_readonly("spot_cosine_falloff", &Light::spot_cosine_falloff)
      .def_readonly("cast_shadows", &Light::cast_shadows);
}

}  // namespace whitted::python
