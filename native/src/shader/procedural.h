// The procedural textures of a shader program (ops NOISE, VORONOI, WAVE, MAGIC, BRICK):
// Blender's definitions (Cycles' SVM kernels), written for one point at a time. Pure
// functions of their arguments: no state, safe from any thread.
#pragma once

#include <cstdint>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "core/math.h"
#include "shader/ops.h"

namespace whitted::procedural {

// Bob Jenkins' lookup3 hash of 1..4 words, as Cycles hashes lattice points and seeds.
uint32_t hash(uint32_t kx);
uint32_t hash(uint32_t kx, uint32_t ky);
uint32_t hash(uint32_t kx, uint32_t ky, uint32_t kz);
uint32_t hash(uint32_t kx, uint32_t ky, uint32_t kz, uint32_t kw);

// Signed Perlin noise of 1..4 dimensions, about [-1, 1] (Cycles' snoise_*d).
float signed_noise(float p);
float signed_noise(glm::vec2 p);
float signed_noise(Vec3 p);
float signed_noise(glm::vec4 p);

// The Noise Texture's fractal kinds (ShaderNodeTexNoise.noise_type), in ops.py's order.
enum class NoiseType : uint32_t {
  kFbm,
  kMultifractal,
  kHybridMultifractal,
  kRidgedMultifractal,
  kHeteroTerrain
};

struct NoiseSettings {
  int dimensions = 3;  // 1..4
  NoiseType type = NoiseType::kFbm;
  bool normalize = true;
  bool color = false;  // compute the Color output (two more fractals)
  float scale = 5.0f, detail = 2.0f, roughness = 0.5f, lacunarity = 2.0f;
  float offset = 0.0f, gain = 1.0f, distortion = 0.0f;
};
// The Noise Texture at `p` (and `w`, for 1D and 4D): (Color, Fac); without `color` the
// Color is Fac in all three.
glm::vec4 noise_texture(const NoiseSettings& s, Vec3 p, float w);

// The Voronoi Texture's features and metrics (ShaderNodeTexVoronoi.feature, .distance),
// in ops.py's order.
enum class VoronoiFeature : uint32_t { kF1, kF2, kSmoothF1, kDistanceToEdge, kNSphereRadius };
enum class VoronoiMetric : uint32_t { kEuclidean, kManhattan, kChebychev, kMinkowski };

struct VoronoiSettings {
  int dimensions = 3;  // 1..4
  VoronoiFeature feature = VoronoiFeature::kF1;
  VoronoiMetric metric = VoronoiMetric::kEuclidean;
  bool normalize = false;
  bool integer_hash = false;  // 2D-4D cells hashed by their integers (Blender 5.0)
  float scale = 5.0f, detail = 0.0f, roughness = 0.5f, lacunarity = 2.0f;
  float smoothness = 1.0f, exponent = 0.5f, randomness = 1.0f;
};
struct VoronoiResult {
  float distance = 0.0f;  // Distance (F1, F2, Smooth F1, Distance to Edge) or Radius
  Vec3 color{0.0f};
  glm::vec4 position{0.0f};  // Position in xyz, W in w
};
VoronoiResult voronoi_texture(const VoronoiSettings& s, Vec3 p, float w);

struct WaveSettings {
  uint32_t type = 0;       // 0 bands, 1 rings
  uint32_t direction = 0;  // bands: X, Y, Z, diagonal; rings: X, Y, Z, spherical
  uint32_t profile = 0;    // 0 sine, 1 saw, 2 triangle
  float scale = 5.0f, distortion = 0.0f, detail = 2.0f, detail_scale = 1.0f;
  float detail_roughness = 0.5f, phase = 0.0f;
};
float wave_texture(const WaveSettings& s, Vec3 p);

// The Magic Texture's colour; its Fac is the colour's average.
Vec3 magic_texture(Vec3 p, float scale, int depth, float distortion);

struct BrickSettings {
  float scale = 5.0f, mortar_size = 0.02f, mortar_smooth = 0.1f, bias = 0.0f;
  float brick_width = 0.5f, row_height = 0.25f;
  float offset = 0.5f, squash = 1.0f;  // the node's offset and squash amounts
  int offset_frequency = 2, squash_frequency = 2;
};
// The Brick Texture's (tint, mortar): tint mixes Color1 to Color2, mortar the result
// to the Mortar colour (the node's Fac).
glm::vec2 brick_texture(const BrickSettings& s, Vec3 p);

// The White Noise Texture: hashes of the point's float bits in [0, 1], Cycles'
// hash_float*_to_float for the Value and hash_float*_to_float3 for the Color. 1D reads
// `w` only, 2D the point's x and y, 3D its xyz, 4D its xyz and `w`: (Color, Value).
glm::vec4 white_noise(int dimensions, Vec3 p, float w);

}  // namespace whitted::procedural

namespace whitted::procedural {

// The program's ops over their registers (docs/notes/shader_program.md gives the modes
// and operands); `mode` holds their fields (shader/ops.h kOpModes), checked by Program.
glm::vec4 voronoi_op(uint32_t mode, const glm::vec4& vector, const glm::vec4& b,
                     const glm::vec4& c);
glm::vec4 noise_op(uint32_t mode, const glm::vec4& vector, const glm::vec4& b, const glm::vec4& c);
glm::vec4 wave_op(uint32_t mode, const glm::vec4& vector, const glm::vec4& b, const glm::vec4& c);
glm::vec4 magic_op(uint32_t mode, const glm::vec4& vector, const glm::vec4& b, const glm::vec4& c);
glm::vec4 brick_op(uint32_t mode, const glm::vec4& vector, const glm::vec4& b, const glm::vec4& c);
// (Color, Value) with the color field, else the Value in all four.
glm::vec4 white_noise_op(uint32_t mode, const glm::vec4& vector, const glm::vec4& w);
// Blender 4.3's Gabor Texture (shader/gabor.cpp): its Value, Phase or Intensity in all four.
glm::vec4 gabor_op(uint32_t mode, const glm::vec4& vector, const glm::vec4& scale,
                   const glm::vec4& frequency, const glm::vec4& anisotropy,
                   const glm::vec4& orientation);

}  // namespace whitted::procedural
