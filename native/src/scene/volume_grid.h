// One voxel grid of a Volume object (issue 48): a float or vector grid read from an
// OpenVDB file (scene/vdb_file.h), kept in blocks of 8^3 voxels (the size of OpenVDB's
// leaf nodes) that any number of threads sample at once. OpenVDB's own accessors cache
// the nodes they last visited and must be one per thread; a lookup here is two shifts
// and two array reads, with no state (tests/native/volume_grid_test.cpp measures both).
//
// Index space is OpenVDB's: voxel (i, j, k) has integer coordinates. Its value stands
// at the voxel's centre (i + 0.5, j + 0.5, k + 0.5), as Cycles samples a grid (its linear
// interpolation reads the index-space point less 0.5, kernel/device/cpu/image.h), so a
// voxel fills the cube [i, i + 1] and the grid's active voxels the box [min, max + 1].
// OpenVDB's BoxSampler puts the value at the integer point itself: half a voxel apart.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <glm/vec3.hpp>

#include "core/math.h"
#include "core/ray.h"

namespace whitted {

// An axis-aligned box; empty while lower > upper on some axis.
struct Box3 {
  Vec3 lower{kInfinity};
  Vec3 upper{-kInfinity};
  bool empty() const { return lower.x > upper.x || lower.y > upper.y || lower.z > upper.z; }
  void extend(const Vec3& p) {
    lower = glm::min(lower, p);
    upper = glm::max(upper, p);
  }
  void extend(const Box3& b) {
    if (b.empty()) return;
    extend(b.lower);
    extend(b.upper);
  }
  // Corner k: x from bit 0 of k, y from bit 1, z from bit 2.
  Vec3 corner(int k) const {
    return {(k & 1) ? upper.x : lower.x, (k & 2) ? upper.y : lower.y, (k & 4) ? upper.z : lower.z};
  }
};

// The box bounding `box`'s eight corners carried by affine `m` at once (a rotated box is
// not widened twice); empty for an empty box.
Box3 placed(const Box3& box, const glm::mat4& m);

// What a VolumeGrid is made of: the reader fills it (scene/vdb_file.cpp), VolumeGrid's
// constructor checks it.
struct VolumeGridData {
  std::string name;
  int channels = 1;                 // 1: a scalar grid; 3: a vector (colour) grid
  glm::mat4 index_to_object{1.0f};  // the grid's transform, affine
  Vec3 background{0.0f};            // the value outside every block (scalar: in x)
  glm::ivec3 active_lower{0};       // the active voxels' bounding box, inclusive;
  glm::ivec3 active_upper{-1};      // empty when upper < lower
  uint64_t active_voxels = 0;       // how many voxels are active
  glm::ivec3 first_block{0};        // block coordinates (voxel >> 3) of the lattice's
  glm::ivec3 block_counts{0};       // first block, and its blocks a side
  std::vector<uint32_t> blocks;     // by block, ((x * ny) + y) * nz + z: 0 the background,
                                    // n the n-th block of `values`
  std::vector<float> values;        // kBlockVoxels * channels floats a block, voxels as in
                                    // an OpenVDB leaf ((x * 8 + y) * 8 + z), channels
                                    // interleaved
};

class VolumeGrid {
 public:
  static constexpr int kBlockBits = 3;
  static constexpr int kBlockSide = 1 << kBlockBits;  // an OpenVDB leaf node's side
  static constexpr int kBlockVoxels = kBlockSide * kBlockSide * kBlockSide;

  // Throws std::invalid_argument for data that does not hold together (sizes, block
  // indices, channels) or a transform without an inverse.
  explicit VolumeGrid(VolumeGridData data);
  // A grid of `resolution` voxels from dense values (`channels` floats a voxel, x fastest,
  // then y, then z: a fluid domain's, as Blender's FluidDomainSettings gives them), voxel
  // (0, 0, 0) the first; the voxels whose channels are all 0 are background (0), blocks
  // of them not stored. Throws std::invalid_argument where the sizes do not match.
  static VolumeGrid dense(const std::string& name, int channels, const glm::ivec3& resolution,
                          const float* values, size_t count, const glm::mat4& index_to_object);

  const std::string& name() const { return data_.name; }
  int channels() const { return data_.channels; }
  uint64_t active_voxels() const { return data_.active_voxels; }
  // Voxels a side of the active bounding box (0, 0, 0 for an empty grid).
  glm::ivec3 resolution() const;
  const glm::mat4& index_to_object() const { return data_.index_to_object; }
  const glm::mat4& object_to_index() const { return object_to_index_; }
  // The active voxels' box [min, max + 1] in index space, and its eight corners carried
  // to object space, bounded.
  Box3 index_bounds() const;
  Box3 object_bounds() const;
  // Bytes it holds (its blocks and their lattice), for the memory guard.
  size_t bytes() const;

  // A block holding a voxel that counts (occupied_blocks), in block coordinates, and which
  // of its six faces' voxel layers hold one: bit 2 * axis for the lower face, bit
  // 2 * axis + 1 for the upper.
  struct OccupiedBlock {
    glm::ivec3 block;
    uint32_t faces;
  };
  // The blocks holding a stored voxel at least `clipping` in magnitude (a vector grid's:
  // in some channel): what Cycles builds a Volume's mesh from (VolumeObject::bound_mesh).
  std::vector<OccupiedBlock> occupied_blocks(float clipping) const;

  // The value of voxel `ijk` (a scalar grid's in x, y and z alike).
  Vec3 voxel(const glm::ivec3& ijk) const;
  // Trilinear interpolation of the voxels at index-space point `p` (the values at the
  // voxels' centres: the header); the background far from the blocks and for a point
  // that is not finite.
  Vec3 sample(const Vec3& p) const;

  // The eight voxels a scalar grid's trilinear interpolation weighs at index-space point
  // `p`, corner c at (c & 1, c >> 1 & 1, c >> 2) of their cell, and where `p` lies in the
  // cell (0 to 1 an axis); where sample() gives the background, eight backgrounds at 0.
  struct Cell {
    float values[8];
    Vec3 t;
    float weight(int c) const {
      return ((c & 1) ? t.x : 1.0f - t.x) * ((c & 2) ? t.y : 1.0f - t.y) *
             ((c & 4) ? t.z : 1.0f - t.z);
    }
    float interpolated() const;  // sample(p).x
  };
  Cell cell(const Vec3& p) const;

 private:
  // Where index-space point `p` falls: its cell's first corner, its place in the cell, and
  // the values of the one block holding all eight corners (null where they straddle
  // blocks); nullopt where every corner is the background.
  struct Located {
    glm::ivec3 first;
    Vec3 t;
    const float* values;
  };
  std::optional<Located> locate(const Vec3& p) const;
  // The values of block `b` (block coordinates), or null where it is the background.
  const float* block(const glm::ivec3& b) const;
  Vec3 read(const float* block, int offset) const;

  VolumeGridData data_;
  glm::mat4 object_to_index_;
  glm::ivec3 last_block_;  // first_block + block_counts - 1
};

}  // namespace whitted
