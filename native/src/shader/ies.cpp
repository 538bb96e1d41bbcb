#include "shader/ies.h"

#include <algorithm>
#include <cmath>

namespace whitted::ies {
namespace {

// Catmull-Rom through b (x = 0) and c (x = 1), with a and d the neighbours beyond.
float catmull_rom(float a, float b, float c, float d, float x) {
  return 0.5f *
             (((d + 3.0f * (b - c) - a) * x + (2.0f * a - 5.0f * b + 4.0f * c - d)) * x + (c - a)) *
             x +
         b;
}

// A table's parts, read from its header.
struct Table {
  int h_count, v_count;
  const float* h;          // horizontal angles
  const float* v;          // vertical angles
  const float* intensity;  // h_count rows of v_count

  explicit Table(const float* t)
      : h_count(static_cast<int>(t[0])),
        v_count(static_cast<int>(t[1])),
        h(t + 2),
        v(t + 2 + h_count),
        intensity(t + 2 + h_count + v_count) {}

  float at(int row, int column) const {
    return intensity[static_cast<size_t>(row) * v_count + column];
  }
};

// The index i of the interval [angles[i], angles[i + 1]] holding x (x within the range).
int interval(const float* angles, int count, float x) {
  int i = 0;
  while (i + 2 < count && angles[i + 1] < x) ++i;
  return i;
}

}  // namespace

size_t table_size(const float* table, size_t available) {
  if (available < 2) return 0;
  const float hf = table[0], vf = table[1];
  if (!(hf >= 2.0f && vf >= 2.0f) || hf != std::floor(hf) || vf != std::floor(vf) ||
      hf > static_cast<float>(available) || vf > static_cast<float>(available)) {
    return 0;
  }
  const auto h = static_cast<size_t>(hf), v = static_cast<size_t>(vf);
  const size_t size = 2 + h + v + h * v;
  if (size > available) return 0;
  const float* angles = table + 2;
  for (size_t i = 0; i < h + v; ++i) {
    if (!std::isfinite(angles[i])) return 0;
    const bool first_of_run = i == 0 || i == h;
    if (!first_of_run && !(angles[i] > angles[i - 1])) return 0;
  }
  return size;
}

float intensity(const float* table, float h, float v, bool legacy) {
  const Table t(table);
  const float h_low = t.h[0], h_high = t.h[t.h_count - 1];
  const float v_low = t.v[0], v_high = t.v[t.v_count - 1];
  if (legacy ? !(v < v_high) : !(v >= v_low && v < v_high) || !(h >= h_low && h < h_high)) {
    return 0.0f;
  }
  // Where each edge's neighbour wraps (else it is held): see the header.
  const bool wrap_h = legacy || (h_low < 1e-7f && h_high > 2.0f * kPi - 1e-7f);
  const bool wrap_v_low = legacy || v_low < 1e-7f;
  const bool wrap_v_high = !legacy && v_high > kPi - 1e-7f;
  const int hi = interval(t.h, t.h_count, h);
  const int vi = interval(t.v, t.v_count, v);
  const float h_frac = (h - t.h[hi]) / (t.h[hi + 1] - t.h[hi]);
  const float v_frac = (v - t.v[vi]) / (t.v[vi + 1] - t.v[vi]);
  // Along the vertical angles at horizontal row `row`; across the first angle the value
  // at the same h on its other side (the profile taken as symmetric).
  auto vertical = [&](int row) {
    const float b = t.at(row, vi), c = t.at(row, vi + 1);
    float a = legacy ? 0.0f : b;  // past the first angle, unwrapped: held (4.x+)
    if (vi > 0) {
      a = t.at(row, vi - 1);
    } else if (wrap_v_low) {
      a = t.at(row, 1);
    }
    float d = c;  // past the last angle: held (3.x at every table, 4.x+ unwrapped)
    if (vi + 2 < t.v_count) {
      d = t.at(row, vi + 2);
    } else if (wrap_v_high) {
      d = t.at(row, t.v_count - 2);
    }
    return catmull_rom(a, b, c, d, v_frac);
  };
  // The last horizontal angle repeats the first (2 pi = 0): wrapped, the neighbour past
  // either end is the one next to the other end. Unwrapped (4.x+), both neighbours are the
  // interval's first row: Cycles holds that one past the last angle too.
  const float b = vertical(hi);
  const float a = hi > 0 ? vertical(hi - 1) : (wrap_h ? vertical(t.h_count - 2) : b);
  const float d = hi + 2 < t.h_count ? vertical(hi + 2) : (wrap_h ? vertical(1) : b);
  return std::max(catmull_rom(a, b, vertical(hi + 1), d, h_frac), 0.0f);
}

float lookup(const float* table, const Vec3& vector, bool legacy) {
  const float length = glm::length(vector);
  if (!(length > 0.0f)) return 0.0f;
  const Vec3 d = vector / length;
  const float v = std::acos(std::clamp(-d.z, -1.0f, 1.0f));
  const float h = std::atan2(d.x, d.y) + kPi;
  return intensity(table, h, v, legacy);
}

}  // namespace whitted::ies
