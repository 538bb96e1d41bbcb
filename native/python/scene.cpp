#include "scene/scene.h"

#include "bindings.h"

namespace whitted::python {
namespace {

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;
using UintArray = py::array_t<uint32_t, py::array::c_style | py::array::forcecast>;
using IntArray = py::array_t<int32_t, py::array::c_style | py::array::forcecast>;

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

// Moves `mesh` into the scene under `name` and builds its BVH, without the GIL.
void set_native_mesh(Scene& scene, const std::string& name, Mesh mesh) {
  py::gil_scoped_release release;
  scene.set_mesh(name, std::move(mesh));
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

void bind_scene(py::module_& m) {
  m.def("zero_area_triangles", &zero_area_from_arrays, py::arg("positions"), py::arg("triangles"),
        "bool[M]: which triangles have zero area, the cross product of their edges (p1 - p0, "
        "p2 - p0), in float64, exactly 0; False where a corner is NaN or infinite. "
        "positions float32[N,3], triangles uint32[M,3].");
  m.def("vertex_normals", &vertex_normals_from_arrays, py::arg("positions"),
        py::arg("loop_vertices"), py::arg("loop_starts"), py::arg("loop_totals"),
        py::arg("face_normals"),
        "float32[N,3]: Blender's smooth vertex normals of a polygon mesh (each vertex's "
        "face normals weighted by the corner angle, normalised; (0, 0, 0) at a vertex of no "
        "face), summed in a fixed order so that one mesh always gives the same bits. "
        "positions float32[N,3]; loop_vertices uint32[L]; loop_starts, loop_totals uint32[P] "
        "(polygon p owns loops loop_starts[p] .. + loop_totals[p] - 1); face_normals "
        "float32[P,3].");
  py::enum_<RayKind>(m, "Visibility", py::arithmetic(),
                     "Kinds of ray an instance is visible to; combine with |.")
      .value("CAMERA", kCameraRay)
      .value("SHADOW", kShadowRay)
      .value("REFLECTION", kReflectionRay)
      .value("REFRACTION", kRefractionRay)
      .value("ALL", kAllRayKinds);

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
      .def_property_readonly("deforms", &Mesh::deforms)
      .def_property_readonly("vertex_count", &Mesh::vertex_count)
      .def_property_readonly("triangle_count", &Mesh::triangle_count)
      .def_property_readonly("curve_segment_count",
                             [](const Mesh& mesh) { return mesh.curves.segment_count(); })
      .def_property_readonly("point_count", [](const Mesh& mesh) { return mesh.points.count(); });

  py::class_<Scene>(m, "Scene",
                    "Meshes, instances, materials and lights keyed by name; setting a name "
                    "again replaces only that item.")
      .def(py::init<>())
      .def(
          "set_mesh",
          [](Scene& scene, const std::string& name, Mesh& mesh) {
            // A made Mesh always holds Embree's padding float; an empty one was moved.
            if (mesh.positions.empty()) {
              throw std::invalid_argument("the Mesh is empty: it was already set in a scene");
            }
            set_native_mesh(scene, name, std::move(mesh));
          },
          py::arg("name"), py::arg("mesh"),
          "Moves a Mesh into the scene (the Mesh is left empty) and builds its BVH.")
      .def(
          "set_mesh",
          [](Scene& scene, const std::string& name, const FloatArray& positions,
             const UintArray& triangles, const std::optional<FloatArray>& normals,
             const std::optional<IntArray>& material_slots, const std::optional<FloatArray>& uvs,
             const std::optional<FloatArray>& vertex_normals,
             const std::vector<FloatArray>& uv_sets, const std::vector<FloatArray>& attributes,
             const std::vector<FloatArray>& tangents) {
            set_native_mesh(scene, name,
                            mesh_from_arrays(positions, triangles, normals, material_slots, uvs,
                                             vertex_normals, uv_sets, attributes, tangents));
          },
          py::arg("name"), py::arg("positions"), py::arg("triangles"),
          py::arg("normals") = py::none(), py::arg("material_slots") = py::none(),
          py::arg("uvs") = py::none(), py::arg("vertex_normals") = py::none(),
          py::arg("uv_sets") = std::vector<FloatArray>{},
          py::arg("attributes") = std::vector<FloatArray>{},
          py::arg("tangents") = std::vector<FloatArray>{},
          "The same as set_mesh(name, Mesh(positions, triangles, ...)).")
      .def(
          "set_instance",
          [](Scene& s, const std::string& name, const std::string& mesh, const py::object& to_world,
             std::vector<std::string> materials, uint32_t visibility, bool holdout,
             const std::optional<std::array<float, 9>>& info,
             const std::optional<std::tuple<float, float, std::vector<float>>>& cryptomatte,
             const std::vector<py::object>& motion,
             const std::tuple<uint8_t, uint8_t, uint64_t, uint64_t>& links) {
            Instance instance{mesh, matrix_from_numpy(to_world), std::move(materials),
                              visibility & kAllRayKinds, holdout};
            const auto& [light_set, shadow_set, light_sets, shadow_sets] = links;
            if (light_set >= kMaxLightSets || shadow_set >= kMaxLightSets) {
              throw std::invalid_argument("a light or shadow set is 0 to 63");
            }
            instance.links = {light_set, shadow_set, light_sets, shadow_sets};
            for (const py::object& m : motion) instance.motion.push_back(matrix_from_numpy(m));
            if (info) {
              const std::array<float, 9>& i = *info;
              for (float v : i) {
                if (!std::isfinite(v)) throw std::invalid_argument("instance info must be finite");
              }
              instance.info = {Vec3(i[0], i[1], i[2]), i[3], i[4],
                               glm::vec4(i[5], i[6], i[7], i[8])};
            } else {
              instance.info.location = Vec3(instance.to_world[3]);
            }
            if (cryptomatte) {
              const auto& [object, asset, materials_ids] = *cryptomatte;
              instance.cryptomatte = {object, asset, materials_ids};
            }
            s.set_instance(name, std::move(instance));
          },
          py::arg("name"), py::arg("mesh"), py::arg("transform"),
          py::arg("materials") = std::vector<std::string>{},
          py::arg("visibility") = static_cast<uint32_t>(kAllRayKinds), py::arg("holdout") = false,
          py::arg("info") = py::none(), py::arg("cryptomatte") = py::none(),
          py::arg("motion") = std::vector<py::object>{},
          py::arg("links") = std::make_tuple(uint8_t{0}, uint8_t{0}, kAllLightSets, kAllLightSets),
          "transform: 4x4 row-major object to world; materials: material name per slot "
          "('' for the default material); visibility: Visibility flags of the rays that see "
          "it; holdout: camera rays that meet it give colour 0 and alpha 0; info: what the "
          "Object Info node reads, (x, y, z location, random, pass index, r, g, b, a colour) "
          "(None: the transform's location, random 0, index 0, white); cryptomatte: its "
          "Cryptomatte ids (object, asset, [material per slot]), floats (None: none); motion: "
          "its transforms (4x4 row-major) at evenly spaced times over the shutter, from its "
          "opening to its closing (motion blur; [] when it does not move); links: light linking, "
          "(light set, shadow set, light sets it lights, shadow sets that block it) as "
          "scene/light.h defines them.")
      .def(
          "set_world",
          [](Scene& s, const std::shared_ptr<Program>& program, uint32_t output) {
            s.set_world(program, output);
          },
          py::arg("program"), py::arg("output") = 0,
          "The world: rays that hit nothing see the program's register `output` (.xyz), "
          "evaluated by their direction; None: the constant background.")
      .def("set_material", &Scene::set_material, py::arg("name"), py::arg("material"))
      .def("set_light", &Scene::set_light, py::arg("name"), py::arg("light"))
      .def("set_texture", &Scene::set_texture, py::arg("name"), py::arg("texture"))
      .def("remove_mesh", &Scene::remove_mesh, py::arg("name"))
      .def("remove_instance", &Scene::remove_instance, py::arg("name"))
      .def("remove_material", &Scene::remove_material, py::arg("name"))
      .def("remove_light", &Scene::remove_light, py::arg("name"))
      .def("remove_texture", &Scene::remove_texture, py::arg("name"))
      .def_readwrite("camera", &Scene::camera,
                     "The view a RenderJob takes by default; not part of the compiled scene, "
                     "so changing it recompiles nothing.")
      .def_property(
          "background", &Scene::background,
          [](Scene& s, Vec3 c) {
            require_finite(c, "background");
            s.set_background(c);
          },
          "Radiance of a ray that hits nothing.")
      .def_property(
          "ambient", &Scene::ambient,
          [](Scene& s, Vec3 c) {
            require_finite(c, "ambient");
            s.set_ambient(c);
          },
          "Ambient light Ia; a material's ambient term is ka * Ia * kd.")
      .def_property_readonly("mesh_count", &Scene::mesh_count)
      .def_property_readonly("instance_count", &Scene::instance_count)
      .def_property_readonly("mesh_build_seconds", &Scene::mesh_build_seconds,
                             "Seconds spent in set_mesh building mesh BVHs, summed.")
      .def_property_readonly("top_level_builds", &Scene::top_level_builds,
                             "How many times this scene has built a top-level BVH: a render "
                             "after a camera, material, texture, light or world change reuses "
                             "the last one; a mesh or instance change builds a new one.");
}

}  // namespace whitted::python
