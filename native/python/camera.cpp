#include "scene/camera.h"

#include <cmath>
#include <optional>
#include <stdexcept>

#include "bindings.h"

namespace whitted::python {
namespace {

glm::mat4 to_glm(const py::array_t<double, py::array::c_style | py::array::forcecast>& a) {
  if (a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4) {
    throw std::invalid_argument("a transform must be a 4x4 matrix");
  }
  glm::mat4 m;
  auto r = a.unchecked<2>();
  // numpy rows are Blender's rows; glm indexes [column][row].
  for (int row = 0; row < 4; ++row) {
    for (int col = 0; col < 4; ++col) m[col][row] = static_cast<float>(r(row, col));
  }
  return m;
}

}  // namespace

glm::mat4 matrix_from_numpy(const py::handle& h) {
  return to_glm(py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(h));
}

py::array_t<double> matrix_to_numpy(const glm::mat4& m) {
  py::array_t<double> out({4, 4});
  auto w = out.mutable_unchecked<2>();
  for (int row = 0; row < 4; ++row) {
    for (int col = 0; col < 4; ++col) w(row, col) = m[col][row];
  }
  return out;
}

void bind_camera(py::module_& m) {
  py::enum_<Projection>(m, "Projection")
      .value("PERSPECTIVE", Projection::kPerspective)
      .value("ORTHOGRAPHIC", Projection::kOrthographic)
      .value("PANORAMIC", Projection::kPanoramic);

  py::class_<Camera>(m, "Camera",
                     "A camera: it looks down its local -Z with +Y up (Blender's convention); "
                     "image rows run bottom to top.")
      .def(py::init(
               [](const py::object& to_world, Projection projection, std::array<float, 4> window,
                  float clip_start, float clip_end, float aperture_radius, float focus_distance,
                  int aperture_blades, float aperture_rotation, float aperture_ratio,
                  const std::optional<Panorama>& panorama, const std::vector<py::object>& motion,
                  const std::vector<float>& shutter_curve, float rolling_shutter) {
                 Camera c;
                 if (!to_world.is_none()) c.to_world = matrix_from_numpy(to_world);
                 c.projection = projection;
                 std::copy(window.begin(), window.end(), c.window);
                 c.clip_start = clip_start;
                 c.clip_end = clip_end;
                 const bool finite =
                     std::isfinite(aperture_radius) && std::isfinite(focus_distance) &&
                     std::isfinite(aperture_rotation) && std::isfinite(aperture_ratio);
                 if (!finite || aperture_radius < 0.0f || !(focus_distance > 0.0f) ||
                     !(aperture_ratio > 0.0f)) {
                   throw std::invalid_argument(
                       "the lens needs a finite aperture radius >= 0, focus distance > 0 and "
                       "aperture ratio > 0");
                 }
                 c.lens = Lens{aperture_radius, focus_distance, aperture_blades, aperture_rotation,
                               aperture_ratio};
                 if ((projection == Projection::kPanoramic) != panorama.has_value()) {
                   throw std::invalid_argument(
                       "a panorama is given with, and only with, the PANORAMIC projection");
                 }
                 if (panorama) c.panorama = *panorama;
                 if (motion.size() > 1) {
                   std::vector<glm::mat4> samples;
                   for (const py::object& m : motion) samples.push_back(matrix_from_numpy(m));
                   for (const glm::mat4& m : samples) {
                     if (!is_finite(m)) throw std::invalid_argument("camera motion must be finite");
                   }
                   auto moving = std::make_shared<const TransformMotion>(samples);
                   if (moving->moves()) c.motion = std::move(moving);
                 }
                 if (!std::isfinite(rolling_shutter) || rolling_shutter > 1.0f) {
                   throw std::invalid_argument("rolling_shutter is a duration in [0, 1], or < 0");
                 }
                 c.shutter = Shutter(shutter_curve, rolling_shutter);
                 return c;
               }),
           py::arg("to_world") = py::none(), py::arg("projection") = Projection::kPerspective,
           py::arg("window") = std::array<float, 4>{-0.5f, 0.5f, -0.5f, 0.5f},
           py::arg("clip_start") = 0.1f, py::arg("clip_end") = 1000.0f,
           py::arg("aperture_radius") = 0.0f, py::arg("focus_distance") = 1.0f,
           py::arg("aperture_blades") = 0, py::arg("aperture_rotation") = 0.0f,
           py::arg("aperture_ratio") = 1.0f, py::arg("panorama") = py::none(),
           py::arg("motion") = std::vector<py::object>{},
           py::arg("shutter_curve") = std::vector<float>{}, py::arg("rolling_shutter") = -1.0f,
           "aperture_radius (world units; 0: a pinhole), focus_distance (of the plane in "
           "focus, along the view axis), aperture_blades (a polygon; below 3 a disc), "
           "aperture_rotation (radians), aperture_ratio (anamorphic: the aperture's width "
           "over it): a thin lens, as Cycles' depth of field. panorama: the projection of a "
           "PANORAMIC camera, whose window spans the panorama's [0, 1]^2 (shift added). "
           "motion: its to_world (4x4 row-major, unit axes) at evenly spaced times over the "
           "shutter (motion blur; [] when it stays put). shutter_curve: how open the shutter "
           "is at evenly spaced times over it ([] or all equal: a box). rolling_shutter: "
           "Cycles' rolling shutter Duration in [0, 1] (rows read from the top), or < 0 "
           "for a global shutter.")
      .def_property(
          "to_world", [](const Camera& c) { return matrix_to_numpy(c.to_world); },
          [](Camera& c, const py::object& o) { c.to_world = matrix_from_numpy(o); },
          "Camera to world, 4x4 row-major.")
      .def_readwrite("projection", &Camera::projection,
                     "PERSPECTIVE, ORTHOGRAPHIC or PANORAMIC (a Projection).")
      .def_property(
          "window",
          [](const Camera& c) {
            return std::array<float, 4>{c.window[0], c.window[1], c.window[2], c.window[3]};
          },
          [](Camera& c, std::array<float, 4> w) { std::copy(w.begin(), w.end(), c.window); },
          "(xmin, xmax, ymin, ymax) on the plane at distance 1 (perspective) or in camera "
          "units (orthographic).")
      .def_readwrite("clip_start", &Camera::clip_start,
                     "Distance along the view axis before which nothing is seen (world units).")
      .def_readwrite("clip_end", &Camera::clip_end,
                     "Distance along the view axis beyond which nothing is seen (world units).")
      .def_property_readonly(
          "aperture_radius", [](const Camera& c) { return c.lens.radius; },
          "Radius of the thin lens's aperture in world units (0: a pinhole, all in focus).")
      .def_property_readonly(
          "moves", [](const Camera& c) { return c.motion != nullptr; },
          "Whether its motion moves it over the shutter (camera motion blur).")
      .def_property_readonly(
          "shutter_box", [](const Camera& c) { return c.shutter.box(); },
          "Whether the shutter is equally open all the time it is open (no shutter_curve).")
      .def_property_readonly(
          "rolling_shutter", [](const Camera& c) { return c.shutter.rolling(); },
          "Whether the shutter rolls (rows read from the top at different times).")
      .def_property_readonly(
          "focus_distance", [](const Camera& c) { return c.lens.focus_distance; },
          "Distance of the plane in focus along the view axis (world units).");
}

}  // namespace whitted::python
