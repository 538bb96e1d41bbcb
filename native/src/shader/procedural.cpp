#include "shader/procedural.h"

#include <algorithm>
#include <bit>
#include <cfloat>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "shader/procedural_detail.h"

namespace whitted::procedural {
namespace {

using namespace detail;

// ---------------------------------------------------------------------------------------
// lookup3 (public domain, burtleburtle.net/bob/c/lookup3.c): its `mix` and `final`.

constexpr uint32_t rotate(uint32_t x, int k) {
  return (x << k) | (x >> (32 - k));
}

void mix_words(uint32_t& a, uint32_t& b, uint32_t& c) {
  a -= c, a ^= rotate(c, 4), c += b;
  b -= a, b ^= rotate(a, 6), a += c;
  c -= b, c ^= rotate(b, 8), b += a;
  a -= c, a ^= rotate(c, 16), c += b;
  b -= a, b ^= rotate(a, 19), a += c;
  c -= b, c ^= rotate(b, 4), b += a;
}

void final_words(uint32_t& a, uint32_t& b, uint32_t& c) {
  c ^= b, c -= rotate(b, 14);
  a ^= c, a -= rotate(c, 11);
  b ^= a, b -= rotate(a, 25);
  c ^= b, c -= rotate(b, 16);
  a ^= c, a -= rotate(c, 4);
  b ^= a, b -= rotate(a, 14);
  c ^= b, c -= rotate(b, 24);
}

constexpr uint32_t seed(uint32_t words) {
  return 0xdeadbeefu + (words << 2) + 13u;
}

// ---------------------------------------------------------------------------------------
// Perlin noise (Ken Perlin's improved noise with the gradient sets of OSL and Cycles).

float fade(float t) {
  return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f);
}
float negate_if(float v, uint32_t condition) {
  return condition != 0 ? -v : v;
}

float gradient(uint32_t h, Point<1> d) {
  h &= 15u;
  return negate_if(1.0f + static_cast<float>(h & 7u), h & 8u) * d.x;
}
float gradient(uint32_t h, Point<2> d) {
  h &= 7u;
  const float u = h < 4 ? d.x : d.y;
  const float v = 2.0f * (h < 4 ? d.y : d.x);
  return negate_if(u, h & 1u) + negate_if(v, h & 2u);
}
float gradient(uint32_t h, Point<3> d) {
  h &= 15u;
  const float u = h < 8 ? d.x : d.y;
  const float v = h < 4 ? d.y : (h == 12 || h == 14 ? d.x : d.z);
  return negate_if(u, h & 1u) + negate_if(v, h & 2u);
}
float gradient(uint32_t h, Point<4> d) {
  h &= 31u;
  const float u = h < 24 ? d.x : d.y;
  const float v = h < 16 ? d.y : d.z;
  const float s = h < 8 ? d.z : d.w;
  return negate_if(u, h & 1u) + negate_if(v, h & 2u) + negate_if(s, h & 4u);
}

uint32_t lattice_hash(const glm::vec<1, int>& c) {
  return hash(static_cast<uint32_t>(c.x));
}
uint32_t lattice_hash(const glm::vec<2, int>& c) {
  return hash(static_cast<uint32_t>(c.x), static_cast<uint32_t>(c.y));
}
uint32_t lattice_hash(const glm::vec<3, int>& c) {
  return hash(static_cast<uint32_t>(c.x), static_cast<uint32_t>(c.y), static_cast<uint32_t>(c.z));
}
uint32_t lattice_hash(const glm::vec<4, int>& c) {
  return hash(static_cast<uint32_t>(c.x), static_cast<uint32_t>(c.y), static_cast<uint32_t>(c.z),
              static_cast<uint32_t>(c.w));
}

// The gradients at the cell's 2^N corners (corner bit k: +1 along axis k), blended along
// x first, then y, z and w, with the quintic fade of each axis.
template <int N>
float perlin(Point<N> p) {
  glm::vec<N, int> cell;
  Point<N> f;
  for (int k = 0; k < N; ++k) {
    const float floor = std::floor(p[k]);
    cell[k] = static_cast<int>(floor);
    f[k] = p[k] - floor;
  }
  float values[1 << N];
  for (int corner = 0; corner < (1 << N); ++corner) {
    glm::vec<N, int> at = cell;
    Point<N> d = f;
    for (int k = 0; k < N; ++k) {
      if ((corner >> k) & 1) at[k] += 1, d[k] -= 1.0f;
    }
    values[corner] = gradient(lattice_hash(at), d);
  }
  for (int k = 0, count = 1 << N; k < N; ++k, count >>= 1) {
    const float t = fade(f[k]);
    for (int i = 0; i < count / 2; ++i) values[i] = lerp(values[2 * i], values[2 * i + 1], t);
  }
  return values[0];
}

// Cycles' experimentally found scales to about [-1, 1], per dimension.
constexpr float kNoiseScale[] = {0.0f, 0.2500f, 0.6616f, 0.9820f, 0.8344f};

template <int N>
float snoise(Point<N> p) {
  // Repeated every 100000 on each axis, as Cycles does, against float precision loss.
  for (int k = 0; k < N; ++k) p[k] = std::fmod(p[k], 100000.0f);
  return kNoiseScale[N] * perlin<N>(p);
}

// ---------------------------------------------------------------------------------------
// The Noise Texture's fractals (Cycles' fractal_noise.h).

template <int N>
float fbm(Point<N> p, float detail, float roughness, float lacunarity, bool normalize) {
  float scale = 1.0f, amp = 1.0f, maxamp = 0.0f, sum = 0.0f;
  const int octaves = static_cast<int>(detail);
  for (int i = 0; i <= octaves; ++i) {
    sum += snoise<N>(scale * p) * amp;
    maxamp += amp;
    amp *= roughness;
    scale *= lacunarity;
  }
  const float rmd = detail - std::floor(detail);
  if (rmd == 0.0f) return normalize ? 0.5f * sum / maxamp + 0.5f : sum;
  const float sum2 = sum + snoise<N>(scale * p) * amp;
  if (!normalize) return lerp(sum, sum2, rmd);
  return lerp(0.5f * sum / maxamp + 0.5f, 0.5f * sum2 / (maxamp + amp) + 0.5f, rmd);
}

template <int N>
float multifractal(Point<N> p, float detail, float roughness, float lacunarity) {
  float value = 1.0f, pwr = 1.0f;
  const int octaves = static_cast<int>(detail);
  for (int i = 0; i <= octaves; ++i) {
    value *= pwr * snoise<N>(p) + 1.0f;
    pwr *= roughness;
    p *= lacunarity;
  }
  const float rmd = detail - std::floor(detail);
  if (rmd != 0.0f) value *= rmd * pwr * snoise<N>(p) + 1.0f;
  return value;
}

template <int N>
float hetero_terrain(Point<N> p, float detail, float roughness, float lacunarity, float offset) {
  float pwr = roughness;
  float value = offset + snoise<N>(p);  // the first octave unscaled
  p *= lacunarity;
  const int octaves = static_cast<int>(detail);
  for (int i = 1; i <= octaves; ++i) {
    value += (snoise<N>(p) + offset) * pwr * value;
    pwr *= roughness;
    p *= lacunarity;
  }
  const float rmd = detail - std::floor(detail);
  if (rmd != 0.0f) value += rmd * ((snoise<N>(p) + offset) * pwr * value);
  return value;
}

template <int N>
float hybrid_multifractal(Point<N> p, float detail, float roughness, float lacunarity, float offset,
                          float gain) {
  float pwr = 1.0f, value = 0.0f, weight = 1.0f;
  const int octaves = static_cast<int>(detail);
  for (int i = 0; weight > 0.001f && i <= octaves; ++i) {
    weight = std::min(weight, 1.0f);
    const float signal = (snoise<N>(p) + offset) * pwr;
    pwr *= roughness;
    value += weight * signal;
    weight *= gain * signal;
    p *= lacunarity;
  }
  const float rmd = detail - std::floor(detail);
  if (rmd != 0.0f && weight > 0.001f) {
    weight = std::min(weight, 1.0f);
    value += rmd * weight * ((snoise<N>(p) + offset) * pwr);
  }
  return value;
}

template <int N>
float ridged_multifractal(Point<N> p, float detail, float roughness, float lacunarity, float offset,
                          float gain) {
  float pwr = roughness;
  float signal = offset - std::fabs(snoise<N>(p));
  signal *= signal;
  float value = signal;
  const int octaves = static_cast<int>(detail);
  for (int i = 1; i <= octaves; ++i) {
    p *= lacunarity;
    const float weight = std::clamp(signal * gain, 0.0f, 1.0f);
    signal = offset - std::fabs(snoise<N>(p));
    signal *= signal;
    signal *= weight;
    value += signal * pwr;
    pwr *= roughness;
  }
  return value;
}

template <int N>
float fractal(const NoiseSettings& s, Point<N> p) {
  switch (s.type) {
    case NoiseType::kFbm:
      return fbm<N>(p, s.detail, s.roughness, s.lacunarity, s.normalize);
    case NoiseType::kMultifractal:
      return multifractal<N>(p, s.detail, s.roughness, s.lacunarity);
    case NoiseType::kHybridMultifractal:
      return hybrid_multifractal<N>(p, s.detail, s.roughness, s.lacunarity, s.offset, s.gain);
    case NoiseType::kRidgedMultifractal:
      return ridged_multifractal<N>(p, s.detail, s.roughness, s.lacunarity, s.offset, s.gain);
    case NoiseType::kHeteroTerrain:
      return hetero_terrain<N>(p, s.detail, s.roughness, s.lacunarity, s.offset);
  }
  return 0.0f;
}

// Cycles' seeds for the distortion and the colour channels: a point offset by [100, 200]
// on each axis, from hashes of the seed.
template <int N>
Point<N> seed_offset(float seed) {
  Point<N> offset;
  if constexpr (N == 1) {
    offset.x = 100.0f + hash_to_float(seed) * 100.0f;
  } else {
    for (int k = 0; k < N; ++k) {
      offset[k] = 100.0f + hash_to_float(seed, static_cast<float>(k)) * 100.0f;
    }
  }
  return offset;
}

template <int N>
glm::vec4 noise(const NoiseSettings& s, Point<N> p) {
  if (s.distortion != 0.0f) {
    Point<N> shift;
    for (int k = 0; k < N; ++k) {
      shift[k] = snoise<N>(p + seed_offset<N>(static_cast<float>(k))) * s.distortion;
    }
    p += shift;
  }
  const float value = fractal<N>(s, p);
  if (!s.color) return glm::vec4(value);
  return {value, fractal<N>(s, p + seed_offset<N>(static_cast<float>(N))),
          fractal<N>(s, p + seed_offset<N>(static_cast<float>(N + 1))), value};
}

// Cycles' smoothstepf: 0 below 0, 1 above 1.
float smoothstep01(float f) {
  if (f <= 0.0f) return 0.0f;
  if (f >= 1.0f) return 1.0f;
  const float ff = f * f;
  return 3.0f * ff - 2.0f * ff * f;
}

// Cycles' brick_noise: a fast integer noise in [0, 1).
float brick_noise(uint32_t n) {
  n = (n + 1013u) & 0x7fffffffu;
  n = (n >> 13) ^ n;
  const uint32_t nn = (n * (n * n * 60493u + 19990303u) + 1376312589u) & 0x7fffffffu;
  return 0.5f * (static_cast<float>(nn) / 1073741824.0f);
}

}  // namespace

