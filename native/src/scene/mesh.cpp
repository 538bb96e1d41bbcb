#include "scene/mesh.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace whitted {

Mesh make_mesh(const float* positions, size_t vertex_count, const uint32_t* triangles,
               size_t triangle_count, const float* normals, const int32_t* material_slots) {
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
  return mesh;
}

}  // namespace whitted
