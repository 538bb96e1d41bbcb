#include "scene/mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

namespace whitted {
namespace {

// A copy of `count` floats with NaN and infinities set to 0 (a zero normal stands for
// the face normal; a zero UV is the texture's corner).
std::vector<float> finite_copy(const float* values, size_t count) {
  std::vector<float> out(values, values + count);
  for (float& x : out) {
    if (!std::isfinite(x)) x = 0.0f;
  }
  return out;
}

}  // namespace

size_t slot_count(const Mesh& mesh) {
  const auto primitives = static_cast<uint32_t>(mesh.primitive_count());
  size_t count = 0;
  for (uint32_t p = 0; p < primitives; ++p) count = std::max(count, mesh.slot(p) + 1);
  return count;
}

Box bounding_box(const Mesh& mesh) {
  Box box;
  const auto grow = [&](const Vec3& v, float radius) {
    box.lower = glm::min(box.lower, v - radius);
    box.upper = glm::max(box.upper, v + radius);
  };
  for (size_t i = 0; i < mesh.vertex_count(); ++i)
    grow(mesh.vertex(static_cast<uint32_t>(i)), 0.0f);
  // A key's or a point's sphere (a Catmull-Rom curve stays within its keys' hull).
  const auto spheres = [&](const std::vector<float>& xyzr) {
    for (size_t i = 0; i + 3 < xyzr.size(); i += 4) {
      grow(Vec3(xyzr[i], xyzr[i + 1], xyzr[i + 2]), xyzr[i + 3]);
    }
  };
  spheres(mesh.curves.keys);
  spheres(mesh.points.spheres);
  return box;
}

Sphere bounding_sphere(const Mesh& mesh) {
  const Box box = bounding_box(mesh);
  if (box.empty()) return {};
  return {0.5f * (box.lower + box.upper), 0.5f * glm::length(box.upper - box.lower)};
}

namespace {

// A radius as Embree may take it: finite and not negative.
float usable_radius(float r) {
  return std::isfinite(r) && r > 0.0f ? r : 0.0f;
}

void require_finite_position(const float* xyz, const char* what, size_t index) {
  if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2])) {
    throw std::invalid_argument(std::string(what) + " " + std::to_string(index) +
                                " has a coordinate that is NaN or infinite");
  }
}

}  // namespace

Curves make_curves(const float* keys, size_t key_count, const uint32_t* counts, size_t strand_count,
                   const int32_t* slots, bool linear, bool flat) {
  Curves out;
  out.linear = linear;
  out.flat = flat;
  // Catmull-Rom segments read a key before and after theirs: the ends are doubled.
  const size_t doubled = linear ? 0 : 1;
  size_t first = 0;
  for (size_t c = 0; c < strand_count; ++c) {
    const size_t n = counts[c];
    if (first + n > key_count) {
      throw std::invalid_argument("strand " + std::to_string(c) + " reads past the " +
                                  std::to_string(key_count) + " keys");
    }
    if (n >= 2) {
      // Its keys, the first and the last twice: segment j reads keys j .. j + 3 of these.
      const auto start = static_cast<uint32_t>(out.keys.size() / 4);
      for (size_t k = 0; k < n + 2 * doubled; ++k) {
        const size_t key = first + std::clamp<size_t>(k, doubled, n - 1 + doubled) - doubled;
        const float* xyzr = keys + 4 * key;
        require_finite_position(xyzr, "strand", c);
        out.keys.insert(out.keys.end(), {xyzr[0], xyzr[1], xyzr[2], usable_radius(xyzr[3])});
      }
      for (size_t j = 0; j + 1 < n; ++j) {
        out.segments.push_back(start + static_cast<uint32_t>(j));
        if (slots != nullptr) out.slots.push_back(std::max(slots[c], 0));
      }
    }
    first += n;
  }
  if (out.keys.size() / 4 > UINT32_MAX) throw std::invalid_argument("too many curve keys");
  return out;
}

Points make_points(const float* spheres, size_t count, const int32_t* slots) {
  Points out;
  out.spheres.reserve(4 * count);
  for (size_t i = 0; i < count; ++i) {
    const float* xyzr = spheres + 4 * i;
    require_finite_position(xyzr, "point", i);
    out.spheres.insert(out.spheres.end(), {xyzr[0], xyzr[1], xyzr[2], usable_radius(xyzr[3])});
  }
  if (slots != nullptr) {
    out.slots.assign(slots, slots + count);
    for (int32_t& s : out.slots) s = std::max(s, 0);
  }
  return out;
}