uint32_t hash(uint32_t kx) {
  uint32_t a = seed(1), b = a, c = a;
  a += kx;
  final_words(a, b, c);
  return c;
}
uint32_t hash(uint32_t kx, uint32_t ky) {
  uint32_t a = seed(2), b = a, c = a;
  b += ky;
  a += kx;
  final_words(a, b, c);
  return c;
}
uint32_t hash(uint32_t kx, uint32_t ky, uint32_t kz) {
  uint32_t a = seed(3), b = a, c = a;
  c += kz;
  b += ky;
  a += kx;
  final_words(a, b, c);
  return c;
}
uint32_t hash(uint32_t kx, uint32_t ky, uint32_t kz, uint32_t kw) {
  uint32_t a = seed(4), b = a, c = a;
  a += kx;
  b += ky;
  c += kz;
  mix_words(a, b, c);
  a += kw;
  final_words(a, b, c);
  return c;
}

float signed_noise(float p) {
  return snoise<1>(Point<1>(p));
}
float signed_noise(glm::vec2 p) {
  return snoise<2>(p);
}
float signed_noise(Vec3 p) {
  return snoise<3>(p);
}
float signed_noise(glm::vec4 p) {
  return snoise<4>(p);
}

glm::vec4 noise_texture(const NoiseSettings& settings, Vec3 p, float w) {
  NoiseSettings s = settings;
  s.detail = std::clamp(s.detail, 0.0f, 15.0f);
  s.roughness = std::fmax(s.roughness, 0.0f);
  p *= s.scale;
  w *= s.scale;
  switch (s.dimensions) {
    case 1:
      return noise<1>(s, Point<1>(w));
    case 2:
      return noise<2>(s, glm::vec2(p));
    case 4:
      return noise<4>(s, glm::vec4(p, w));
    default:
      return noise<3>(s, p);
  }
}

