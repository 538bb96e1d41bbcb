#include "scene/volume_object.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <unordered_map>
#include <utility>
#include <vector>

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
  if (!(render.clipping >= 0.0f) || !std::isfinite(render.clipping)) {
    throw std::invalid_argument("a Volume's clipping must be 0 or more, and finite");
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
  if (grid(GridRole::kTemperature)) {
    const int r = static_cast<int>(GridRole::kTemperature);
    s.temperature_cell = grids_[r]->cell(transform_point(world_to_index_[r], x));
    s.temperature = s.temperature_cell.interpolated();
  }
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

namespace {

// A block's coordinates packed into one key (21 bits an axis, offset to be unsigned):
// blocks of 8 voxels reach 8 million voxels either side of the origin.
uint64_t block_key(const glm::ivec3& b) {
  constexpr int64_t kOffset = int64_t(1) << 20;
  const auto axis = [](int v) {
    return uint64_t(int64_t(v) + kOffset) & ((uint64_t(1) << 21) - 1);
  };
  return (axis(b.x) << 42) | (axis(b.y) << 21) | axis(b.z);
}

}  // namespace

Box3 VolumeObject::interpolated_bounds() const {
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
  return box;
}

Mesh VolumeObject::bound_mesh() const {
  // The blocks of the first grid's lattice the mesh encloses, by key.
  const VolumeGrid* lattice = nullptr;
  std::unordered_map<uint64_t, glm::ivec3> blocks;
  const auto add = [&](const glm::ivec3& b) { blocks.emplace(block_key(b), b); };
  for (const std::shared_ptr<const VolumeGrid>& grid : grids_) {
    if (!grid || grid->index_bounds().empty()) continue;
    if (lattice == nullptr) lattice = grid.get();
    const bool same = grid->index_to_object() == lattice->index_to_object();
    // Into the lattice's block coordinates: a grid of another transform adds every block
    // its occupied blocks' boxes overlap (Cycles resamples the topology instead).
    const glm::mat4 to_lattice = lattice->object_to_index() * grid->index_to_object();
    for (const VolumeGrid::OccupiedBlock& o : grid->occupied_blocks(render_.clipping)) {
      if (same) {
        add(o.block);
        // The one voxel of padding: a counted voxel on a face reaches the next block.
        for (int axis = 0; axis < 3; ++axis) {
          glm::ivec3 step(0);
          step[axis] = 1;
          if (o.faces & (1u << (2 * axis))) add(o.block - step);
          if (o.faces & (1u << (2 * axis + 1))) add(o.block + step);
        }
        continue;
      }
      const Box3 voxels{Vec3(o.block * VolumeGrid::kBlockSide) - 1.0f,
                        Vec3((o.block + 1) * VolumeGrid::kBlockSide) + 1.0f};
      const Box3 there = placed(voxels, to_lattice);
      const glm::ivec3 lo(glm::floor(there.lower / float(VolumeGrid::kBlockSide)));
      const glm::ivec3 hi(glm::floor(there.upper / float(VolumeGrid::kBlockSide)));
      for (int x = lo.x; x <= hi.x; ++x)
        for (int y = lo.y; y <= hi.y; ++y)
          for (int z = lo.z; z <= hi.z; ++z) add({x, y, z});
    }
  }
  if (blocks.empty()) return {};

  // A quad on every face between an enclosed block and one that is not, its corners
  // shared by key (corner c of block b is block corner b + c, in units of a block).
  std::vector<float> positions;
  std::vector<uint32_t> triangles;
  std::unordered_map<uint64_t, uint32_t> corners;
  const glm::mat4& to_object = lattice->index_to_object();
  const bool mirrored = glm::determinant(to_object) < 0.0f;
  const auto corner = [&](const glm::ivec3& c) {
    const auto [it, fresh] = corners.emplace(block_key(c), uint32_t(positions.size() / 3));
    if (fresh) {
      const Vec3 p = transform_point(to_object, Vec3(c * VolumeGrid::kBlockSide));
      positions.insert(positions.end(), {p.x, p.y, p.z});
    }
    return it->second;
  };
  for (const auto& [key, b] : blocks) {
    for (int axis = 0; axis < 3; ++axis) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (int side = 0; side < 2; ++side) {
        glm::ivec3 next = b;
        next[axis] += side ? 1 : -1;
        if (blocks.count(block_key(next))) continue;
        glm::ivec3 c[4];
        for (int k = 0; k < 4; ++k) {
          c[k] = b;
          c[k][axis] += side;
          c[k][u] += (k == 1 || k == 2);
          c[k][v] += (k >= 2);
        }
        // (0,0), (1,0), (1,1), (0,1) in (u, v) turns about +axis: outward on the upper
        // side; reversed on the lower, and where the grid's transform mirrors.
        uint32_t q[4] = {corner(c[0]), corner(c[1]), corner(c[2]), corner(c[3])};
        if ((side == 0) != mirrored) std::swap(q[1], q[3]);
        triangles.insert(triangles.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
      }
    }
  }
  Mesh mesh = make_mesh(positions.data(), positions.size() / 3, triangles.data(),
                        triangles.size() / 3, nullptr, nullptr);
  // Generated coordinates span the grids' reach, not the blocks'.
  const Box3 reach = interpolated_bounds();
  fit_texspace(reach.lower, reach.upper, &mesh);
  return mesh;
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
