// A Volume object's grids placed in the world (issue 48): what a medium driven by grids
// reads at a point x, and where it can be non-zero. The grids are those the object's
// material reads (addon/export/volume_object.py names them by role), each immutable and
// shared; sample() and world_bounds() keep no state, so any thread may call them.
#pragma once

#include <array>
#include <memory>

#include <glm/mat4x4.hpp>

#include "core/math.h"
#include "scene/volume_grid.h"

namespace whitted {

// What a material reads of a Volume object's grids: Principled Volume's Density, Color
// and Temperature attributes, and the Volume Info node's Flame.
enum class GridRole : int { kDensity = 0, kColor, kTemperature, kFlame };
inline constexpr int kGridRoles = 4;

// The grids' values at a point. A role without a grid reads as Cycles' Principled Volume
// reads an attribute it does not find: density, colour and temperature 1 (the node's own
// inputs unscaled), flame 0 (the Volume Info node's output).
struct VolumeSample {
  float density = 1.0f;
  Color color{1.0f};
  float temperature = 1.0f;
  float flame = 0.0f;
};

class VolumeObject {
 public:
  using Grids = std::array<std::shared_ptr<const VolumeGrid>, kGridRoles>;  // by GridRole
  // `to_world`: the object's transform (object space -> world), affine. Throws
  // std::invalid_argument for a transform without inverse, or a colour grid of one
  // channel or a scalar role's grid of three.
  VolumeObject(const glm::mat4& to_world, Grids grids);

  // The grids at world point x (each trilinear in its own index space, scene/volume_grid.h).
  VolumeSample sample(const Vec3& x) const;
  // The world-space box bounding every grid's active voxels: outside it density is the
  // grids' background (0 for every grid Blender writes). Empty without active voxels.
  Box3 world_bounds() const;
  const glm::mat4& to_world() const { return to_world_; }
  const std::shared_ptr<const VolumeGrid>& grid(GridRole role) const {
    return grids_[static_cast<int>(role)];
  }
  size_t bytes() const;

 private:
  glm::mat4 to_world_;
  Grids grids_;
  std::array<glm::mat4, kGridRoles> world_to_index_;  // by role (identity where no grid)
};

}  // namespace whitted
