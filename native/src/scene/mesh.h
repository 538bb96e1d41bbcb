// A triangle mesh in object space, shared by every instance that uses it.
#pragma once

#include <cstdint>
#include <vector>

#include "core/math.h"

namespace whitted {

struct Mesh {
  std::vector<float> positions;         // 3 per vertex, plus one float of padding Embree reads
  std::vector<uint32_t> triangles;      // 3 vertex indices per triangle
  std::vector<float> normals;           // 9 per triangle (corner normals), or empty for flat
  std::vector<int32_t> material_slots;  // 1 per triangle, or empty for slot 0
  std::vector<float> uvs;               // 6 per triangle (corner UVs), or empty
  // Blender's automatic texture space: generated = (p - location + size) / (2 size).
  Vec3 texspace_location{0.0f};
  Vec3 texspace_size{1.0f};

  size_t vertex_count() const { return positions.size() / 3; }
  size_t triangle_count() const { return triangles.size() / 3; }
  Vec3 vertex(uint32_t i) const {
    return {positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]};
  }
};

// Builds a mesh from flat arrays, checking every index and value; throws
// std::invalid_argument naming the first problem.
Mesh make_mesh(const float* positions, size_t vertex_count, const uint32_t* triangles,
               size_t triangle_count, const float* normals, const int32_t* material_slots,
               const float* uvs = nullptr);

}  // namespace whitted
