// The Voronoi Texture (ShaderNodeTexVoronoi): Blender's definitions (Cycles' voronoi.h),
// for one point at a time.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "shader/procedural.h"
#include "shader/procedural_detail.h"

namespace whitted::procedural {
namespace {

using namespace detail;

// Feature points jittered in each cell by a hash of the cell.

// PCG 2D-4D (Jarzynski and Olano, "Hash Functions for GPU Rendering", JCGT 2020) on
// signed integers, as Blender 5.0 hashes Voronoi cells: wrapping arithmetic, an
// arithmetic shift, the sign bit cleared, then scaled to [0, 1].
uint32_t shift_xor(uint32_t v) {
  return v ^ static_cast<uint32_t>(static_cast<int32_t>(v) >> 16);
}
constexpr uint32_t kPcgMul = 1664525u, kPcgAdd = 1013904223u;

template <int N>
Point<N> pcg(const glm::vec<N, int>& cell) {
  uint32_t v[4] = {};
  for (int k = 0; k < N; ++k) v[k] = static_cast<uint32_t>(cell[k]) * kPcgMul + kPcgAdd;
  const auto round = [&v] {
    if constexpr (N == 2) {
      v[0] += v[1] * kPcgMul;
      v[1] += v[0] * kPcgMul;
    } else if constexpr (N == 3) {
      v[0] += v[1] * v[2];
      v[1] += v[2] * v[0];
      v[2] += v[0] * v[1];
    } else {
      v[0] += v[1] * v[3];
      v[1] += v[2] * v[0];
      v[2] += v[0] * v[1];
      v[3] += v[1] * v[2];
    }
  };
  round();
  for (int k = 0; k < N; ++k) v[k] = shift_xor(v[k]);
  round();
  Point<N> out;
  for (int k = 0; k < N; ++k) {
    out[k] = static_cast<float>(v[k] & 0x7FFFFFFFu) * (1.0f / static_cast<float>(0x7FFFFFFFu));
  }
  return out;
}

// A cell's integer coordinates (x86's conversion: INT_MIN out of range).
template <int N>
glm::vec<N, int> integer_cell(const Point<N>& cell) {
  glm::vec<N, int> out;
  for (int k = 0; k < N; ++k) {
    const bool in_range = cell[k] >= -2147483648.0f && cell[k] < 2147483648.0f;
    out[k] = in_range ? static_cast<int>(cell[k]) : std::numeric_limits<int>::min();
  }
  return out;
}

// The feature point's place in its cell (and the cell's colour, below): hashes of the
// cell's coordinates, their float bits (Blender before 5.0, and 1D) or their integers.
template <int N>
Point<N> cell_point(const Point<N>& cell, bool integer_hash) {
  if constexpr (N > 1) {
    if (integer_hash) return pcg<N>(integer_cell<N>(cell));
  }
  if constexpr (N == 1) {
    return Point<1>(hash_to_float(cell.x));
  } else if constexpr (N == 2) {
    return {hash_to_float(cell.x, cell.y), unit(hash(bits(cell.x), bits(cell.y), bits(1.0f)))};
  } else if constexpr (N == 3) {
    const uint32_t x = bits(cell.x), y = bits(cell.y), z = bits(cell.z);
    return {unit(hash(x, y, z)), unit(hash(x, y, z, bits(1.0f))), unit(hash(x, y, z, bits(2.0f)))};
  } else {
    const uint32_t x = bits(cell.x), y = bits(cell.y), z = bits(cell.z), w = bits(cell.w);
    return {unit(hash(x, y, z, w)), unit(hash(w, x, y, z)), unit(hash(z, w, x, y)),
            unit(hash(y, z, w, x))};
  }
}

template <int N>
Vec3 cell_color(const Point<N>& cell, bool integer_hash) {
  if constexpr (N == 2) {
    if (integer_hash) return pcg<3>(glm::ivec3(integer_cell<2>(cell), 0));
  } else if constexpr (N > 2) {
    if (integer_hash) return Vec3(pcg<N>(integer_cell<N>(cell)));
  }
  if constexpr (N == 1) {
    const uint32_t x = bits(cell.x);
    return {unit(hash(x)), unit(hash(x, bits(1.0f))), unit(hash(x, bits(2.0f)))};
  } else if constexpr (N == 2) {
    const uint32_t x = bits(cell.x), y = bits(cell.y);
    return {unit(hash(x, y)), unit(hash(x, y, bits(1.0f))), unit(hash(x, y, bits(2.0f)))};
  } else if constexpr (N == 3) {
    return cell_point<3>(cell, false);
  } else {
    const uint32_t x = bits(cell.x), y = bits(cell.y), z = bits(cell.z), w = bits(cell.w);
    return {unit(hash(x, y, z, w)), unit(hash(z, x, w, y)), unit(hash(w, z, y, x))};
  }
}

template <int N>
glm::vec4 as_position(const Point<N>& p) {
  if constexpr (N == 1) {
    return {0.0f, 0.0f, 0.0f, p.x};
  } else if constexpr (N == 2) {
    return {p.x, p.y, 0.0f, 0.0f};
  } else if constexpr (N == 3) {
    return {p, 0.0f};
  } else {
    return p;
  }
}

template <int N>
float euclidean(const Point<N>& a, const Point<N>& b) {
  return glm::length(a - b);
}

template <int N>
float metric_distance(const Point<N>& a, const Point<N>& b, const VoronoiSettings& s) {
  if constexpr (N == 1) {
    return std::fabs(b.x - a.x);  // 1D: one metric
  } else {
    const Point<N> d = glm::abs(a - b);
    float sum = 0.0f, most = 0.0f;
    switch (s.metric) {
      case VoronoiMetric::kEuclidean:
        return euclidean<N>(a, b);
      case VoronoiMetric::kManhattan:
        for (int k = 0; k < N; ++k) sum += d[k];
        return sum;
      case VoronoiMetric::kChebychev:
        for (int k = 0; k < N; ++k) most = std::fmax(most, d[k]);
        return most;
      case VoronoiMetric::kMinkowski:
        for (int k = 0; k < N; ++k) sum += std::pow(d[k], s.exponent);
        return std::pow(sum, 1.0f / s.exponent);
    }
    return 0.0f;
  }
}

// The cells around a cell, -radius..radius on each axis, x varying fastest (the order
// decides ties and the smooth blend, as in Cycles' nested loops).
template <int N>
Point<N> neighbour(int index, int radius) {
  const int width = 2 * radius + 1;
  Point<N> offset;
  for (int k = 0; k < N; ++k, index /= width)
    offset[k] = static_cast<float>(index % width - radius);
  return offset;
}
constexpr int cells(int n, int radius) {
  int count = 1;
  for (int k = 0; k < n; ++k) count *= 2 * radius + 1;
  return count;
}

template <int N>
VoronoiResult voronoi_f1(const VoronoiSettings& s, const Point<N>& coord) {
  const Point<N> cell = glm::floor(coord);
  const Point<N> local = coord - cell;
  float best = FLT_MAX;
  Point<N> offset(0.0f), position(0.0f);
  for (int i = 0; i < cells(N, 1); ++i) {
    const Point<N> o = neighbour<N>(i, 1);
    const Point<N> point = o + cell_point<N>(cell + o, s.integer_hash) * s.randomness;
    const float d = metric_distance<N>(point, local, s);
    if (d < best) best = d, offset = o, position = point;
  }
  return {best, cell_color<N>(cell + offset, s.integer_hash), as_position<N>(position + cell)};
}

template <int N>
VoronoiResult voronoi_smooth_f1(const VoronoiSettings& s, const Point<N>& coord) {
  const Point<N> cell = glm::floor(coord);
  const Point<N> local = coord - cell;
  float distance = 0.0f, h = -1.0f;
  Vec3 color(0.0f);
  Point<N> position(0.0f);
  for (int i = 0; i < cells(N, 2); ++i) {
    const Point<N> o = neighbour<N>(i, 2);
    const Point<N> point = o + cell_point<N>(cell + o, s.integer_hash) * s.randomness;
    const float d = metric_distance<N>(point, local, s);
    h = h == -1.0f ? 1.0f : smoothstep(0.5f + 0.5f * (distance - d) / s.smoothness);
    float correction = s.smoothness * h * (1.0f - h);
    distance = lerp(distance, d, h) - correction;
    correction /= 1.0f + 3.0f * s.smoothness;
    color = color + h * (cell_color<N>(cell + o, s.integer_hash) - color) - correction;
    position = position + h * (point - position) - correction;
  }
  return {distance, color, as_position<N>(cell + position)};
}

template <int N>
VoronoiResult voronoi_f2(const VoronoiSettings& s, const Point<N>& coord) {
  const Point<N> cell = glm::floor(coord);
  const Point<N> local = coord - cell;
  float d1 = FLT_MAX, d2 = FLT_MAX;
  Point<N> offset1(0.0f), position1(0.0f), offset2(0.0f), position2(0.0f);
  for (int i = 0; i < cells(N, 1); ++i) {
    const Point<N> o = neighbour<N>(i, 1);
    const Point<N> point = o + cell_point<N>(cell + o, s.integer_hash) * s.randomness;
    const float d = metric_distance<N>(point, local, s);
    if (d < d1) {
      d2 = d1, offset2 = offset1, position2 = position1;
      d1 = d, offset1 = o, position1 = point;
    } else if (d < d2) {
      d2 = d, offset2 = o, position2 = point;
    }
  }
  return {d2, cell_color<N>(cell + offset2, s.integer_hash), as_position<N>(position2 + cell)};
}

template <int N>
float voronoi_distance_to_edge(const VoronoiSettings& s, const Point<N>& coord) {
  const Point<N> cell = glm::floor(coord);
  const Point<N> local = coord - cell;
  if constexpr (N == 1) {
    const float mid = cell_point<1>(cell, false).x * s.randomness;
    const float left = -1.0f + cell_point<1>(cell - 1.0f, false).x * s.randomness;
    const float right = 1.0f + cell_point<1>(cell + 1.0f, false).x * s.randomness;
    return std::fmin(std::fabs((mid + left) / 2.0f - local.x),
                     std::fabs((mid + right) / 2.0f - local.x));
  } else {
    Point<N> closest(0.0f);
    float best = FLT_MAX;
    for (int i = 0; i < cells(N, 1); ++i) {
      const Point<N> o = neighbour<N>(i, 1);
      const Point<N> to_point = o + cell_point<N>(cell + o, s.integer_hash) * s.randomness - local;
      const float d = glm::dot(to_point, to_point);
      if (d < best) best = d, closest = to_point;
    }
    best = FLT_MAX;
    for (int i = 0; i < cells(N, 1); ++i) {
      const Point<N> o = neighbour<N>(i, 1);
      const Point<N> to_point = o + cell_point<N>(cell + o, s.integer_hash) * s.randomness - local;
      const Point<N> across = to_point - closest;
      if (glm::dot(across, across) > 0.0001f) {
        best = std::fmin(best, glm::dot((closest + to_point) / 2.0f, glm::normalize(across)));
      }
    }
    return best;
  }
}

template <int N>
float voronoi_n_sphere_radius(const VoronoiSettings& s, const Point<N>& coord) {
  const Point<N> cell = glm::floor(coord);
  const Point<N> local = coord - cell;
  Point<N> closest(0.0f), closest_offset(0.0f);
  float best = FLT_MAX;
  for (int i = 0; i < cells(N, 1); ++i) {
    const Point<N> o = neighbour<N>(i, 1);
    const Point<N> point = o + cell_point<N>(cell + o, s.integer_hash) * s.randomness;
    const float d = euclidean<N>(point, local);
    if (d < best) best = d, closest = point, closest_offset = o;
  }
  best = FLT_MAX;
  Point<N> nearest(0.0f);  // the feature point nearest the closest one
  for (int i = 0; i < cells(N, 1); ++i) {
    if (i == cells(N, 1) / 2) continue;  // the closest point's own cell
    const Point<N> o = neighbour<N>(i, 1) + closest_offset;
    const Point<N> point = o + cell_point<N>(cell + o, s.integer_hash) * s.randomness;
    const float d = euclidean<N>(closest, point);
    if (d < best) best = d, nearest = point;
  }
  return euclidean<N>(nearest, closest) / 2.0f;
}

// Octaves of F1, F2 or Smooth F1 summed as fBM noise's, positions blended.
template <int N>
VoronoiResult fractal_voronoi(const VoronoiSettings& s, const Point<N>& coord, float max_distance) {
  float amplitude = 1.0f, max_amplitude = 0.0f, scale = 1.0f;
  VoronoiResult out;
  const bool single = s.detail == 0.0f || s.roughness == 0.0f;
  for (int i = 0; static_cast<float>(i) <= std::ceil(s.detail); ++i) {
    const VoronoiResult octave = s.feature == VoronoiFeature::kF2 ? voronoi_f2<N>(s, coord * scale)
                                 : s.feature == VoronoiFeature::kSmoothF1 && s.smoothness != 0.0f
                                     ? voronoi_smooth_f1<N>(s, coord * scale)
                                     : voronoi_f1<N>(s, coord * scale);
    if (single) {
      max_amplitude = 1.0f;
      out = octave;
      break;
    }
    if (static_cast<float>(i) <= s.detail) {
      max_amplitude += amplitude;
      out.distance += octave.distance * amplitude;
      out.color += octave.color * amplitude;
      out.position = out.position + amplitude * (octave.position / scale - out.position);
      scale *= s.lacunarity;
      amplitude *= s.roughness;
    } else {
      const float rmd = s.detail - std::floor(s.detail);
      if (rmd != 0.0f) {
        max_amplitude = lerp(max_amplitude, max_amplitude + amplitude, rmd);
        out.distance = lerp(out.distance, out.distance + octave.distance * amplitude, rmd);
        out.color = out.color + rmd * (out.color + octave.color * amplitude - out.color);
        const glm::vec4 blended =
            out.position + amplitude * (octave.position / scale - out.position);
        out.position = out.position + rmd * (blended - out.position);
      }
    }
  }
  if (s.normalize) {
    out.distance /= max_amplitude * max_distance;
    out.color /= max_amplitude;
  }
  out.position = s.scale != 0.0f ? out.position / s.scale : glm::vec4(0.0f);
  return out;
}

template <int N>
float fractal_distance_to_edge(const VoronoiSettings& s, const Point<N>& coord,
                               float max_distance) {
  float amplitude = 1.0f, max_amplitude = max_distance, scale = 1.0f, distance = 8.0f;
  const bool single = s.detail == 0.0f || s.roughness == 0.0f;
  for (int i = 0; static_cast<float>(i) <= std::ceil(s.detail); ++i) {
    const float octave = voronoi_distance_to_edge<N>(s, coord * scale);
    if (single) {
      distance = octave;
      break;
    }
    if (static_cast<float>(i) <= s.detail) {
      max_amplitude = lerp(max_amplitude, max_distance / scale, amplitude);
      distance = lerp(distance, std::fmin(distance, octave / scale), amplitude);
      scale *= s.lacunarity;
      amplitude *= s.roughness;
    } else {
      const float rmd = s.detail - std::floor(s.detail);
      if (rmd != 0.0f) {
        const float lerp_amplitude = lerp(max_amplitude, max_distance / scale, amplitude);
        max_amplitude = lerp(max_amplitude, lerp_amplitude, rmd);
        const float lerp_distance = lerp(distance, std::fmin(distance, octave / scale), amplitude);
        distance = lerp(distance, std::fmin(distance, lerp_distance), rmd);
      }
    }
  }
  return s.normalize ? distance / max_amplitude : distance;
}

template <int N>
VoronoiResult voronoi(const VoronoiSettings& s, const Point<N>& coord) {
  const float spread = 0.5f + 0.5f * s.randomness;
  VoronoiResult out;
  if (s.feature == VoronoiFeature::kDistanceToEdge) {
    out.distance = fractal_distance_to_edge<N>(s, coord, spread);
  } else if (s.feature == VoronoiFeature::kNSphereRadius) {
    out.distance = voronoi_n_sphere_radius<N>(s, coord);
  } else {
    // The largest distance to the nearest point (twice that for F2), for Normalize.
    const float reach = metric_distance<N>(Point<N>(0.0f), Point<N>(spread), s);
    out = fractal_voronoi<N>(s, coord, reach * (s.feature == VoronoiFeature::kF2 ? 2.0f : 1.0f));
  }
  return out;
}

}  // namespace

VoronoiResult voronoi_texture(const VoronoiSettings& settings, Vec3 p, float w) {
  VoronoiSettings s = settings;
  s.detail = std::clamp(s.detail, 0.0f, 15.0f);
  s.roughness = std::clamp(s.roughness, 0.0f, 1.0f);
  s.randomness = std::clamp(s.randomness, 0.0f, 1.0f);
  s.smoothness = std::clamp(s.smoothness / 2.0f, 0.0f, 0.5f);
  p *= s.scale;
  w *= s.scale;
  switch (s.dimensions) {
    case 1:
      return voronoi<1>(s, Point<1>(w));
    case 2:
      return voronoi<2>(s, glm::vec2(p));
    case 4:
      return voronoi<4>(s, glm::vec4(p, w));
    default:
      return voronoi<3>(s, p);
  }
}

}  // namespace whitted::procedural
