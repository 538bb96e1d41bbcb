#include "scene/image_file.h"

#include <cstring>
#include <memory>
#include <string>

// The one file that holds stb_image's implementation (Debian's libstb-dev); only the
// formats Blender reads the same way are compiled in.
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#define STBI_NO_STDIO
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_ONLY_BMP
#define STBI_ONLY_TGA
#define STBI_FAILURE_USERMSG
#include <stb/stb_image.h>

namespace whitted {
namespace {

bool starts_with(const std::uint8_t* data, std::size_t size, const char* magic) {
  const std::size_t n = std::strlen(magic);
  return size >= n && std::memcmp(data, magic, n) == 0;
}

// Formats Blender reads that stb_image does not, or not as Blender does, named by their
// first bytes.
const char* unsupported_format(const std::uint8_t* data, std::size_t size) {
  if (starts_with(data, size, "v/1\x01")) return "OpenEXR";
  if (starts_with(data, size, "#?")) return "Radiance HDR";  // "#?RADIANCE", "#?RGBE"
  return nullptr;
}

// The decoded rows (top to bottom, 4 channels of T) as floats v * (1 / full), bottom to
// top: the bits Blender's Image.pixels gives a byte image (each code times 1 / 255).
template <typename T>
DecodedImage flipped(const T* rows, int width, int height, float full) {
  DecodedImage image;
  image.width = width;
  image.height = height;
  image.pixels.resize(4 * static_cast<std::size_t>(width) * height);
  const std::size_t row = 4 * static_cast<std::size_t>(width);
  for (int y = 0; y < height; ++y) {
    const T* in = rows + (static_cast<std::size_t>(height - 1 - y)) * row;
    float* out = &image.pixels[static_cast<std::size_t>(y) * row];
    for (std::size_t i = 0; i < row; ++i) out[i] = static_cast<float>(in[i]) * (1.0f / full);
  }
  return image;
}

}  // namespace

DecodedImage decode_image(const std::uint8_t* data, std::size_t size) {
  if (const char* format = unsupported_format(data, size)) {
    throw ImageFileError(std::string(format) + " files are not read");
  }
  if (size == 0 || size > static_cast<std::size_t>(INT32_MAX)) {
    throw ImageFileError("not an image file (" + std::to_string(size) + " bytes)");
  }
  const int length = static_cast<int>(size);
  int width = 0;
  int height = 0;
  int channels = 0;
  if (!stbi_info_from_memory(data, length, &width, &height, &channels)) {
    throw ImageFileError(std::string("not a PNG, JPEG, BMP or TGA image: ") +
                         stbi_failure_reason());
  }
  if (int64_t{width} * height > (int64_t{1} << 28)) {
    throw ImageFileError("an image of " + std::to_string(width) + " x " + std::to_string(height) +
                         " pixels is larger than 2^28 pixels");
  }
  // 4 channels asked for: stb expands grey to R = G = B and adds an opaque alpha.
  if (stbi_is_16_bit_from_memory(data, length)) {
    const std::unique_ptr<stbi_us, decltype(&stbi_image_free)> rows(
        stbi_load_16_from_memory(data, length, &width, &height, &channels, 4), stbi_image_free);
    if (!rows) throw ImageFileError(std::string("broken image: ") + stbi_failure_reason());
    return flipped(rows.get(), width, height, 65535.0f);
  }
  const std::unique_ptr<stbi_uc, decltype(&stbi_image_free)> rows(
      stbi_load_from_memory(data, length, &width, &height, &channels, 4), stbi_image_free);
  if (!rows) throw ImageFileError(std::string("broken image: ") + stbi_failure_reason());
  return flipped(rows.get(), width, height, 255.0f);
}

}  // namespace whitted
