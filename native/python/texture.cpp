#include <algorithm>
#include <cstdint>
#include <string_view>
#include <utility>
#include <vector>

#include "scene/image_file.h"
#include "scene/texture.h"

#include "bindings.h"

namespace whitted::python {

// RGBA float pixels[height, width, 4] as the bindings take them.
using Pixels = py::array_t<float, py::array::c_style | py::array::forcecast>;

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
      [](const Pixels& pixels, Extension extension, Interpolation interpolation,
         TexCoord coordinates) {
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
      "UdimTexture",
      [](const std::vector<std::pair<int, Pixels>>& tiles, Extension extension,
         Interpolation interpolation, TexCoord coordinates) {
        std::vector<ImageTile> made;
        for (const auto& [number, pixels] : tiles) {
          if (pixels.ndim() != 3 || pixels.shape(2) != 4) {
            throw std::invalid_argument("each tile's pixels must have shape (height, width, 4)");
          }
          made.push_back(make_image_tile(number, pixels.data(), static_cast<int>(pixels.shape(1)),
                                         static_cast<int>(pixels.shape(0))));
        }
        return Texture{coordinates, make_udim_texture(std::move(made), extension, interpolation)};
      },
      py::arg("tiles"), py::arg("extension") = Extension::kRepeat,
      py::arg("interpolation") = Interpolation::kLinear, py::arg("coordinates") = TexCoord::kUV,
      "A UDIM image: its tiles as (number, pixels) pairs, each tile's pixels as "
      "ImageTexture's; uv (u, v) shows tile 1001 + int(u) + 10 int(v), and magenta (as "
      "Cycles) where the image has no such tile.");

  m.def(
      "decode_image",
      [](const py::bytes& data) {
        const std::string_view view = data;
        DecodedImage image;
        try {
          const py::gil_scoped_release unlocked;  // the bytes stay alive: they are an argument
          image = decode_image(reinterpret_cast<const std::uint8_t*>(view.data()), view.size());
        } catch (const ImageFileError& e) {
          throw py::value_error(e.what());
        }
        py::array_t<float> pixels({image.height, image.width, 4});
        std::copy(image.pixels.begin(), image.pixels.end(), pixels.mutable_data());
        return pixels;
      },
      py::arg("data"),
      "An image file's bytes (PNG of 8 or 16 bits, JPEG, BMP, TGA) decoded to float32 "
      "pixels[height, width, 4], rows bottom to top (as Blender's Image.pixels): values as "
      "stored, in the file's colour space (code k as k * (1 / 255), the bits of "
      "Image.pixels, or k * (1 / 65535)); grey fills R, G and B and a missing alpha is 1. "
      "ValueError for other formats (OpenEXR, Radiance HDR) and broken data.");

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
