// The image decoder of UDIM tiles: PNG files written here (stb_image_write) decode to
// their values, rows bottom to top; other formats are refused by name.
#include "scene/image_file.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#define STBI_WRITE_NO_STDIO
#include <stb/stb_image_write.h>

namespace whitted {
namespace {

void append(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<std::uint8_t>*>(context);
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  out->insert(out->end(), bytes, bytes + size);
}

// A PNG of `channels` 8-bit channels, rows top to bottom as PNG stores them.
std::vector<std::uint8_t> png(const std::vector<std::uint8_t>& rows, int width, int height,
                              int channels) {
  std::vector<std::uint8_t> file;
  EXPECT_TRUE(stbi_write_png_to_func(append, &file, width, height, channels, rows.data(),
                                     width * channels));
  return file;
}

TEST(ImageFile, PngDecodesToItsValuesBottomRowFirst) {
  // 2 x 2 RGBA: the top row red then green, the bottom row blue then half-grey.
  const std::vector<std::uint8_t> rows = {255, 0, 0,   255, 0,   255, 0,   128,
                                          0,   0, 255, 255, 128, 128, 128, 0};
  const std::vector<std::uint8_t> file = png(rows, 2, 2, 4);
  const DecodedImage image = decode_image(file.data(), file.size());
  ASSERT_EQ(image.width, 2);
  ASSERT_EQ(image.height, 2);
  const std::vector<float> expected = {0,
                                       0,
                                       1,
                                       1,
                                       128 * (1 / 255.0f),
                                       128 * (1 / 255.0f),
                                       128 * (1 / 255.0f),
                                       0,  // bottom row first
                                       1,
                                       0,
                                       0,
                                       1,
                                       0,
                                       1,
                                       0,
                                       128 * (1 / 255.0f)};
  EXPECT_EQ(image.pixels, expected);
}

TEST(ImageFile, GreyFillsRgbAndMissingAlphaIsOpaque) {
  const std::vector<std::uint8_t> rows = {51, 204};
  const std::vector<std::uint8_t> file = png(rows, 2, 1, 1);
  const DecodedImage image = decode_image(file.data(), file.size());
  const float grey = 51 * (1 / 255.0f);
  const float light = 204 * (1 / 255.0f);
  const std::vector<float> expected = {grey, grey, grey, 1, light, light, light, 1};
  EXPECT_EQ(image.pixels, expected);
}

TEST(ImageFile, OtherFormatsAndBrokenDataAreRefusedByName) {
  const std::string exr = std::string("v/1\x01", 4) + "rest of an OpenEXR header";
  const std::string hdr = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n";
  const std::string junk = "not an image at all";
  const auto refusal = [](const std::string& bytes) {
    try {
      decode_image(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    } catch (const ImageFileError& e) {
      return std::string(e.what());
    }
    return std::string("decoded");
  };
  EXPECT_NE(refusal(exr).find("OpenEXR"), std::string::npos);
  EXPECT_NE(refusal(hdr).find("Radiance HDR"), std::string::npos);
  EXPECT_NE(refusal(junk).find("not a PNG"), std::string::npos);
  EXPECT_NE(refusal("").find("not an image"), std::string::npos);
  std::vector<std::uint8_t> cut = png({1, 2, 3, 4}, 2, 2, 1);
  cut.resize(cut.size() / 2);  // a truncated file
  EXPECT_THROW(decode_image(cut.data(), cut.size()), ImageFileError);
}

}  // namespace
}  // namespace whitted
