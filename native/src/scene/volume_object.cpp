#include "scene/volume_object.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/scene.h"

namespace whitted {

VolumeObject::VolumeObject(const glm::mat4& to_world, Grids grids, VolumeRender render)
    : to_world_(to_world), grids_(std::move(grids)), render_(render) {
  if (!is_finite(to_world) || glm::determinant(to_world) == 0.0f) {
    throw std::invalid_argument("a Volume object's transform must be finite and invertible");
  }
  if (!(render.step_size >= 0.0f) || !std::isfinite(render.step_size)) {
    throw std::invalid_argument("a Volume's step size must be 0 or more, and finite");
  }
  for (int role = 0; role < kGridRoles; ++role) {
    const std::shared_ptr<const VolumeGrid>& grid = grids_[role];
    world_to_index_[role] = glm::mat4(1.0f);
    if (!grid) continue;
    const int wanted = role == static_cast<int>(GridRole::kColor) ? 3 : 1;
    if (grid->channels() != wanted) {
      throw std::invalid_argument("volume grid '" + grid->name() + "' has " +
                                  std::to_string(grid->channels()) + " channel(s); its role " +
                                  "reads " + std::to_string(wanted));
    }
    // world -> object -> index; a value at the integer point is VolumeGrid's half a voxel on.
    const glm::mat4 shift = glm::translate(glm::mat4(1.0f), Vec3(render.centred ? 0.0f : 0.5f));
    world_to_index_[role] = shift * grid->object_to_index() * glm::inverse(to_world_);
  }
  density_scale_ = compute_density_scale();
  step_ = compute_step();
}

VolumeSample VolumeObject::sample(const Vec3& x) const {
  VolumeSample s;
  const auto at = [&](GridRole role) {
    const int r = static_cast<int>(role);
    return grids_[r]->sample(transform_point(world_to_index_[r], x));
  };
  if (grid(GridRole::kDensity)) s.density = at(GridRole::kDensity).x;
  if (grid(GridRole::kColor)) s.color = at(GridRole::kColor);
  if (grid(GridRole::kTemperature)) s.temperature = at(GridRole::kTemperature).x;
  if (grid(GridRole::kFlame)) s.flame = at(GridRole::kFlame).x;
  return s;
}

Box3 VolumeObject::world_bounds() const {
  Box3 out;
  for (const std::shared_ptr<const VolumeGrid>& grid : grids_) {
    if (grid) out.extend(placed(grid->index_bounds(), to_world_ * grid->index_to_object()));
  }
  return out;
}

Mesh VolumeObject::bound_mesh() const {
  Box3 box;
  for (const std::shared_ptr<const VolumeGrid>& grid : grids_) {
    if (!grid) continue;
    Box3 index = grid->index_bounds();
    if (index.empty()) continue;
    // A voxel's value reaches half a voxel past its cube, all moved back half a voxel
    // where values stand at the integer points.
    const float shift = render_.centred ? 0.0f : -0.5f;
    index.lower += shift - 0.5f;
    index.upper += shift + 0.5f;
    box.extend(placed(index, grid->index_to_object()));
  }
  if (box.empty()) return {};
  // Vertex k is the box's corner k (Box3::corner); faces wound outward.
  std::array<float, 24> positions{};
  for (int k = 0; k < 8; ++k) {
    const Vec3 p = box.corner(k);
    positions[3 * k + 0] = p.x;
    positions[3 * k + 1] = p.y;
    positions[3 * k + 2] = p.z;
  }
  static constexpr std::array<uint32_t, 36> kTriangles = {
      0, 2, 3, 0, 3, 1,  // -z
      4, 5, 7, 4, 7, 6,  // +z
      0, 1, 5, 0, 5, 4,  // -y
      2, 6, 7, 2, 7, 3,  // +y
      0, 4, 6, 0, 6, 2,  // -x
      1, 3, 7, 1, 7, 5,  // +x
  };
  return make_mesh(positions.data(), 8, kTriangles.data(), 12, nullptr, nullptr);
}

float VolumeObject::compute_density_scale() const {
  if (!render_.object_space) return 1.0f;
  const float length = glm::length(glm::mat3(to_world_) * glm::normalize(Vec3(1.0f)));
  return length > 0.0f ? 1.0f / length : 1.0f;
}

float VolumeObject::compute_step() const {
  // The smallest component of |m * v|: how Cycles carries a step to the world.
  const auto smallest = [](const glm::mat3& m, const Vec3& v) {
    const Vec3 d = glm::abs(m * v);
    return std::min({d.x, d.y, d.z});
  };
  if (render_.step_size > 0.0f) {
    return render_.object_space ? smallest(glm::mat3(to_world_), Vec3(render_.step_size))
                                : render_.step_size;
  }
  float step = kInfinity;
  for (const std::shared_ptr<const VolumeGrid>& grid : grids_) {
    if (!grid || grid->index_bounds().empty()) continue;
    const float voxel = smallest(glm::mat3(to_world_ * grid->index_to_object()), Vec3(1.0f));
    if (voxel > 0.0f) step = std::min(step, voxel);
  }
  return std::isfinite(step) ? step : 0.0f;
}

size_t VolumeObject::bytes() const {
  size_t total = sizeof(*this);
  for (const std::shared_ptr<const VolumeGrid>& grid : grids_) {
    if (grid) total += grid->bytes();
  }
  return total;
}

}  // namespace whitted