float wave_texture(const WaveSettings& s, Vec3 p) {
  p *= s.scale;
  p = (p + 0.000001f) * 0.999999f;  // Cycles' guard against unit coordinates
  float n;
  if (s.type == 0) {
    n = s.direction == 3 ? (p.x + p.y + p.z) * 10.0f : p[static_cast<int>(s.direction)] * 20.0f;
  } else {
    Vec3 r = p;
    if (s.direction < 3) r[static_cast<int>(s.direction)] = 0.0f;
    n = glm::length(r) * 20.0f;
  }
  n += s.phase;
  if (s.distortion != 0.0f) {
    // The detail's fractal: normalised fBM of lacunarity 2, its octaves at most 15.
    const float detail = std::clamp(s.detail, 0.0f, 15.0f);
    n += s.distortion *
         (fbm<3>(p * s.detail_scale, detail, s.detail_roughness, 2.0f, true) * 2.0f - 1.0f);
  }
  if (s.profile == 0) return 0.5f + 0.5f * std::sin(n - 0.5f * kPi);
  n /= 2.0f * kPi;
  if (s.profile == 1) return n - std::floor(n);
  return std::fabs(n - std::floor(n + 0.5f)) * 2.0f;
}

Vec3 magic_texture(Vec3 p, float scale, int depth, float distortion) {
  // Each coordinate brought into (-2 pi, 2 pi) first, as Cycles does.
  const float px = std::fmod(p.x, 2.0f * kPi);
  const float py = std::fmod(p.y, 2.0f * kPi);
  const float pz = std::fmod(p.z, 2.0f * kPi);
  float x = std::sin((px + py + pz) * 5.0f * scale);
  float y = std::cos((-px + py - pz) * 5.0f * scale);
  float z = -std::cos((-px - py + pz) * 5.0f * scale);
  // Each level of depth folds one coordinate through a sine or cosine of the others.
  if (depth > 0) {
    x *= distortion, y *= distortion, z *= distortion;
    y = -std::cos(x - y + z) * distortion;
  }
  if (depth > 1) x = std::cos(x - y - z) * distortion;
  if (depth > 2) z = std::sin(-x - y - z) * distortion;
  if (depth > 3) x = -std::cos(-x + y - z) * distortion;
  if (depth > 4) y = -std::sin(-x + y + z) * distortion;
  if (depth > 5) y = -std::cos(-x + y + z) * distortion;
  if (depth > 6) x = std::cos(x + y + z) * distortion;
  if (depth > 7) z = std::sin(x + y - z) * distortion;
  if (depth > 8) x = -std::cos(-x - y + z) * distortion;
  if (depth > 9) y = -std::sin(x - y + z) * distortion;
  if (distortion != 0.0f) {
    const float d = 2.0f * distortion;
    x /= d, y /= d, z /= d;
  }
  return {0.5f - x, 0.5f - y, 0.5f - z};
}

