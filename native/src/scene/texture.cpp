#include "scene/texture.h"

#include <cmath>
#include <stdexcept>

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

glm::vec4 texel(const ImageTexture& image, int x, int y) {
  x = wrap(x, image.width, image.extension);
  y = wrap(y, image.height, image.extension);
  if (x < 0 || y < 0) return glm::vec4(0.0f);  // outside a clipped image: transparent
  const float* p = &image.pixels[4 * (static_cast<size_t>(y) * image.width + x)];
  return {p[0], p[1], p[2], p[3]};
}

}  // namespace

glm::vec4 sample_image(const ImageTexture& image, glm::vec2 uv) {
  if (image.extension == Extension::kClip &&
      (uv.x < 0.0f || uv.x > 1.0f || uv.y < 0.0f || uv.y > 1.0f)) {
    return glm::vec4(0.0f);
  }
  const float x = uv.x * static_cast<float>(image.width);
  const float y = uv.y * static_cast<float>(image.height);
  if (!std::isfinite(x) || !std::isfinite(y) || std::fabs(x) > limits::kMaxTexelCoordinate ||
      std::fabs(y) > limits::kMaxTexelCoordinate) {
    return glm::vec4(0.0f);
  }
  if (image.interpolation == Interpolation::kClosest) {
    return texel(image, static_cast<int>(std::floor(x)), static_cast<int>(std::floor(y)));
  }
  const float fx = x - 0.5f;
  const float fy = y - 0.5f;
  const int x0 = static_cast<int>(std::floor(fx));
  const int y0 = static_cast<int>(std::floor(fy));
  const float tx = fx - static_cast<float>(x0);
  const float ty = fy - static_cast<float>(y0);
  return (1.0f - ty) * ((1.0f - tx) * texel(image, x0, y0) + tx * texel(image, x0 + 1, y0)) +
         ty * ((1.0f - tx) * texel(image, x0, y0 + 1) + tx * texel(image, x0 + 1, y0 + 1));
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

ImageTexture make_image_texture(const float* rgba, int width, int height, Extension extension,
                                Interpolation interpolation) {
  if (width <= 0 || height <= 0 || int64_t{width} * height > (int64_t{1} << 28)) {
    throw std::invalid_argument("an image texture must have between 1 and 2^28 pixels");
  }
  ImageTexture image;
  image.width = width;
  image.height = height;
  image.extension = extension;
  image.interpolation = interpolation;
  image.pixels.assign(rgba, rgba + 4 * static_cast<size_t>(width) * height);
  for (float& v : image.pixels) {
    if (!std::isfinite(v)) v = 0.0f;  // a NaN texel would poison every pixel that reads it
  }
  return image;
}

}  // namespace whitted
