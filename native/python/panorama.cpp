#include "scene/panorama.h"

#include <array>
#include <cmath>
#include <stdexcept>

#include "bindings.h"

namespace whitted::python {

void bind_panorama(py::module_& m) {
  py::enum_<PanoramaType>(m, "PanoramaType")
      .value("EQUIRECTANGULAR", PanoramaType::kEquirectangular)
      .value("EQUIANGULAR_CUBEMAP_FACE", PanoramaType::kEquiangularCubemapFace)
      .value("MIRRORBALL", PanoramaType::kMirrorBall)
      .value("FISHEYE_EQUIDISTANT", PanoramaType::kFisheyeEquidistant)
      .value("FISHEYE_EQUISOLID", PanoramaType::kFisheyeEquisolid)
      .value("FISHEYE_LENS_POLYNOMIAL", PanoramaType::kFisheyeLensPolynomial)
      .value("CENTRAL_CYLINDRICAL", PanoramaType::kCentralCylindrical);

  py::class_<Panorama>(m, "Panorama", "A panoramic camera's projection (Blender's panorama types).")
      .def(py::init([](PanoramaType type, std::array<float, 4> longitude_latitude,
                       float fisheye_fov, float fisheye_lens, std::array<float, 2> sensor,
                       std::array<float, 5> polynomial, std::array<float, 4> cylinder) {
             Panorama p;
             p.type = type;
             p.longitude_min = longitude_latitude[0];
             p.longitude_max = longitude_latitude[1];
             p.latitude_min = longitude_latitude[2];
             p.latitude_max = longitude_latitude[3];
             p.fisheye_fov = fisheye_fov;
             p.fisheye_lens = fisheye_lens;
             p.sensor_width = sensor[0];
             p.sensor_height = sensor[1];
             std::copy(polynomial.begin(), polynomial.end(), p.polynomial);
             p.cylinder_u_min = cylinder[0];
             p.cylinder_u_max = cylinder[1];
             p.cylinder_v_min = cylinder[2];
             p.cylinder_v_max = cylinder[3];
             bool finite = std::isfinite(fisheye_fov) && std::isfinite(fisheye_lens);
             for (float f : longitude_latitude) finite = finite && std::isfinite(f);
             for (float f : sensor) finite = finite && std::isfinite(f);
             for (float f : polynomial) finite = finite && std::isfinite(f);
             for (float f : cylinder) finite = finite && std::isfinite(f);
             if (!finite || !(fisheye_lens > 0.0f) || !(sensor[0] > 0.0f) || !(sensor[1] > 0.0f)) {
               throw std::invalid_argument(
                   "a panorama needs finite values, a fisheye lens > 0 and a sensor > 0");
             }
             return p;
           }),
           py::arg("type") = PanoramaType::kEquirectangular,
           py::arg("longitude_latitude") = std::array<float, 4>{-kPi, kPi, -0.5f * kPi, 0.5f * kPi},
           py::arg("fisheye_fov") = kPi, py::arg("fisheye_lens") = 10.5f,
           py::arg("sensor") = std::array<float, 2>{36.0f, 24.0f},
           py::arg("polynomial") = std::array<float, 5>{},
           py::arg("cylinder") = std::array<float, 4>{-kPi, kPi, -1.0f, 1.0f},
           "longitude_latitude (longitude min, max, latitude min, max; radians), "
           "fisheye_fov (radians), fisheye_lens (mm), sensor (width, height in mm, fitted "
           "to the image), polynomial (k0..k4 of the polynomial fisheye), cylinder "
           "(longitude min, max in radians, height min, max over the radius).")
      .def_readonly("type", &Panorama::type, "Which of Blender's panorama projections it is.")
      .def(
          "direction",
          [](const Panorama& p, float u, float v) -> py::object {
            Vec3 d;
            if (!p.direction(u, v, &d)) return py::none();
            return py::cast(d);
          },
          py::arg("u"), py::arg("v"),
          "The unit direction in the camera's frame (looking down -Z, +Y up) of image point "
          "(u, v) in [0, 1]^2 from the bottom-left corner; None outside the projection.");
}

}  // namespace whitted::python