glm::vec2 brick_texture(const BrickSettings& s, Vec3 p) {
  p *= s.scale;
  float brick_width = s.brick_width;
  float offset = 0.0f;
  const int row = static_cast<int>(std::floor(p.y / s.row_height));
  if (s.offset_frequency != 0 && s.squash_frequency != 0) {
    brick_width *= row % s.squash_frequency != 0 ? 1.0f : s.squash;
    offset = row % s.offset_frequency != 0 ? 0.0f : brick_width * s.offset;
  }
  const int brick = static_cast<int>(std::floor((p.x + offset) / brick_width));
  const float x = (p.x + offset) - brick_width * static_cast<float>(brick);
  const float y = p.y - s.row_height * static_cast<float>(row);
  const uint32_t id = (static_cast<uint32_t>(row) << 16) + (static_cast<uint32_t>(brick) & 0xFFFFu);
  const float tint = std::clamp(brick_noise(id) + s.bias, 0.0f, 1.0f);
  const float min_dist = std::min(std::min(x, y), std::min(brick_width - x, s.row_height - y));
  float mortar;
  if (min_dist >= s.mortar_size) {
    mortar = 0.0f;
  } else if (s.mortar_smooth == 0.0f) {
    mortar = 1.0f;
  } else {
    mortar = smoothstep01((1.0f - min_dist / s.mortar_size) / s.mortar_smooth);
  }
  return {tint, mortar};
}

