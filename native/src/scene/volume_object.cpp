#include "scene/volume_object.h"

#include <stdexcept>

#include "scene/scene.h"

namespace whitted {

VolumeObject::VolumeObject(const glm::mat4& to_world, Grids grids)
    : to_world_(to_world), grids_(std::move(grids)) {
  if (!is_finite(to_world) || glm::determinant(to_world) == 0.0f) {
    throw std::invalid_argument("a Volume object's transform must be finite and invertible");
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
    // world -> object -> index.
    world_to_index_[role] = grid->object_to_index() * glm::inverse(to_world_);
  }
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
    if (!grid) continue;
    // The corners of the index-space box carried to the world at once: a rotated grid's
    // box is not widened twice.
    const Box3 index = grid->index_bounds();
    if (index.empty()) continue;
    const glm::mat4 index_to_world = to_world_ * grid->index_to_object();
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3 p((corner & 1) ? index.upper.x : index.lower.x,
                   (corner & 2) ? index.upper.y : index.lower.y,
                   (corner & 4) ? index.upper.z : index.lower.z);
      out.extend(transform_point(index_to_world, p));
    }
  }
  return out;
}

size_t VolumeObject::bytes() const {
  size_t total = sizeof(*this);
  for (const std::shared_ptr<const VolumeGrid>& grid : grids_) {
    if (grid) total += grid->bytes();
  }
  return total;
}

}  // namespace whitted
