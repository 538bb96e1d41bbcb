#include "scene/texture.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/limits.h"

namespace whitted {
namespace {

// Resolves texel index i of an axis of n texels, or returns -1 outside a clipped image.
int wrap(int i, int n, Extension extension) {
  if (i >= 0 && i < n) return i;  // inside the image, as every extension leaves it
  switch (extension) {
    case Extension::kRepeat:
      i %= n;
      return i < 0 ? i + n : i;
    case Extension::kExtend:
      return std::clamp(i, 0, n - 1);
    case Extension::kClip:
      return (i < 0 || i >= n) ? -1 : i;
  }
  return -1;
}

glm::vec4 texel(const ImageTile& tile, Extension extension, int x, int y) {
  x = wrap(x, tile.width, extension);
  y = wrap(y, tile.height, extension);
  if (x < 0 || y < 0) return glm::vec4(0.0f);  // outside a clipped image: transparent
  const float* p = &tile.pixels[4 * (static_cast<size_t>(y) * tile.width + x)];
  return {p[0], p[1], p[2], p[3]};
}

// One picture at uv, by the image's extension and interpolation.
glm::vec4 sample_tile(const ImageTexture& image, const ImageTile& tile, glm::vec2 uv) {
  if (image.extension == Extension::kClip &&
      (uv.x < 0.0f || uv.x > 1.0f || uv.y < 0.0f || uv.y > 1.0f)) {
    return glm::vec4(0.0f);
  }
  const float x = uv.x * static_cast<float>(tile.width);
  const float y = uv.y * static_cast<float>(tile.height);
  if (!std::isfinite(x) || !std::isfinite(y) || std::fabs(x) > limits::kMaxTexelCoordinate ||
      std::fabs(y) > limits::kMaxTexelCoordinate) {
    return glm::vec4(0.0f);
  }
  if (image.interpolation == Interpolation::kClosest) {
    return texel(tile, image.extension, static_cast<int>(std::floor(x)),
                 static_cast<int>(std::floor(y)));
  }
  const float fx = x - 0.5f;
  const float fy = y - 0.5f;
  const int x0 = static_cast<int>(std::floor(fx));
  const int y0 = static_cast<int>(std::floor(fy));
  const float tx = fx - static_cast<float>(x0);
  const float ty = fy - static_cast<float>(y0);
  const Extension e = image.extension;
  return (1.0f - ty) * ((1.0f - tx) * texel(tile, e, x0, y0) + tx * texel(tile, e, x0 + 1, y0)) +
         ty * ((1.0f - tx) * texel(tile, e, x0, y0 + 1) + tx * texel(tile, e, x0 + 1, y0 + 1));
}

// Blender's UDIM tile numbers: 10 columns of u, 100 rows of v.
constexpr int kFirstUdim = 1001;
constexpr int kLastUdim = 2000;

}  // namespace

UdimPoint udim_point(glm::vec2 uv) {
  // The bounds also keep the truncation defined (no NaN, nothing beyond int).
  if (!(uv.x > -1.0f && uv.x < 10.0f && uv.y > -1.0f && uv.y < 100.0f)) return {};
  const int column = static_cast<int>(uv.x);  // truncated toward 0, as Cycles
  const int row = static_cast<int>(uv.y);
  return {kFirstUdim + column + 10 * row,
          {uv.x - static_cast<float>(column), uv.y - static_cast<float>(row)}};
}

glm::vec4 sample_image(const ImageTexture& image, glm::vec2 uv) {
  if (!image.udim) return sample_tile(image, image.tiles.front(), uv);
  const UdimPoint point = udim_point(uv);
  const auto found =
      std::lower_bound(image.tiles.begin(), image.tiles.end(), point.tile,
                       [](const ImageTile& tile, int number) { return tile.number < number; });
  if (found == image.tiles.end() || found->number != point.tile) return kMissingImage;
  return sample_tile(image, *found, point.uv);
}

glm::vec4 sample_first_tile(const ImageTexture& image, glm::vec2 uv) {
  return sample_tile(image, image.tiles.front(), uv);
}

bool checker_first(Vec3 p) {
  p = (p + 0.000001f) * 0.999999f;  // avoids flicker on whole-number coordinates
  const auto parity = [](float v) {
    return static_cast<int>(std::fabs(std::fmod(std::floor(v), 2.0f)));
  };
  return (parity(p.x) == parity(p.y)) == (parity(p.z) == 1);
}

glm::vec4 Texture::evaluate(const TexturePoint& point) const {
  const Vec3 coord = coordinates == TexCoord::kUV          ? Vec3(point.uv, 0.0f)
                     : coordinates == TexCoord::kGenerated ? point.generated
                                                           : point.object;
  if (const auto* image = std::get_if<ImageTexture>(&source)) {
    return sample_image(*image, glm::vec2(coord));
  }
  const auto& checker = std::get<CheckerTexture>(source);
  return glm::vec4(checker_first(coord * checker.scale) ? checker.color1 : checker.color2, 1.0f);
}

ImageTile make_image_tile(int number, const float* rgba, int width, int height) {
  if (width <= 0 || height <= 0 || int64_t{width} * height > (int64_t{1} << 28)) {
    throw std::invalid_argument("an image texture must have between 1 and 2^28 pixels");
  }
  ImageTile tile;
  tile.number = number;
  tile.width = width;
  tile.height = height;
  tile.pixels.assign(rgba, rgba + 4 * static_cast<size_t>(width) * height);
  for (float& v : tile.pixels) {
    if (!std::isfinite(v)) v = 0.0f;  // a NaN texel would poison every pixel that reads it
  }
  return tile;
}

ImageTexture make_image_texture(const float* rgba, int width, int height, Extension extension,
                                Interpolation interpolation) {
  ImageTexture image;
  image.tiles.push_back(make_image_tile(0, rgba, width, height));
  image.extension = extension;
  image.interpolation = interpolation;
  return image;
}

ImageTexture make_udim_texture(std::vector<ImageTile> tiles, Extension extension,
                               Interpolation interpolation) {
  if (tiles.empty()) throw std::invalid_argument("a UDIM image needs at least one tile");
  std::sort(tiles.begin(), tiles.end(),
            [](const ImageTile& a, const ImageTile& b) { return a.number < b.number; });
  for (size_t i = 0; i < tiles.size(); ++i) {
    if (tiles[i].number < kFirstUdim || tiles[i].number > kLastUdim) {
      throw std::invalid_argument("UDIM tile " + std::to_string(tiles[i].number) +
                                  " is outside 1001 to 2000");
    }
    if (i > 0 && tiles[i].number == tiles[i - 1].number) {
      throw std::invalid_argument("UDIM tile " + std::to_string(tiles[i].number) +
                                  " is given twice");
    }
  }
  ImageTexture image;
  image.tiles = std::move(tiles);
  image.udim = true;
  image.extension = extension;
  image.interpolation = interpolation;
  return image;
}

}  // namespace whitted
