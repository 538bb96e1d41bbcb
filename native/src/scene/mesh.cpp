#include "scene/mesh.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace whitted {

Mesh make_mesh(const float* positions, size_t vertex_count, const uint32_t* triangles,
               size_t triangle_count, const float* normals, const int32_t* material_slots,
               const float* uvs) {
  if (vertex_count > UINT32_MAX) throw std::invalid_argument("mesh has too many vertices");
  Mesh mesh;
  mesh.positions.assign(positions, positions + 3 * vertex_count);
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    if (!std::isfinite(mesh.positions[i])) {
      throw std::invalid_argument("vertex " + std::to_string(i / 3) +
                                  " has a coordinate that is NaN or infinite");
    }
  }
  mesh.positions.push_back(0.0f);  // Embree reads 16 bytes at the last vertex
  mesh.triangles.assign(triangles, triangles + 3 * triangle_count);
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    if (mesh.triangles[i] >= vertex_count) {
      throw std::invalid_argument("triangle " + std::to_string(i / 3) + " refers to vertex " +
                                  std::to_string(mesh.triangles[i]) + " of " +
                                  std::to_string(vertex_count));
    }
  }
  if (normals != nullptr) {
    mesh.normals.assign(normals, normals + 9 * triangle_count);
    for (float& n : mesh.normals) {
      if (!std::isfinite(n)) n = 0.0f;  // a zero normal falls back to the face normal
    }
  }
  if (material_slots != nullptr) {
    mesh.material_slots.assign(material_slots, material_slots + triangle_count);
    for (int32_t& s : mesh.material_slots) s = std::max(s, 0);
  }
  if (uvs != nullptr) {
    mesh.uvs.assign(uvs, uvs + 6 * triangle_count);
    for (float& uv : mesh.uvs) {
      if (!std::isfinite(uv)) uv = 0.0f;
    }
  }
  // The bounds of the vertices, as Blender's automatic texture space: a flat axis gets
  // size 1 and a tiny one 1e-5, so generated coordinates stay finite.
  if (vertex_count > 0) {
    Vec3 lo = mesh.vertex(0);
    Vec3 hi = lo;
    for (uint32_t i = 1; i < vertex_count; ++i) {
      lo = glm::min(lo, mesh.vertex(i));
      hi = glm::max(hi, mesh.vertex(i));
    }
    mesh.texspace_location = 0.5f * (lo + hi);
    for (int k = 0; k < 3; ++k) {
      const float half = 0.5f * (hi[k] - lo[k]);
      mesh.texspace_size[k] = half == 0.0f ? 1.0f : std::max(half, 1e-5f);
    }
  }
  return mesh;
}

}  // namespace whitted