glm::vec4 white_noise(int dimensions, Vec3 p, float w) {
  // Each dimension's Value hash, and its Color: the Value, then two more hashes of the
  // words with a 1 and a 2 appended (4D: the words reordered instead).
  const uint32_t one = bits(1.0f), two = bits(2.0f);
  const uint32_t x = bits(p.x), y = bits(p.y), z = bits(p.z), k = bits(w);
  switch (dimensions) {
    case 1:
      return {unit(hash(k)), unit(hash(k, one)), unit(hash(k, two)), unit(hash(k))};
    case 2: {
      const float value = unit(hash(x, y));
      return {value, unit(hash(x, y, one)), unit(hash(x, y, two)), value};
    }
    case 3: {
      const float value = unit(hash(x, y, z));
      return {value, unit(hash(x, y, z, one)), unit(hash(x, y, z, two)), value};
    }
    default: {
      const float value = unit(hash(x, y, z, k));
      return {value, unit(hash(z, x, k, y)), unit(hash(k, z, y, x)), value};
    }
  }
}

}  // namespace whitted::procedural

namespace whitted::procedural {

glm::vec4 noise_op(uint32_t mode, const glm::vec4& vector, const glm::vec4& b, const glm::vec4& c) {
  NoiseSettings s;
  s.dimensions = static_cast<int>(mode_field::kDimensions.in(mode)) + 1;
  s.type = static_cast<NoiseType>(mode_field::kNoiseType.in(mode));
  s.normalize = mode_field::kNormalize.on(mode);
  s.color = mode_field::kNoiseColor.on(mode);
  s.scale = b.y, s.detail = b.z, s.roughness = b.w;
  s.lacunarity = c.x, s.offset = c.y, s.gain = c.z, s.distortion = c.w;
  return noise_texture(s, Vec3(vector), b.x);
}

glm::vec4 voronoi_op(uint32_t mode, const glm::vec4& vector, const glm::vec4& b,
                     const glm::vec4& c) {
  VoronoiSettings s;
  s.dimensions = static_cast<int>(mode_field::kDimensions.in(mode)) + 1;
  s.feature = static_cast<VoronoiFeature>(mode_field::kVoronoiFeature.in(mode));
  s.metric = static_cast<VoronoiMetric>(mode_field::kVoronoiMetric.in(mode));
  s.integer_hash = mode_field::kVoronoiIntegerHash.on(mode);
  s.normalize = mode_field::kNormalize.on(mode);
  s.scale = b.y, s.detail = b.z, s.roughness = b.w;
  s.lacunarity = c.x, s.smoothness = c.y, s.exponent = c.z, s.randomness = c.w;
  const VoronoiResult r = voronoi_texture(s, Vec3(vector), b.x);
  switch (mode_field::kVoronoiOutput.in(mode)) {
    case 1:
      return {r.color, 1.0f};
    case 2:
      return r.position;
    default:
      return glm::vec4(r.distance);
  }
}

glm::vec4 wave_op(uint32_t mode, const glm::vec4& vector, const glm::vec4& b, const glm::vec4& c) {
  WaveSettings s;
  s.type = mode_field::kWaveType.in(mode);
  // Bands' and rings' directions lie in the same bits.
  s.direction = (s.type == 0 ? mode_field::kWaveBands : mode_field::kWaveRings).in(mode);
  s.profile = mode_field::kWaveProfile.in(mode);
  s.scale = b.x, s.distortion = b.y, s.detail = b.z, s.detail_scale = b.w;
  s.detail_roughness = c.x, s.phase = c.y;
  return glm::vec4(wave_texture(s, Vec3(vector)));
}

glm::vec4 magic_op(uint32_t mode, const glm::vec4& vector, const glm::vec4& b, const glm::vec4& c) {
  const Vec3 color =
      magic_texture(Vec3(vector), b.x, static_cast<int>(mode_field::kMagicDepth.in(mode)), c.x);
  return {color, (color.x + color.y + color.z) * (1.0f / 3.0f)};
}

glm::vec4 brick_op(uint32_t mode, const glm::vec4& vector, const glm::vec4& b, const glm::vec4& c) {
  BrickSettings s;
  s.offset_frequency = static_cast<int>(mode_field::kBrickOffset.in(mode));
  s.squash_frequency = static_cast<int>(mode_field::kBrickSquash.in(mode));
  s.scale = b.x, s.mortar_size = b.y, s.mortar_smooth = b.z, s.bias = b.w;
  s.brick_width = c.x, s.row_height = c.y, s.offset = c.z, s.squash = c.w;
  return {brick_texture(s, Vec3(vector)), 0.0f, 0.0f};
}

glm::vec4 white_noise_op(uint32_t mode, const glm::vec4& vector, const glm::vec4& w) {
  const int dimensions = static_cast<int>(mode_field::kDimensions.in(mode)) + 1;
  const glm::vec4 noise = white_noise(dimensions, Vec3(vector), w.x);
  return mode_field::kWhiteNoiseColor.on(mode) ? noise : glm::vec4(noise.w);
}

}  // namespace whitted::procedural