Mesh make_mesh(const float* positions, size_t vertex_count, const uint32_t* triangles,
               size_t triangle_count, const float* normals, const int32_t* material_slots,
               const float* uvs, const float* vertex_normals, const CornerLayers& layers) {
  if (vertex_count > UINT32_MAX) throw std::invalid_argument("mesh has too many vertices");
  if (normals != nullptr && vertex_normals != nullptr) {
    throw std::invalid_argument("a mesh takes corner normals or vertex normals, not both");
  }
  Mesh mesh;
  // Reserved with the padding float Embree reads (16 bytes at the last vertex), so the
  // push_back below does not reallocate (and double) the array.
  mesh.positions.reserve(3 * vertex_count + 1);
  mesh.positions.assign(positions, positions + 3 * vertex_count);
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    if (!std::isfinite(mesh.positions[i])) {
      throw std::invalid_argument("vertex " + std::to_string(i / 3) +
                                  " has a coordinate that is NaN or infinite");
    }
  }
  mesh.positions.push_back(0.0f);
  mesh.triangles.assign(triangles, triangles + 3 * triangle_count);
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    if (mesh.triangles[i] >= vertex_count) {
      throw std::invalid_argument("triangle " + std::to_string(i / 3) + " refers to vertex " +
                                  std::to_string(mesh.triangles[i]) + " of " +
                                  std::to_string(vertex_count));
    }
  }
  if (normals != nullptr) mesh.normals = finite_copy(normals, 9 * triangle_count);
  if (vertex_normals != nullptr)
    mesh.vertex_normals = finite_copy(vertex_normals, 3 * vertex_count);
  if (material_slots != nullptr) {
    mesh.material_slots.assign(material_slots, material_slots + triangle_count);
    for (int32_t& s : mesh.material_slots) s = std::max(s, 0);
  }
  if (layers.tangents.size() > std::max<size_t>(layers.uv_sets.size(), uvs != nullptr ? 1 : 0)) {
    throw std::invalid_argument("a mesh takes at most one tangent set per UV set");
  }
  if (uvs != nullptr) mesh.uvs = finite_copy(uvs, 6 * triangle_count);
  for (const float* uv : layers.uv_sets)
    mesh.uv_sets.push_back(finite_copy(uv, 6 * triangle_count));
  for (const float* a : layers.attributes) {
    mesh.attributes.push_back(finite_copy(a, 12 * triangle_count));
  }
  for (const float* t : layers.tangents)
    mesh.tangents.push_back(finite_copy(t, 12 * triangle_count));
  // The bounds of the vertices, as Blender's automatic texture space.
  if (vertex_count > 0) {
    Vec3 lo = mesh.vertex(0);
    Vec3 hi = lo;
    for (uint32_t i = 1; i < vertex_count; ++i) {
      lo = glm::min(lo, mesh.vertex(i));
      hi = glm::max(hi, mesh.vertex(i));
    }
    fit_texspace(lo, hi, &mesh);
  }
  return mesh;
}

void fit_texspace(const Vec3& lo, const Vec3& hi, Mesh* mesh) {
  mesh->texspace_location = 0.5f * (lo + hi);
  for (int k = 0; k < 3; ++k) {
    const float half = 0.5f * (hi[k] - lo[k]);
    mesh->texspace_size[k] = half == 0.0f ? 1.0f : std::max(half, 1e-5f);
  }
}

