// Image files decoded from their bytes: the tiles of a UDIM image, which Blender's
// Image.pixels does not hold (it holds the first tile only).
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace whitted {

// A file that cannot be decoded: not an image, a format not read here (OpenEXR,
// Radiance HDR), or broken data. what() says which.
struct ImageFileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct DecodedImage {
  int width = 0;
  int height = 0;
  // RGBA, rows bottom to top (as Blender's Image.pixels): an 8-bit file's codes k as
  // k * (1 / 255), the bits Image.pixels gives, a 16-bit file's as k * (1 / 65535), as
  // stored (in the file's colour space); grey fills R, G and B, and a missing alpha is 1.
  std::vector<float> pixels;
};

// Decodes a PNG (8 or 16 bits), JPEG, BMP or TGA file's bytes (stb_image). Throws
// ImageFileError for anything else.
DecodedImage decode_image(const std::uint8_t* data, std::size_t size);

}  // namespace whitted
