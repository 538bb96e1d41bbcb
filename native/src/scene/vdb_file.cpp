#include "scene/vdb_file.h"

#include <filesystem>

#include "core/limits.h"

#if WHITTED_OPENVDB
#include <openvdb/openvdb.h>
#include <openvdb/version.h>
#endif

namespace whitted {

#if WHITTED_OPENVDB
namespace {

bool readable(const openvdb::GridBase& grid) {
  return grid.isType<openvdb::FloatGrid>() || grid.isType<openvdb::DoubleGrid>() ||
         grid.isType<openvdb::Vec3SGrid>() || grid.isType<openvdb::Vec3DGrid>();
}

template <class T>
void put(const T& value, float* out) {
  if constexpr (std::is_arithmetic_v<T>) {
    out[0] = static_cast<float>(value);
  } else {
    for (int c = 0; c < 3; ++c) out[c] = static_cast<float>(value[c]);
  }
}

glm::ivec3 ivec(const openvdb::Coord& c) {
  return {c.x(), c.y(), c.z()};
}

// An OpenVDB grid of ValueType float, double, Vec3s or Vec3d as VolumeGridData: its
// leaves copied as blocks, its tiles (constant regions above the leaves: active ones,
// and inactive ones whose value is not the background) as one shared block each.
template <class GridT>
VolumeGridData convert(const GridT& grid, const std::string& path) {
  using ValueT = typename GridT::ValueType;
  using TreeT = typename GridT::TreeType;
  constexpr int kChannels = std::is_arithmetic_v<ValueT> ? 1 : 3;
  const std::string what = "grid '" + grid.getName() + "' of " + path;
  if (!grid.transform().isLinear()) {
    throw VolumeFileError(what +
                          ": its transform is not affine (a frustum grid), which "
                          "Whitted does not read");
  }
  VolumeGridData data;
  data.name = grid.getName();
  data.channels = kChannels;
  // OpenVDB's matrices act on row vectors (p' = p M, the translation in row 3): their
  // rows are glm's columns (p' = G p), element for element.
  const openvdb::math::Mat4d m = grid.transform().baseMap()->getAffineMap()->getMat4();
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) data.index_to_object[c][r] = static_cast<float>(m(c, r));
  }
  const TreeT& tree = grid.tree();
  float background[3] = {0.0f, 0.0f, 0.0f};
  put(tree.background(), background);
  data.background =
      kChannels == 1 ? Vec3(background[0]) : Vec3(background[0], background[1], background[2]);
  const openvdb::CoordBBox active = grid.evalActiveVoxelBoundingBox();
  data.active_voxels = grid.activeVoxelCount();
  if (active.empty() || data.active_voxels == 0) return data;  // an empty grid
  data.active_lower = ivec(active.min());
  data.active_upper = ivec(active.max());
  // The lattice covers the active voxels and every leaf (whose inactive voxels may hold
  // values that the samples just inside the active box read).
  openvdb::CoordBBox covered = active;
  openvdb::CoordBBox leaves;
  if (tree.evalLeafBoundingBox(leaves)) covered.expand(leaves);
  constexpr int kBits = VolumeGrid::kBlockBits;
  const glm::ivec3 first = ivec(covered.min()) >> kBits;
  const glm::ivec3 last = ivec(covered.max()) >> kBits;
  const glm::ivec3 counts = last - first + 1;
  const double lattice = double(counts.x) * double(counts.y) * double(counts.z);
  if (lattice > double(limits::kMaxGridBlocks)) {
    throw VolumeFileError(what + ": its voxels spread over " + std::to_string(counts.x * 8) +
                          " x " + std::to_string(counts.y * 8) + " x " +
                          std::to_string(counts.z * 8) +
                          " voxels, more than Whitted's block "
                          "lattice holds");
  }
  data.first_block = first;
  data.block_counts = counts;
  data.blocks.assign(size_t(lattice), 0);
  const auto lattice_index = [&](const glm::ivec3& block) {
    const glm::ivec3 r = block - first;
    return (size_t(r.x) * size_t(counts.y) + size_t(r.y)) * size_t(counts.z) + size_t(r.z);
  };
  constexpr size_t kBlockFloats = size_t(VolumeGrid::kBlockVoxels) * kChannels;
  uint32_t stored = 0;
  // Tiles first: leaves below a tile's level replace its block where they exist.
  typename TreeT::ValueAllCIter tile = tree.cbeginValueAll();
  tile.setMaxDepth(TreeT::ValueAllCIter::LEAF_DEPTH - 1);
  for (; tile; ++tile) {
    if (!tile.isValueOn() && openvdb::math::isExactlyEqual(*tile, tree.background())) continue;
    openvdb::CoordBBox box;
    tile.getBoundingBox(box);
    const glm::ivec3 lo = glm::max(ivec(box.min()) >> kBits, first);
    const glm::ivec3 hi = glm::min(ivec(box.max()) >> kBits, last);
    if (lo.x > hi.x || lo.y > hi.y || lo.z > hi.z) continue;  // outside the lattice
    data.values.resize(data.values.size() + kBlockFloats);
    float* values = data.values.data() + size_t(stored) * kBlockFloats;
    for (int v = 0; v < VolumeGrid::kBlockVoxels; ++v) put(*tile, values + v * kChannels);
    ++stored;
    for (int x = lo.x; x <= hi.x; ++x) {
      for (int y = lo.y; y <= hi.y; ++y) {
        for (int z = lo.z; z <= hi.z; ++z) data.blocks[lattice_index({x, y, z})] = stored;
      }
    }
  }
  for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) {
    data.values.resize(data.values.size() + kBlockFloats);
    float* values = data.values.data() + size_t(stored) * kBlockFloats;
    // OpenVDB's leaf order is ours: offset (x * 8 + y) * 8 + z within the leaf.
    for (openvdb::Index v = 0; v < openvdb::Index(VolumeGrid::kBlockVoxels); ++v) {
      put(leaf->getValue(v), values + v * kChannels);
    }
    ++stored;
    data.blocks[lattice_index(ivec(leaf->origin()) >> kBits)] = stored;
  }
  return data;
}

