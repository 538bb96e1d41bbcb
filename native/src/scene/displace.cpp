#include "scene/displace.h"

#include <array>
#include <cmath>
#include <stdexcept>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

namespace whitted {
namespace {

Vec3 at3(const std::vector<float>& a, size_t i) {
  return {a[3 * i], a[3 * i + 1], a[3 * i + 2]};
}

Vec3 safe_normalize(const Vec3& v) {
  const float length = glm::length(v);
  return length > 0.0f && std::isfinite(length) ? v / length : Vec3(0.0f);
}

// The unit normal of triangle t as it winds (0 for a degenerate one).
Vec3 face_normal(const Mesh& mesh, size_t t) {
  const uint32_t* tri = &mesh.triangles[3 * t];
  const Vec3 p0 = mesh.vertex(tri[0]);
  return safe_normalize(glm::cross(mesh.vertex(tri[1]) - p0, mesh.vertex(tri[2]) - p0));
}

// Blender's vertex normals where the mesh has none of its own (flat or corner normals):
// the face normals around each vertex weighted by the corner's angle, normalised; over
// triangles, which for planar polygons is Blender's sum over polygons.
std::vector<Vec3> angle_weighted_normals(const Mesh& mesh) {
  std::vector<Vec3> sum(mesh.vertex_count(), Vec3(0.0f));
  for (size_t t = 0; t < mesh.triangle_count(); ++t) {
    const uint32_t* tri = &mesh.triangles[3 * t];
    const Vec3 n = face_normal(mesh, t);
    for (int j = 0; j < 3; ++j) {
      const Vec3 p = mesh.vertex(tri[j]);
      const Vec3 a = safe_normalize(mesh.vertex(tri[(j + 1) % 3]) - p);
      const Vec3 b = safe_normalize(mesh.vertex(tri[(j + 2) % 3]) - p);
      sum[tri[j]] += std::acos(std::clamp(glm::dot(a, b), -1.0f, 1.0f)) * n;
    }
  }
  for (Vec3& n : sum) n = safe_normalize(n);
  return sum;
}

// The normalised sum of the unit normals of the triangles `use` marks, at each of their
// vertices (Cycles' vertex normals of displaced faces); 0 at the others.
std::vector<Vec3> face_sum_normals(const Mesh& mesh, const std::vector<bool>& use) {
  std::vector<Vec3> sum(mesh.vertex_count(), Vec3(0.0f));
  for (size_t t = 0; t < mesh.triangle_count(); ++t) {
    if (!use[t]) continue;
    const Vec3 n = face_normal(mesh, t);
    for (int j = 0; j < 3; ++j) sum[mesh.triangles[3 * t + j]] += n;
  }
  for (Vec3& n : sum) n = safe_normalize(n);
  return sum;
}

// What the program reads at corner `corner` of triangle `t`, the vertex's shading point:
// the geometry's inputs; the camera, the ray, the object's info and attributes and the
// grids read 0, as nothing traces or renders there.
struct VertexPoint {
  const Mesh& mesh;
  size_t t;
  int corner;
  Vec3 local;   // the vertex, object space
  Vec3 normal;  // its shading normal, world, unit
  const glm::mat4& to_world;

