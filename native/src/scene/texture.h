// Textures: images with UV lookup and Blender's checker, evaluated at a surface point.
#pragma once

#include <variant>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "core/math.h"

namespace whitted {

enum class TexCoord { kUV, kGenerated, kObject };
enum class Extension { kRepeat, kExtend, kClip };
enum class Interpolation { kLinear, kClosest };

struct ImageTexture {
  int width = 0;
  int height = 0;
  std::vector<float> pixels;  // linear RGBA, rows bottom to top (as Blender's Image.pixels)
  Extension extension = Extension::kRepeat;
  Interpolation interpolation = Interpolation::kLinear;
};

struct CheckerTexture {
  Color color1{0.8f};
  Color color2{0.2f};
  float scale = 5.0f;
};

// The coordinates a texture may be looked up with, at one surface point.
struct TexturePoint {
  glm::vec2 uv{0.0f};
  Vec3 generated{0.0f};  // object space mapped to [0,1] over the mesh's bounds
  Vec3 object{0.0f};     // object space
};

struct Texture {
  TexCoord coordinates = TexCoord::kUV;
  std::variant<ImageTexture, CheckerTexture> source;

  glm::vec4 evaluate(const TexturePoint& point) const;
};

// The image at texture coordinates uv, by its extension and interpolation (texel centres
// at (i + 0.5) / size, as in Blender).
glm::vec4 sample_image(const ImageTexture& image, glm::vec2 uv);

// Blender's checker (Cycles svm_checker): whether point p lies in a cell of the first
// colour.
bool checker_first(Vec3 p);

// Builds an image texture from RGBA pixels; throws std::invalid_argument on bad sizes.
ImageTexture make_image_texture(const float* rgba, int width, int height, Extension extension,
                                Interpolation interpolation);

}  // namespace whitted
