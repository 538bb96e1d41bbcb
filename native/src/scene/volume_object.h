// A Volume object's grids placed in the world (issue 48): what a medium driven by grids
// reads at a point x, and where it can be non-zero. The grids are those the object's
// material reads (addon/export/volume_object.py names them by role), each immutable and
// shared; sample() and world_bounds() keep no state, so any thread may call them.
#pragma once

#include <array>
#include <memory>

#include <glm/mat4x4.hpp>

#include "core/math.h"
#include "scene/mesh.h"
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
  // The temperature grid's eight voxels that its interpolation weighs, with where the
  // point lies among them (their weights): the outcomes of a read that picks one voxel by
  // its weight, as Cycles 5.x's Principled Volume reads it (shader/ops.h
  // kInputGridTemperatureVoxel). Without a grid, the temperature alone at weight 1.
  VolumeGrid::Cell temperature_cell{{1.0f}, Vec3(0.0f)};
};

// A Volume's Render settings (Blender's Volume > Render): the space its step size and
// density are in, and the step size, Blender units of that space (0: from the voxels).
struct VolumeRender {
  bool object_space = true;  // Space: Object (Blender's default) or World
  float step_size = 0.0f;
  // Where a voxel's value stands: its cube's centre (VolumeGrid's convention, Cycles
  // before Blender 5.0), or its integer index point (OpenVDB's own, Cycles in 5.0):
  // half a voxel apart (addon/export/volume_object.py says what was measured).
  bool centred = true;
  // Volume > Render > Clipping: voxels below it in magnitude are empty space, which the
  // object's mesh leaves out where whole blocks of them are (bound_mesh).
  float clipping = 0.001f;
};

class VolumeObject {
 public:
  using Grids = std::array<std::shared_ptr<const VolumeGrid>, kGridRoles>;  // by GridRole
  // `to_world`: the object's transform (object space -> world), affine. Throws
  // std::invalid_argument for a transform without inverse, a colour grid of one channel
  // or a scalar role's grid of three, or a step size that is negative or not finite.
  VolumeObject(const glm::mat4& to_world, Grids grids, VolumeRender render = {});

  // The grids at world point x (each trilinear in its own index space, scene/volume_grid.h).
  VolumeSample sample(const Vec3& x) const;
  // The world-space box bounding every grid's active voxels: outside it density is the
  // grids' background (0 for every grid Blender writes). Empty without active voxels.
  Box3 world_bounds() const;
  // The mesh a ray enters and leaves the object's medium through, as Cycles builds a
  // Volume's (scene/volume.cpp, its volume mesh builder): the faces around the blocks of
  // 8^3 voxels (OpenVDB's leaf nodes) that hold a voxel at least Clipping in magnitude in
  // some grid, or are next to one across a face (the voxel of padding linear
  // interpolation reaches). The rest of the grids' box is not marched. Outward faces in
  // object space; its texture space interpolated_bounds(). Empty (no triangles) where no
  // voxel counts.
  Mesh bound_mesh() const;
  // The object-space box bounding every grid's active voxels and the half voxel around
  // them that trilinear interpolation reaches.
  Box3 interpolated_bounds() const;
  // Cycles' object_volume_density: in object space a density is per unit of the object,
  // so a Volume scaled by s is 1/s as dense per world unit (1 / |linear part * (1, 1, 1)
  // normalised|); in world space 1.
  float density_scale() const { return density_scale_; }
  // The march step its grids call for, world units, before the step rates (Cycles'
  // Object::compute_volume_step_size): the Render step size carried to the world (object
  // space: the smallest component of |linear part * (s, s, s)|), or where it is 0 each
  // grid's voxel carried to the world likewise, the smallest; 0 where none gives one.
  float step() const { return step_; }
  const glm::mat4& to_world() const { return to_world_; }
  const std::shared_ptr<const VolumeGrid>& grid(GridRole role) const {
    return grids_[static_cast<int>(role)];
  }
  size_t bytes() const;

 private:
  glm::mat4 to_world_;
  Grids grids_;
  VolumeRender render_;
  float density_scale_;
  float step_;
  float compute_density_scale() const;
  float compute_step() const;
  std::array<glm::mat4, kGridRoles> world_to_index_;  // by role (identity where no grid)
};

}  // namespace whitted
