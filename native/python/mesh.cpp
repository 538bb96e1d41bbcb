#include "scene/mesh.h"

#include "bindings.h"

namespace whitted::python {
namespace {

// A list of corner layers, each float32[M, 3, width], as pointers for make_mesh (the
// arrays stay alive in `layers`).
std::vector<const float*> corner_layers(const std::vector<FloatArray>& layers, const char* name,
                                        py::ssize_t m, py::ssize_t width) {
  std::vector<const float*> out;
  for (const FloatArray& layer : layers) {
    require_shape(layer, name, {m, 3, width});
    out.push_back(layer.data());
  }
  return out;
}

// Blender's vertex normals of a polygon mesh (vertex_normals in scene/mesh.h).
py::array_t<float> vertex_normals_from_arrays(const FloatArray& positions,
                                              const UintArray& loop_vertices,
                                              const UintArray& loop_starts,
                                              const UintArray& loop_totals,
                                              const FloatArray& face_normals) {
  require_shape(positions, "positions", {-1, 3});
  require_shape(loop_vertices, "loop_vertices", {-1});
  require_shape(loop_starts, "loop_starts", {-1});
  const py::ssize_t polygons = loop_starts.shape(0);
  require_shape(loop_totals, "loop_totals", {polygons});
  require_shape(face_normals, "face_normals", {polygons, 3});
  const auto n = static_cast<size_t>(positions.shape(0));
  std::vector<float> normals;
  {
    py::gil_scoped_release release;
    normals = vertex_normals(
        positions.data(), n, loop_vertices.data(), static_cast<size_t>(loop_vertices.shape(0)),
        loop_starts.data(), loop_totals.data(), face_normals.data(), static_cast<size_t>(polygons));
  }
  py::array_t<float> out({static_cast<py::ssize_t>(n), py::ssize_t{3}});
  std::copy(normals.begin(), normals.end(), out.mutable_data());
  return out;
}

// zero_area_triangles in scene/mesh.h, as bool[M].
py::array_t<bool> zero_area_from_arrays(const FloatArray& positions, const UintArray& triangles) {
  require_shape(positions, "positions", {-1, 3});
  require_shape(triangles, "triangles", {-1, 3});
  std::vector<uint8_t> zero;
  {
    py::gil_scoped_release release;
    zero = zero_area_triangles(positions.data(), static_cast<size_t>(positions.shape(0)),
                               triangles.data(), static_cast<size_t>(triangles.shape(0)));
  }
  py::array_t<bool> out(static_cast<py::ssize_t>(zero.size()));
  std::copy(zero.begin(), zero.end(), out.mutable_data());
  return out;
}

}  // namespace

void require_shape(const py::array& a, const char* name, std::initializer_list<py::ssize_t> shape) {
  bool ok = a.ndim() == static_cast<py::ssize_t>(shape.size());
  py::ssize_t axis = 0;
  for (py::ssize_t s : shape) {
    if (ok && s >= 0 && a.shape(axis) != s) ok = false;
    ++axis;
  }
  if (!ok) {
    std::string expected = "(";
    for (py::ssize_t s : shape) expected += (s < 0 ? std::string("N") : std::to_string(s)) + ",";
    expected.back() = ')';
    throw std::invalid_argument(std::string(name) + " must have shape " + expected);
  }
}

// The arrays of a mesh, checked and copied into a native Mesh (the GIL released while
// copying: the arrays stay alive in the caller's frame).
Mesh mesh_from_arrays(const FloatArray& positions, const UintArray& triangles,
                      const std::optional<FloatArray>& normals,
                      const std::optional<IntArray>& material_slots,
                      const std::optional<FloatArray>& uvs,
                      const std::optional<FloatArray>& vertex_normals,
                      const std::vector<FloatArray>& uv_sets,
                      const std::vector<FloatArray>& attributes,
                      const std::vector<FloatArray>& tangents) {
  require_shape(positions, "positions", {-1, 3});
  require_shape(triangles, "triangles", {-1, 3});
  const auto n = static_cast<py::ssize_t>(positions.shape(0));
  const auto m = static_cast<py::ssize_t>(triangles.shape(0));
  if (normals) require_shape(*normals, "normals", {m, 3, 3});
  if (vertex_normals) require_shape(*vertex_normals, "vertex_normals", {n, 3});
  if (material_slots) require_shape(*material_slots, "material_slots", {m});
  if (uvs) require_shape(*uvs, "uvs", {m, 3, 2});
  const float* p = positions.data();
  const uint32_t* t = triangles.data();
  const float* cn = normals ? normals->data() : nullptr;
  const float* vn = vertex_normals ? vertex_normals->data() : nullptr;
  const int32_t* s = material_slots ? material_slots->data() : nullptr;
  const float* uv = uvs ? uvs->data() : nullptr;
  const CornerLayers layers{corner_layers(uv_sets, "each of uv_sets", m, 2),
                            corner_layers(attributes, "each of attributes", m, 4),
                            corner_layers(tangents, "each of tangents", m, 4)};
  py::gil_scoped_release release;
  return make_mesh(p, static_cast<size_t>(n), t, static_cast<size_t>(m), cn, s, uv, vn, layers);
}

void bind_mesh(py::module_& m) {
  m.def("zero_area_triangles", &zero_area_from_arrays, py::arg("positions"), py::arg("triangles"),
        "bool[M]: which triangles have zero area, the cross product of their edges (p1 - p0, "
        "p2 - p0), in float64, exactly 0; False where a corner is NaN or infinite. "
        "positions float32[N,3], triangles uint32[M,3].");
  m.def("vertex_normals", &vertex_normals_from_arrays, py::arg("positions"),
        py::arg("loop_vertices"), py::arg("loop_starts"), py::arg("loop_totals"),
        py::arg("face_normals"),
        "float32[N,3]: Blender's smooth vertex normals of a polygon mesh (each vertex's "
        "face normals weighted by the corner angle, normalised; (0, 0, 0) at a vertex of no "
        "face), summed in fixed point so that the same faces in any order give the same "
        "bits. "
        "positions float32[N,3]; loop_vertices uint32[L]; loop_starts, loop_totals uint32[P] "
        "(polygon p owns loops loop_starts[p] .. + loop_totals[p] - 1); face_normals "
        "float32[P,3].");
  py::class_<Mesh>(m, "Mesh",
                   "A triangle mesh copied out of numpy arrays, ready for Scene.set_mesh. "
                   "Making it first lets the caller free its arrays before the BVH is built.")
      .def(py::init(&mesh_from_arrays), py::arg("positions"), py::arg("triangles"),
           py::arg("normals") = py::none(), py::arg("material_slots") = py::none(),
           py::arg("uvs") = py::none(), py::arg("vertex_normals") = py::none(),
           py::arg("uv_sets") = std::vector<FloatArray>{},
           py::arg("attributes") = std::vector<FloatArray>{},
           py::arg("tangents") = std::vector<FloatArray>{},
           "positions float32[N,3], triangles uint32[M,3]; shading normals, at most one of: "
           "normals float32[M,3,3] corner normals, vertex_normals float32[N,3] (indexed like "
           "positions); neither: flat. material_slots int32[M] or None (slot 0), uvs "
           "float32[M,3,2] corner texture coordinates or None (UV set 0; or give uv_sets, a "
           "list of float32[M,3,2]); attributes: list of float32[M,3,4] corner RGBA; "
           "tangents: list of float32[M,3,4], one per UV set (object-space xyz tangent, w "
           "the bitangent sign).")
      .def(
          "set_motion",
          [](Mesh& mesh, const std::vector<FloatArray>& steps) {
            const auto n = static_cast<py::ssize_t>(mesh.vertex_count());
            std::vector<std::vector<float>> motion;
            for (const FloatArray& step : steps) {
              require_shape(step, "each motion step", {n, 3});
              std::vector<float> positions(step.data(), step.data() + 3 * n);
              for (float v : positions) {
                if (!std::isfinite(v))
                  throw std::invalid_argument("motion positions must be finite");
              }
              positions.push_back(0.0f);  // Embree reads one float past the last vertex
              motion.push_back(std::move(positions));
            }
            if (motion.size() == 1) motion.clear();  // one step: no motion
            mesh.motion_positions = std::move(motion);
          },
          py::arg("steps"),
          "Deformation motion blur: its positions (float32[N,3] each, as the mesh's) at "
          "evenly spaced times from the shutter's opening to its closing.")
      .def(
          "set_curves",
          [](Mesh& mesh, const FloatArray& keys, const UintArray& counts,
             const std::optional<IntArray>& slots, bool linear, bool flat) {
            require_shape(keys, "keys", {-1, 4});
            require_shape(counts, "counts", {-1});
            if (slots) require_shape(*slots, "slots", {counts.shape(0)});
            const int32_t* slot = slots ? slots->data() : nullptr;
            py::gil_scoped_release release;
            mesh.curves =
                make_curves(keys.data(), static_cast<size_t>(keys.shape(0)), counts.data(),
                            static_cast<size_t>(counts.shape(0)), slot, linear, flat);
          },
          py::arg("keys"), py::arg("counts"), py::arg("slots") = py::none(),
          py::arg("linear") = false, py::arg("flat") = false,
          "Strands (hair, curves) of the same object: keys float32[K,4] (x, y, z, radius, "
          "object space), counts uint32[C] keys of each strand in order, slots int32[C] "
          "material slot of each (None: slot 0). Traced as round Catmull-Rom tubes through "
          "the keys, or with `linear` straight cones from key to key (round joints and "
          "ends); with `flat`, the same curves as ribbons facing each ray, shaded as the "
          "round tubes they stand for (Cycles' Ribbons); strands of fewer than two keys are "
          "left out.")
      .def(
          "set_points",
          [](Mesh& mesh, const FloatArray& spheres, const std::optional<IntArray>& slots) {
            require_shape(spheres, "spheres", {-1, 4});
            if (slots) require_shape(*slots, "slots", {spheres.shape(0)});
            const int32_t* slot = slots ? slots->data() : nullptr;
            py::gil_scoped_release release;
            mesh.points = make_points(spheres.data(), static_cast<size_t>(spheres.shape(0)), slot);
          },
          py::arg("spheres"), py::arg("slots") = py::none(),
          "Points (a point cloud) of the same object: spheres float32[P,4] (x, y, z, radius, "
          "object space), slots int32[P] (None: slot 0).")
      .def_property_readonly("deforms", &Mesh::deforms,
                             "Whether set_motion gave it positions that move over the shutter.")
      .def_property_readonly("vertex_count", &Mesh::vertex_count, "Its number of vertices (N).")
      .def_property_readonly(
          "positions",
          [](const Mesh& mesh) {
            const auto n = static_cast<py::ssize_t>(mesh.vertex_count());
            py::array_t<float> out({n, py::ssize_t{3}});
            std::copy(mesh.positions.begin(), mesh.positions.begin() + 3 * n, out.mutable_data());
            return out;
          },
          "A copy of its vertices, float32[N,3], object space.")
      .def_property_readonly(
          "vertex_normals",
          [](const Mesh& mesh) -> std::optional<py::array_t<float>> {
            if (mesh.vertex_normals.empty()) return std::nullopt;
            const auto n = static_cast<py::ssize_t>(mesh.vertex_count());
            py::array_t<float> out({n, py::ssize_t{3}});
            std::copy(mesh.vertex_normals.begin(), mesh.vertex_normals.end(), out.mutable_data());
            return out;
          },
          "A copy of its vertex normals, float32[N,3], or None (corner normals, or flat).")
      .def_property_readonly("triangle_count", &Mesh::triangle_count,
                             "Its number of triangles (M).")
      .def_property_readonly(
          "curve_segment_count", [](const Mesh& mesh) { return mesh.curves.segment_count(); },
          "Its number of curve segments (from set_curves).")
      .def_property_readonly(
          "point_count", [](const Mesh& mesh) { return mesh.points.count(); },
          "Its number of point spheres (from set_points).");
}

}  // namespace whitted::python