// The file opened with its trees read at once (no delayed loading: the file may be a
// temporary one, deleted once read). Throws VolumeFileError.
std::unique_ptr<openvdb::io::File> open(const std::string& path) {
  openvdb::initialize();  // registers the grid types; idempotent and thread-safe
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) {
    throw VolumeFileError("OpenVDB file " + path + " does not exist");
  }
  auto file = std::make_unique<openvdb::io::File>(path);
  try {
    file->open(false);
  } catch (const openvdb::Exception& e) {
    throw VolumeFileError(path + " is not a readable OpenVDB file: " + e.what());
  }
  return file;
}

}  // namespace

std::string openvdb_version() {
  return openvdb::getLibraryVersionString();
}

std::vector<VdbGridInfo> vdb_grids(const std::string& path) {
  const std::unique_ptr<openvdb::io::File> file = open(path);
  std::vector<VdbGridInfo> out;
  try {
    // Held here: a range-for over *readAllGridMetadata() would outlive the vector.
    const openvdb::GridPtrVecPtr grids = file->readAllGridMetadata();
    for (const openvdb::GridBase::Ptr& grid : *grids) {
      out.push_back({grid->getName(), grid->valueType(), readable(*grid)});
    }
  } catch (const openvdb::Exception& e) {
    throw VolumeFileError(path + ": its grids cannot be listed: " + e.what());
  }
  return out;
}

std::vector<std::shared_ptr<const VolumeGrid>> read_vdb_grids(
    const std::string& path, const std::vector<std::string>& names) {
  const std::unique_ptr<openvdb::io::File> file = open(path);
  std::vector<std::shared_ptr<const VolumeGrid>> out;
  for (const std::string& name : names) {
    if (!file->hasGrid(name)) {
      throw VolumeFileError(path + " has no grid named '" + name + "'");
    }
    openvdb::GridBase::Ptr grid;
    try {
      grid = file->readGrid(name);
    } catch (const openvdb::Exception& e) {
      throw VolumeFileError(path + ": grid '" + name + "' cannot be read: " + e.what());
    }
    VolumeGridData data;
    if (auto g = openvdb::gridPtrCast<openvdb::FloatGrid>(grid)) {
      data = convert(*g, path);
    } else if (auto d = openvdb::gridPtrCast<openvdb::DoubleGrid>(grid)) {
      data = convert(*d, path);
    } else if (auto v = openvdb::gridPtrCast<openvdb::Vec3SGrid>(grid)) {
      data = convert(*v, path);
    } else if (auto w = openvdb::gridPtrCast<openvdb::Vec3DGrid>(grid)) {
      data = convert(*w, path);
    } else {
      throw VolumeFileError(path + ": grid '" + name + "' holds " + grid->valueType() +
                            " values; Whitted reads float, double and vector grids");
    }
    try {
      out.push_back(std::make_shared<const VolumeGrid>(std::move(data)));
    } catch (const std::invalid_argument& e) {
      throw VolumeFileError(path + ": " + e.what());
    }
  }
  return out;
}

#else  // built without OpenVDB

namespace {
[[noreturn]] void unavailable() {
  throw VolumeFileError(
      "this build of Whitted reads no OpenVDB files: it was configured with "
      "-DWHITTED_OPENVDB=OFF (install libopenvdb-dev and build again)");
}
}  // namespace

std::string openvdb_version() {
  return "";
}
std::vector<VdbGridInfo> vdb_grids(const std::string&) {
  unavailable();
}
std::vector<std::shared_ptr<const VolumeGrid>> read_vdb_grids(const std::string&,
                                                              const std::vector<std::string>&) {
  unavailable();
}

#endif

}  // namespace whitted