std::vector<float> vertex_normals(const float* positions, size_t vertex_count,
                                  const uint32_t* loop_vertices, size_t loop_count,
                                  const uint32_t* loop_starts, const uint32_t* loop_totals,
                                  const float* face_normals, size_t polygon_count) {
  for (size_t l = 0; l < loop_count; ++l) {
    if (loop_vertices[l] >= vertex_count) {
      throw std::invalid_argument("loop " + std::to_string(l) + " refers to vertex " +
                                  std::to_string(loop_vertices[l]) + " of " +
                                  std::to_string(vertex_count));
    }
  }
  for (size_t p = 0; p < polygon_count; ++p) {
    if (size_t{loop_starts[p]} + loop_totals[p] > loop_count) {
      throw std::invalid_argument("polygon " + std::to_string(p) + "'s loops are out of range");
    }
  }
  const auto at = [&](size_t loop) {
    const float* v = &positions[3 * size_t{loop_vertices[loop]}];
    return glm::dvec3(v[0], v[1], v[2]);
  };
  const auto squared = [](const glm::dvec3& a) { return (a.x * a.x + a.y * a.y) + a.z * a.z; };
  // Each corner's share, its face normal times its angle, rounded to a multiple of
  // 2^-kFixedBits and summed as an integer: integer sums do not depend on the order of
  // their terms, float and double sums do in their last bits, and one mesh can come in
  // several face orders (Blender's UV sphere operator gives the same faces in a new order
  // each time). A share is at most pi (unit face normals); one beyond kMaxShare (NaN,
  // infinite) is skipped, so a vertex of fewer than 2^32 corners cannot overflow its sum.
  constexpr int kFixedBits = 28;
  constexpr int64_t kMaxShare = 4;
  static_assert((kMaxShare << kFixedBits) <= (std::numeric_limits<int64_t>::max() >> 32));
  const double scale = std::ldexp(1.0, kFixedBits);
  std::vector<int64_t> sums(3 * vertex_count, 0);
  for (size_t p = 0; p < polygon_count; ++p) {
    const size_t start = loop_starts[p];
    const size_t total = loop_totals[p];
    for (size_t k = 0; k < total; ++k) {
      // The corner's angle between the edges to its two neighbours in the polygon; a
      // zero-length edge gives NaN, counted as a right angle.
      const glm::dvec3 here = at(start + k);
      const glm::dvec3 a = at(start + (k + total - 1) % total) - here;
      const glm::dvec3 b = at(start + (k + 1) % total) - here;
      double cosine =
          ((a.x * b.x + a.y * b.y) + a.z * b.z) / (std::sqrt(squared(a)) * std::sqrt(squared(b)));
      if (std::isnan(cosine)) cosine = 0.0;
      const double angle = std::acos(std::clamp(cosine, -1.0, 1.0));
      const uint32_t v = loop_vertices[start + k];
      for (size_t i = 0; i < 3; ++i) {
        const double share = static_cast<double>(face_normals[3 * p + i]) * angle;
        if (std::fabs(share) <= static_cast<double>(kMaxShare))
          sums[3 * size_t{v} + i] += std::llround(share * scale);
      }
    }
  }
  std::vector<float> normals(3 * vertex_count, 0.0f);
  for (size_t v = 0; v < vertex_count; ++v) {
    const glm::dvec3 sum(static_cast<double>(sums[3 * v]), static_cast<double>(sums[3 * v + 1]),
                         static_cast<double>(sums[3 * v + 2]));
    const double length = std::sqrt(squared(sum));
    if (!(length > 0.0)) continue;  // no face, or zero-area faces only
    for (int i = 0; i < 3; ++i) normals[3 * v + i] = static_cast<float>(sum[i] / length);
  }
  return normals;
}

std::vector<uint8_t> zero_area_triangles(const float* positions, size_t vertex_count,
                                         const uint32_t* triangles, size_t triangle_count) {
  std::vector<uint8_t> zero(triangle_count, 0);
  const auto at = [&](size_t corner) {
    if (triangles[corner] >= vertex_count) {
      throw std::invalid_argument("triangle " + std::to_string(corner / 3) + " refers to vertex " +
                                  std::to_string(triangles[corner]) + " of " +
                                  std::to_string(vertex_count));
    }
    const float* v = &positions[3 * size_t{triangles[corner]}];
    return glm::dvec3(v[0], v[1], v[2]);
  };
  for (size_t t = 0; t < triangle_count; ++t) {
    const glm::dvec3 p0 = at(3 * t);
    const glm::dvec3 a = at(3 * t + 1) - p0;
    const glm::dvec3 b = at(3 * t + 2) - p0;
    // A component a_i b_j - a_j b_i is 0 exactly when its two products are equal.
    zero[t] = a.y * b.z == a.z * b.y && a.z * b.x == a.x * b.z && a.x * b.y == a.y * b.x;
  }
  return zero;
}

}  // namespace whitted
