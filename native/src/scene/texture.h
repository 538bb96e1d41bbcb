// Textures: images (one picture, or UDIM tiles) with UV lookup and Blender's checker,
// evaluated at a surface point.
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

// What Cycles shows where an image has no pixels: a file it cannot load, or a UDIM
// image's uv outside every tile it has (TEX_IMAGE_MISSING in Cycles).
inline constexpr glm::vec4 kMissingImage{1.0f, 0.0f, 1.0f, 1.0f};

// One picture: a plain image, or one tile of a UDIM image.
struct ImageTile {
  int number = 0;  // a UDIM tile's number (1001 + u + 10 v); 0 for a plain image
  int width = 0;
  int height = 0;
  std::vector<float> pixels;  // linear RGBA, rows bottom to top (as Blender's Image.pixels)
};

// A plain image is one tile that covers every uv (by its extension); a UDIM image's
// tiles, sorted by number, each cover the unit square of uv their number names.
struct ImageTexture {
  std::vector<ImageTile> tiles;
  bool udim = false;
  Extension extension = Extension::kRepeat;
  Interpolation interpolation = Interpolation::kLinear;
};

// Blender's UDIM tile of texture coordinates uv and uv relative to that tile, as Cycles
// finds it: the tile 1001 + trunc(u) + 10 trunc(v), for trunc(u) in [0, 9] and trunc(v)
// in [0, 99] (Blender's tiles run 1001 to 2000); tile 0 when there is none. Truncation,
// not floor, as Cycles: u in (-1, 0) is in the first column, and stays negative for the
// tile's extension.
struct UdimPoint {
  int tile = 0;
  glm::vec2 uv{0.0f};
};
UdimPoint udim_point(glm::vec2 uv);

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
// at (i + 0.5) / size, as in Blender); a UDIM image samples the tile uv lies in
// (udim_point), and is kMissingImage where it has no such tile.
glm::vec4 sample_image(const ImageTexture& image, glm::vec2 uv);

// The image's first tile at uv, as sample_image samples a plain image: what Cycles shows
// of a UDIM image in a box projection or an environment.
glm::vec4 sample_first_tile(const ImageTexture& image, glm::vec2 uv);

// Blender's checker (Cycles svm_checker): whether point p lies in a cell of the first
// colour.
bool checker_first(Vec3 p);

// Builds an image tile from RGBA pixels (NaN and infinite values become 0); throws
// std::invalid_argument on bad sizes.
ImageTile make_image_tile(int number, const float* rgba, int width, int height);

// A plain image of RGBA pixels; throws std::invalid_argument on bad sizes.
ImageTexture make_image_texture(const float* rgba, int width, int height, Extension extension,
                                Interpolation interpolation);

// A UDIM image of its tiles; throws std::invalid_argument without tiles, on a number
// outside 1001 to 2000 or on a number given twice.
ImageTexture make_udim_texture(std::vector<ImageTile> tiles, Extension extension,
                               Interpolation interpolation);

}  // namespace whitted
