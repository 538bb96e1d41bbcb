// Volume objects' grids (scene/vdb_file.h, volume_grid.h, volume_object.h): reading an
// OpenVDB file's grids, and what they give at a point.
#include "scene/volume_object.h"
#include "scene/vdb_file.h"

#include "bindings.h"

namespace whitted::python {
namespace {

// A box as ((x, y, z), (x, y, z)), or None when it is empty.
py::object volume_box(const Box3& box) {
  if (box.empty()) return py::none();
  return py::make_tuple(box.lower, box.upper);
}

// pybind11 holds the grids as shared_ptr<VolumeGrid>; the native side shares them const.
using GridHandle = std::shared_ptr<VolumeGrid>;

}  // namespace

void bind_volume_object(py::module_& m) {
  auto error = py::register_exception<VolumeFileError>(m, "VolumeFileError", PyExc_RuntimeError);
  error.attr("__doc__") =
      "An OpenVDB file that cannot be read as asked (missing, not OpenVDB, without the grid "
      "named, a grid of a type or transform Whitted does not read); the message says which.";
  m.attr("OPENVDB_VERSION") = openvdb_version();

  m.def(
      "vdb_grids",
      [](const std::string& path) {
        std::vector<VdbGridInfo> grids;
        {
          py::gil_scoped_release release;
          grids = vdb_grids(path);
        }
        py::list out;
        for (const VdbGridInfo& g : grids)
          out.append(py::make_tuple(g.name, g.value_type, g.readable));
        return out;
      },
      py::arg("path"),
      "The grids an OpenVDB file holds, from its metadata: [(name, value type, readable)], "
      "value types as OpenVDB names them ('float', 'vec3s', ...); readable: a type "
      "read_volume_grids reads. Raises VolumeFileError.");

  m.def(
      "read_volume_grids",
      [](const std::string& path, const std::vector<std::string>& names) {
        std::vector<std::shared_ptr<const VolumeGrid>> grids;
        {
          py::gil_scoped_release release;
          grids = read_vdb_grids(path, names);
        }
        std::vector<GridHandle> out;
        for (auto& grid : grids) out.push_back(std::const_pointer_cast<VolumeGrid>(grid));
        return out;
      },
      py::arg("path"), py::arg("names"),
      "The grids `names` of an OpenVDB file, in that order, as VolumeGrids (float and double "
      "grids of one channel, vec3s and vec3d of three), read at once (the file may be "
      "deleted afterwards). Raises VolumeFileError.");

  m.def(
      "dense_volume_grid",
      [](const std::string& name, const FloatArray& values, const std::array<int, 3>& resolution,
         int channels, const py::object& index_to_object) {
        const glm::mat4 to_object = matrix_from_numpy(index_to_object);
        const float* data = values.data();
        const auto count = static_cast<size_t>(values.size());
        py::gil_scoped_release release;
        return std::make_shared<VolumeGrid>(VolumeGrid::dense(
            name, channels, glm::ivec3(resolution[0], resolution[1], resolution[2]), data, count,
            to_object));
      },
      py::arg("name"), py::arg("values"), py::arg("resolution"), py::arg("channels"),
      py::arg("index_to_object"),
      "A VolumeGrid from dense values (float32, `channels` a voxel, x fastest, then y, then "
      "z: a fluid domain's grid as Blender gives it); voxels of all 0 are background. "
      "index_to_object: 4x4 row-major, index space to the object's.");

  py::class_<VolumeGrid, GridHandle>(
      m, "VolumeGrid",
      "One grid of a Volume object, in blocks of 8^3 voxels; immutable. Index space is "
      "OpenVDB's, each voxel's value at its centre (i + 0.5, ...), as Cycles samples grids.")
      .def_property_readonly("name", &VolumeGrid::name, "The grid's name in its file.")
      .def_property_readonly("channels", &VolumeGrid::channels,
                             "1 for a scalar grid, 3 for a vector (colour) grid.")
      .def_property_readonly("active_voxels", &VolumeGrid::active_voxels,
                             "How many of its voxels are active.")
      .def_property_readonly(
          "resolution",
          [](const VolumeGrid& g) {
            const glm::ivec3 r = g.resolution();
            return py::make_tuple(r.x, r.y, r.z);
          },
          "Voxels a side of the active voxels' bounding box ((0, 0, 0) when empty).")
      .def_property_readonly(
          "index_to_object",
          [](const VolumeGrid& g) { return matrix_to_numpy(g.index_to_object()); },
          "The grid's transform, index space to object space, as a 4x4 row-major matrix.")
      .def_property_readonly(
          "object_bounds", [](const VolumeGrid& g) { return volume_box(g.object_bounds()); },
          "The active voxels' box [min, max + 1] carried to object space, bounded: ((x, y, z), "
          "(x, y, z)), or None when the grid is empty.")
      .def_property_readonly("bytes", &VolumeGrid::bytes, "Bytes it holds, for the memory guard.")
      .def(
          "voxel",
          [](const VolumeGrid& g, int i, int j, int k) {
            return g.voxel({i, j, k});
          },
          py::arg("i"), py::arg("j"), py::arg("k"),
          "Voxel (i, j, k)'s value as (x, y, z) (a scalar grid's three times).")
      .def("sample", &VolumeGrid::sample, py::arg("p"),
           "Trilinear interpolation at index-space point p, as (x, y, z).");

  py::class_<VolumeObject, std::shared_ptr<VolumeObject>>(
      m, "VolumeObject",
      "A Volume object's grids placed in the world: what a grid-driven medium reads at a "
      "point, and the box outside which its grids are background.")
      .def(py::init([](const py::object& to_world, GridHandle density, GridHandle color,
                       GridHandle temperature, GridHandle flame, const std::string& space,
                       float step_size, bool centred, float clipping) {
             if (space != "OBJECT" && space != "WORLD") {
               throw std::invalid_argument("space is 'OBJECT' or 'WORLD', not '" + space + "'");
             }
             return std::make_shared<VolumeObject>(
                 matrix_from_numpy(to_world),
                 VolumeObject::Grids{std::move(density), std::move(color), std::move(temperature),
                                     std::move(flame)},
                 VolumeRender{space == "OBJECT", step_size, centred, clipping});
           }),
           py::arg("to_world"), py::kw_only(), py::arg("density") = py::none(),
           py::arg("color") = py::none(), py::arg("temperature") = py::none(),
           py::arg("flame") = py::none(), py::arg("space") = "OBJECT", py::arg("step_size") = 0.0f,
           py::arg("centred") = true, py::arg("clipping") = 0.001f,
           "to_world: the object's 4x4 row-major matrix; each role's VolumeGrid or None "
           "(color: a vector grid; the others scalar); space and step_size: its Volume > "
           "Render settings ('OBJECT' or 'WORLD'; Blender units of that space, 0 from the "
           "voxels); centred: a voxel's value at its cube's centre, else at its integer "
           "index point; clipping: Volume > Render > Clipping, the magnitude below which a "
           "voxel is empty space.")
      .def("bound_mesh", &VolumeObject::bound_mesh,
           "The Mesh (object space) rays enter and leave its medium through, for "
           "Scene.set_mesh: the faces around the blocks of 8^3 voxels that hold a voxel of "
           "at least clipping or border one, as Cycles builds a Volume's mesh; a Mesh of no "
           "triangles where no voxel counts.")
      .def_property_readonly("density_scale", &VolumeObject::density_scale,
                             "Cycles' object volume density: 1/scale in object space, else 1.")
      .def_property_readonly("step", &VolumeObject::step,
                             "The march step its grids call for, world units (0: none).")
      .def(
          "sample",
          [](const VolumeObject& v, const Vec3& x) {
            const VolumeSample s = v.sample(x);
            py::dict out;
            out["density"] = s.density;
            out["color"] = s.color;
            out["temperature"] = s.temperature;
            out["flame"] = s.flame;
            return out;
          },
          py::arg("x"),
          "The grids at world point x: {'density', 'color', 'temperature', 'flame'}; a role "
          "without a grid reads 1 (flame 0), as Principled Volume reads a missing attribute.")
      .def_property_readonly(
          "world_bounds", [](const VolumeObject& v) { return volume_box(v.world_bounds()); },
          "The world box bounding every grid's active voxels, or None when all are empty.")
      .def_property_readonly("bytes", &VolumeObject::bytes,
                             "Bytes its grids hold, for the memory guard.");
}

}  // namespace whitted::python
