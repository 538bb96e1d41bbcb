// OpenVDB files (.vdb), the grids of Volume objects: the one file that talks to OpenVDB
// (Debian's libopenvdb 10; CMake's WHITTED_OPENVDB, on by default). A grid read becomes
// a VolumeGrid of our own (scene/volume_grid.h) and nothing of OpenVDB stays behind.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "scene/volume_grid.h"

namespace whitted {

// A file that cannot be read as asked: missing, not an OpenVDB file, without the grid
// named, a grid of a type or transform Whitted does not read. The message says which.
class VolumeFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A grid a file holds, from its metadata (no voxels read).
struct VdbGridInfo {
  std::string name;
  std::string value_type;  // OpenVDB's: "float", "double", "vec3s", "vec3d", "int32", ...
  bool readable;           // a type read_vdb_grids reads: float, double, vec3s, vec3d
};

// The OpenVDB library this build reads files with ("10.0.1"), or "" where it was built
// without (-DWHITTED_OPENVDB=OFF: every read then throws VolumeFileError saying so).
std::string openvdb_version();

// The grids file `path` holds, in its order. Throws VolumeFileError.
std::vector<VdbGridInfo> vdb_grids(const std::string& path);

// The grids `names` of file `path`, in that order, as VolumeGrids (float and double
// grids as one channel, vec3s and vec3d as three). Throws VolumeFileError: a missing
// file or grid, a grid of another type, a transform that is not affine (a frustum), a
// grid too sparse for the block lattice (limits::kMaxGridBlocks).
std::vector<std::shared_ptr<const VolumeGrid>> read_vdb_grids(
    const std::string& path, const std::vector<std::string>& names);

}  // namespace whitted
