#include "scene/volume_grid.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <optional>
#include <stdexcept>

#include "scene/scene.h"

namespace whitted {
namespace {

// Where voxel `ijk` sits in its block, as in an OpenVDB leaf node.
int offset_in_block(const glm::ivec3& ijk) {
  constexpr int mask = VolumeGrid::kBlockSide - 1;
  return ((ijk.x & mask) << (2 * VolumeGrid::kBlockBits)) |
         ((ijk.y & mask) << VolumeGrid::kBlockBits) | (ijk.z & mask);
}

// Block coordinates of a voxel: a floor division by the block's side (an arithmetic
// shift, defined for negative values since C++20).
glm::ivec3 block_of(const glm::ivec3& ijk) {
  return {ijk.x >> VolumeGrid::kBlockBits, ijk.y >> VolumeGrid::kBlockBits,
          ijk.z >> VolumeGrid::kBlockBits};
}

// Trilinear interpolation of eight corner values, corner c at (c & 1, c >> 1 & 1, c >> 2):
// along x, then y, then z.
template <class T>
T trilinear(const T (&c)[8], const Vec3& t) {
  const T x00 = c[0] + (c[1] - c[0]) * t.x;
  const T x10 = c[2] + (c[3] - c[2]) * t.x;
  const T x01 = c[4] + (c[5] - c[4]) * t.x;
  const T x11 = c[6] + (c[7] - c[6]) * t.x;
  const T y0 = x00 + (x10 - x00) * t.y;
  const T y1 = x01 + (x11 - x01) * t.y;
  return y0 + (y1 - y0) * t.z;
}

// Where corner c of a voxel's cell sits in its block, from the first corner's offset.
constexpr int kCornerStep[8] = {0, 64, 8, 72, 1, 65, 9, 73};
static_assert(VolumeGrid::kBlockSide == 8, "kCornerStep is for blocks of 8^3 voxels");

}  // namespace

VolumeGrid::VolumeGrid(VolumeGridData data) : data_(std::move(data)) {
  if (data_.channels != 1 && data_.channels != 3) {
    throw std::invalid_argument("a volume grid has 1 or 3 channels");
  }
  const glm::ivec3 n = data_.block_counts;
  if (n.x < 0 || n.y < 0 || n.z < 0) throw std::invalid_argument("negative block counts");
  const size_t lattice = size_t(n.x) * size_t(n.y) * size_t(n.z);
  if (data_.blocks.size() != lattice) {
    throw std::invalid_argument("the block lattice does not match its counts");
  }
  const size_t block_floats = size_t(kBlockVoxels) * size_t(data_.channels);
  if (data_.values.size() % block_floats != 0) {
    throw std::invalid_argument("block values are not whole blocks");
  }
  const size_t stored = data_.values.size() / block_floats;
  for (uint32_t index : data_.blocks) {
    if (index > stored) throw std::invalid_argument("a block index past the stored blocks");
  }
  if (!is_finite(data_.index_to_object) || !is_finite(data_.background)) {
    throw std::invalid_argument("a volume grid's transform and background must be finite");
  }
  object_to_index_ = glm::inverse(data_.index_to_object);
  if (!is_finite(object_to_index_) || glm::determinant(data_.index_to_object) == 0.0f) {
    throw std::invalid_argument("volume grid '" + data_.name +
                                "': its transform has no inverse (a zero voxel size)");
  }
  last_block_ = data_.first_block + n - 1;
}

VolumeGrid VolumeGrid::dense(const std::string& name, int channels, const glm::ivec3& resolution,
                             const float* values, size_t count, const glm::mat4& index_to_object) {
  const glm::ivec3& n = resolution;
  if (n.x <= 0 || n.y <= 0 || n.z <= 0) throw std::invalid_argument("a dense grid is not empty");
  if (channels != 1 && channels != 3) throw std::invalid_argument("a grid has 1 or 3 channels");
  const size_t voxels = size_t(n.x) * size_t(n.y) * size_t(n.z);
  if (count != voxels * size_t(channels)) {
    throw std::invalid_argument("dense grid '" + name + "': " + std::to_string(count) +
                                " values for " + std::to_string(voxels) + " voxels of " +
                                std::to_string(channels) + " channel(s)");
  }
  VolumeGridData data;
  data.name = name;
  data.channels = channels;
  data.index_to_object = index_to_object;
  data.block_counts = block_of(n - 1) + 1;
  data.blocks.assign(
      size_t(data.block_counts.x) * size_t(data.block_counts.y) * size_t(data.block_counts.z), 0u);
  data.active_lower = n;
  data.active_upper = glm::ivec3(-1);
  const size_t block_floats = size_t(kBlockVoxels) * size_t(channels);
  for (int z = 0; z < n.z; ++z) {
    for (int y = 0; y < n.y; ++y) {
      for (int x = 0; x < n.x; ++x) {
        const float* v = values + ((size_t(z) * n.y + y) * n.x + x) * size_t(channels);
        bool active = false;
        for (int c = 0; c < channels; ++c) active |= v[c] != 0.0f;
        if (!active) continue;
        const glm::ivec3 ijk(x, y, z);
        const glm::ivec3 b = block_of(ijk);
        uint32_t& index =
            data.blocks[(size_t(b.x) * data.block_counts.y + b.y) * data.block_counts.z + b.z];
        if (index == 0) {
          data.values.resize(data.values.size() + block_floats, 0.0f);
          index = static_cast<uint32_t>(data.values.size() / block_floats);
        }
        float* out = &data.values[(index - 1) * block_floats +
                                  size_t(offset_in_block(ijk)) * size_t(channels)];
        for (int c = 0; c < channels; ++c) out[c] = std::isfinite(v[c]) ? v[c] : 0.0f;
        data.active_lower = glm::min(data.active_lower, ijk);
        data.active_upper = glm::max(data.active_upper, ijk);
        data.active_voxels += 1;
      }
    }
  }
  if (data.active_voxels == 0) data.active_lower = glm::ivec3(0);
  return VolumeGrid(std::move(data));
}

glm::ivec3 VolumeGrid::resolution() const {
  const glm::ivec3 size = data_.active_upper - data_.active_lower + 1;
  if (size.x <= 0 || size.y <= 0 || size.z <= 0) return glm::ivec3(0);
  return size;
}

Box3 VolumeGrid::index_bounds() const {
  if (resolution() == glm::ivec3(0)) return {};
  return {Vec3(data_.active_lower), Vec3(data_.active_upper + 1)};
}

Box3 placed(const Box3& box, const glm::mat4& m) {
  Box3 out;
  if (box.empty()) return out;
  for (int k = 0; k < 8; ++k) out.extend(transform_point(m, box.corner(k)));
  return out;
}

Box3 VolumeGrid::object_bounds() const {
  return placed(index_bounds(), data_.index_to_object);
}

size_t VolumeGrid::bytes() const {
  return data_.values.size() * sizeof(float) + data_.blocks.size() * sizeof(uint32_t) +
         sizeof(*this);
}

std::vector<VolumeGrid::OccupiedBlock> VolumeGrid::occupied_blocks(float clipping) const {
  std::vector<OccupiedBlock> out;
  const glm::ivec3 n = data_.block_counts;
  const int channels = data_.channels;
  constexpr int last = kBlockSide - 1;
  for (int x = 0; x < n.x; ++x) {
    for (int y = 0; y < n.y; ++y) {
      for (int z = 0; z < n.z; ++z) {
        const glm::ivec3 b = data_.first_block + glm::ivec3(x, y, z);
        const float* values = block(b);
        if (values == nullptr) continue;
        bool any = false;
        uint32_t faces = 0;
        for (int offset = 0; offset < kBlockVoxels; ++offset) {
          bool counts = false;
          for (int c = 0; c < channels; ++c) {
            counts |= std::abs(values[offset * channels + c]) >= clipping;
          }
          if (!counts) continue;
          any = true;
          const glm::ivec3 v(offset >> (2 * kBlockBits), (offset >> kBlockBits) & last,
                             offset & last);
          for (int axis = 0; axis < 3; ++axis) {
            if (v[axis] == 0) faces |= 1u << (2 * axis);
            if (v[axis] == last) faces |= 1u << (2 * axis + 1);
          }
        }
        if (any) out.push_back({b, faces});
      }
    }
  }
  return out;
}

const float* VolumeGrid::block(const glm::ivec3& b) const {
  if (b.x < data_.first_block.x || b.y < data_.first_block.y || b.z < data_.first_block.z ||
      b.x > last_block_.x || b.y > last_block_.y || b.z > last_block_.z) {
    return nullptr;
  }
  const glm::ivec3 r = b - data_.first_block;
  const uint32_t index = data_.blocks[(size_t(r.x) * size_t(data_.block_counts.y) + size_t(r.y)) *
                                          size_t(data_.block_counts.z) +
                                      size_t(r.z)];
  if (index == 0) return nullptr;
  return data_.values.data() + size_t(index - 1) * size_t(kBlockVoxels) * size_t(data_.channels);
}

Vec3 VolumeGrid::read(const float* values, int offset) const {
  if (values == nullptr) return data_.background;
  if (data_.channels == 1) return Vec3(values[offset]);
  const float* v = values + 3 * offset;
  return {v[0], v[1], v[2]};
}

Vec3 VolumeGrid::voxel(const glm::ivec3& ijk) const {
  return read(block(block_of(ijk)), offset_in_block(ijk));
}

std::optional<VolumeGrid::Located> VolumeGrid::locate(const Vec3& p) const {
  // The voxels' values stand at their centres (header): interpolate from p - 0.5.
  const Vec3 q = p - 0.5f;
  // Beyond the lattice by a voxel or more (and for NaN), every corner is the background;
  // this also keeps the float-to-int conversion below in range.
  const Vec3 low = Vec3(data_.first_block * kBlockSide) - 1.0f;
  const Vec3 high = Vec3((last_block_ + 1) * kBlockSide);
  if (!(q.x > low.x && q.y > low.y && q.z > low.z && q.x < high.x && q.y < high.y &&
        q.z < high.z)) {
    return std::nullopt;
  }
  const Vec3 floor = glm::floor(q);
  const glm::ivec3 first(floor);
  constexpr int mask = kBlockSide - 1;
  // All eight corners in one block (7 of 8 cells): one lattice lookup.
  const bool one_block =
      (first.x & mask) != mask && (first.y & mask) != mask && (first.z & mask) != mask;
  const float* values = one_block ? block(block_of(first)) : nullptr;
  if (one_block && values == nullptr) return std::nullopt;
  return Located{first, q - floor, values};
}

float VolumeGrid::Cell::interpolated() const {
  return trilinear(values, t);
}

VolumeGrid::Cell VolumeGrid::cell(const Vec3& p) const {
  Cell out;
  const std::optional<Located> at = locate(p);
  if (!at) {
    std::fill(std::begin(out.values), std::end(out.values), data_.background.x);
    out.t = Vec3(0.0f);
    return out;
  }
  const int base = offset_in_block(at->first);
  for (int c = 0; c < 8; ++c) {
    out.values[c] = at->values ? at->values[base + kCornerStep[c]]
                               : voxel(at->first + glm::ivec3(c & 1, (c >> 1) & 1, c >> 2)).x;
  }
  out.t = at->t;
  return out;
}

Vec3 VolumeGrid::sample(const Vec3& p) const {
  if (data_.channels == 1) return Vec3(cell(p).interpolated());
  const std::optional<Located> at = locate(p);
  if (!at) return data_.background;
  const int base = offset_in_block(at->first);
  Vec3 corners[8];
  for (int c = 0; c < 8; ++c) {
    corners[c] = at->values ? read(at->values, base + kCornerStep[c])
                            : voxel(at->first + glm::ivec3(c & 1, (c >> 1) & 1, c >> 2));
  }
  return trilinear(corners, at->t);
}

}  // namespace whitted
