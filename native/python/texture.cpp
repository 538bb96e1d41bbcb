#include "scene/texture.h"

#include "bindings.h"

namespace whitted::python {

void bind_texture(py::module_& m) {
  py::enum_<TexCoord>(m, "TexCoord")
      .value("UV", TexCoord::kUV)
      .value("GENERATED", TexCoord::kGenerated)
      .value("OBJECT", TexCoord::kObject);
  py::enum_<Extension>(m, "Extension")
      .value("REPEAT", Extension::kRepeat)
      .value("EXTEND", Extension::kExtend)
      .value("CLIP", Extension::kClip);
  py::enum_<Interpolation>(m, "Interpolation")
      .value("LINEAR", Interpolation::kLinear)
      .value("CLOSEST", Interpolation::kClosest);

  py::class_<Texture>(m, "Texture", "An image or checker texture; set it with Scene.set_texture.")
      .def_readonly("coordinates", &Texture::coordinates,
                    "What it is looked up by: UV, GENERATED (object space mapped to [0, 1] "
                    "over the mesh's bounds) or OBJECT (object space).");

  m.def(
      "ImageTexture",
      [](const py::array_t<float, py::array::c_style | py::array::forcecast>& pixels,
         Extension extension, Interpolation interpolation, TexCoord coordinates) {
        if (pixels.ndim() != 3 || pixels.shape(2) != 4) {
          throw std::invalid_argument("pixels must have shape (height, width, 4)");
        }
        const auto height = static_cast<int>(pixels.shape(0));
        const auto width = static_cast<int>(pixels.shape(1));
        return Texture{coordinates,
                       make_image_texture(pixels.data(), width, height, extension, interpolation)};
      },
      py::arg("pixels"), py::arg("extension") = Extension::kRepeat,
      py::arg("interpolation") = Interpolation::kLinear, py::arg("coordinates") = TexCoord::kUV,
      "An image: linear RGBA float pixels[height, width, 4], rows bottom to top (as "
      "Blender's Image.pixels).");

  m.def(
      "CheckerTexture",
      [](Vec3 color1, Vec3 color2, float scale, TexCoord coordinates) {
        require_finite(color1, "checker colours");
        require_finite(color2, "checker colours");
        if (!std::isfinite(scale)) throw std::invalid_argument("checker scale must be finite");
        return Texture{coordinates, CheckerTexture{color1, color2, scale}};
      },
      py::arg("color1") = Vec3(0.8f), py::arg("color2") = Vec3(0.2f), py::arg("scale") = 5.0f,
      py::arg("coordinates") = TexCoord::kGenerated, "Blender's Checker Texture node.");
}

}  // namespace whitted::python