  glm::vec4 corner_layer(const std::vector<float>& layer, size_t width) const {
    const float* v = &layer[(3 * t + static_cast<size_t>(corner)) * width];
    glm::vec4 out(0.0f);
    for (size_t k = 0; k < width; ++k) out[static_cast<int>(k)] = v[k];
    return out;
  }
  glm::vec4 layer(const std::vector<std::vector<float>>& layers, size_t k, size_t width) const {
    return k < layers.size() ? corner_layer(layers[k], width) : glm::vec4(0.0f);
  }
  glm::vec4 input(uint32_t mode) const {
    const auto vec = [](const Vec3& v) { return glm::vec4(v, 0.0f); };
    const glm::mat3 linear(to_world);
    if (mode >= kInputTangent && mode < kInputObjectNormal) {
      return layer(mesh.tangents, mode - kInputTangent, 4);
    }
    if (mode >= kInputAttribute && mode < kInputPublicEnd) {
      return layer(mesh.attributes, mode - kInputAttribute, 4);
    }
    if (mode >= kInputUvSet && mode < kInputAttribute) {
      if (mesh.uv_sets.empty() && mode == kInputUvSet && !mesh.uvs.empty()) {
        return corner_layer(mesh.uvs, 2);
      }
      return layer(mesh.uv_sets, mode - kInputUvSet, 2);
    }
    switch (mode) {
      case kInputPosition:
        return vec(Vec3(to_world * glm::vec4(local, 1.0f)));
      case kInputNormal:
      case kInputIncoming:
        return vec(normal);
      case kInputTrueNormal: {
        const glm::mat3 normal_to_world = glm::transpose(glm::inverse(linear));
        return vec(safe_normalize(normal_to_world * face_normal(mesh, t)));
      }
      case kInputGenerated:
        return vec(mesh.generated(local));
      case kInputObject:
        return vec(local);
      case kInputReflection:
        return vec(normal);  // the mirror of the incoming direction, which is the normal
      case kInputObjectSpaceNormal:
        return vec(safe_normalize(glm::transpose(linear) * normal));
      case kInputObjectNormalScale:
        return glm::vec4(glm::length(glm::transpose(linear) * normal));
      case kInputObjectNormal:
        return vec(glm::transpose(linear) * normal);
      case kInputTriangleVertex:
      case kInputTriangleVertex + 1:
      case kInputTriangleVertex + 2: {
        const uint32_t v = mesh.triangles[3 * t + (mode - kInputTriangleVertex)];
        return vec(Vec3(to_world * glm::vec4(mesh.vertex(v), 1.0f)));
      }
      default:
        return glm::vec4(0.0f);
    }
  }
};

}  // namespace

size_t displace(Mesh* mesh, std::span<const SlotDisplacement* const> slots,
                const glm::mat4& to_world) {
  const size_t triangles = mesh->triangle_count();
  const auto of = [&](size_t t) -> const SlotDisplacement* {
    const size_t slot = mesh->slot(static_cast<uint32_t>(t));
    return slot < slots.size() ? slots[slot] : nullptr;
  };
  std::vector<bool> moves(triangles), renormal(triangles);
  bool any = false;
  for (size_t t = 0; t < triangles; ++t) {
    const SlotDisplacement* d = of(t);
    if (d != nullptr && d->program && d->output >= d->program->register_count()) {
      throw std::invalid_argument("displacement output register " + std::to_string(d->output) +
                                  " is past the program's registers");
    }
    moves[t] = d != nullptr && d->program != nullptr;
    renormal[t] = moves[t] && d->renormal;
    any = any || moves[t];
  }
  if (!any) return 0;
  const glm::mat3 linear(to_world);
  const glm::mat3 normal_to_world = glm::transpose(glm::inverse(linear));
  const glm::mat3 to_object = glm::inverse(linear);
  const std::vector<Vec3> own_normals =
      mesh->vertex_normals.empty() ? angle_weighted_normals(*mesh) : std::vector<Vec3>{};
  const bool corners = !mesh->normals.empty();
  // Corner normals: each vertex's normal before the move, from every face (Cycles 4.5+).
  const std::vector<bool> all(triangles, true);
  const std::vector<Vec3> before = corners ? face_sum_normals(*mesh, all) : std::vector<Vec3>{};

  // Every offset first (all read the mesh as it was), then the moves.
  std::vector<Vec3> offsets(mesh->vertex_count(), Vec3(0.0f));
  std::vector<bool> done(mesh->vertex_count(), false);
  std::vector<glm::vec4> inputs;
  std::array<glm::vec4, Program::kMaxRegisters + 1> registers;
  size_t moved = 0;
  for (size_t t = 0; t < triangles; ++t) {
    if (!moves[t]) continue;
    const SlotDisplacement& d = *of(t);
    for (int j = 0; j < 3; ++j) {
      const uint32_t v = mesh->triangles[3 * t + static_cast<size_t>(j)];
      if (done[v]) continue;
      done[v] = true;
      ++moved;
      const Vec3 object_normal =
          mesh->vertex_normals.empty() ? own_normals[v] : at3(mesh->vertex_normals, v);
      const VertexPoint point{
          *mesh, t, j, mesh->vertex(v), safe_normalize(normal_to_world * object_normal), to_world};
      inputs.clear();
      for (uint32_t mode : d.program->inputs()) {
        inputs.push_back(point.input(mode & ~(kInputBumpX | kInputBumpY)));
      }
      ProgramHit hit;
      hit.inputs = inputs.data();
      hit.incoming = point.normal;
      hit.normal = point.normal;
      hit.to_world = linear;
      hit.normal_to_world = normal_to_world;
      hit.images = d.images.data();
      d.program->run(hit, registers.data());
      const Vec3 offset = to_object * Vec3(registers[d.output]);
      offsets[v] = is_finite(offset) ? offset : Vec3(0.0f);
    }
  }
  const size_t count = mesh->vertex_count();
  if (mesh->undisplaced.empty()) {
    mesh->undisplaced.assign(mesh->positions.begin(), mesh->positions.begin() + 3 * count);
  }
  for (size_t v = 0; v < count; ++v) {
    for (int k = 0; k < 3; ++k) mesh->positions[3 * v + k] += offsets[v][k];
    for (std::vector<float>& step : mesh->motion_positions) {
      for (int k = 0; k < 3; ++k) step[3 * v + k] += offsets[v][k];
    }
  }
  if (corners) {
    const std::vector<Vec3> after = face_sum_normals(*mesh, all);
    for (size_t t = 0; t < triangles; ++t) {
      float* n = &mesh->normals[9 * t];
      const bool flat = std::equal(n, n + 3, n + 3) && std::equal(n, n + 3, n + 6);
      const Vec3 face = face_normal(*mesh, t);
      for (int j = 0; j < 3; ++j) {
        const uint32_t v = mesh->triangles[3 * t + static_cast<size_t>(j)];
        const Vec3 bent =
            flat
                ? face
                : safe_normalize(Vec3(n[3 * j], n[3 * j + 1], n[3 * j + 2]) + after[v] - before[v]);
        for (int k = 0; k < 3; ++k) n[3 * j + k] = bent[k];
      }
    }
  } else if (!mesh->vertex_normals.empty()) {
    const std::vector<Vec3> after = face_sum_normals(*mesh, renormal);
    std::vector<bool> touched(count, false);
    for (size_t t = 0; t < triangles; ++t) {
      if (!renormal[t]) continue;
      for (int j = 0; j < 3; ++j) touched[mesh->triangles[3 * t + static_cast<size_t>(j)]] = true;
    }
    for (size_t v = 0; v < count; ++v) {
      if (!touched[v]) continue;
      for (int k = 0; k < 3; ++k) mesh->vertex_normals[3 * v + k] = after[v][k];
    }
  }
  return moved;
}

}  // namespace whitted
