#include "scene/scene.h"

#include "bindings.h"
#include "shader/ops.h"

namespace whitted::python {
namespace {
// Moves `mesh` into the scene under `name` and builds its BVH, without the GIL.
void set_native_mesh(Scene& scene, const std::string& name, Mesh mesh) {
  py::gil_scoped_release release;
  scene.set_mesh(name, std::move(mesh));
}

}  // namespace

void bind_scene(py::module_& m) {
  py::enum_<RayKind>(m, "RayVisibility", py::arithmetic(),
                     "Kinds of ray an instance is visible to; combine with |.")
      .value("CAMERA", kCameraRay)
      .value("SHADOW", kShadowRay)
      .value("REFLECTION", kReflectionRay)
      .value("REFRACTION", kRefractionRay)
      .value("ALL", kAllRayKinds);

  py::class_<Scene>(m, "Scene",
                    "Meshes, instances, materials, textures and lights keyed by name; setting a "
                    "name again replaces only that item. A running RenderJob keeps its own "
                    "snapshot, so the scene may be edited while it renders.")
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
          "displace",
          [](const Scene& scene, Mesh& mesh,
             const std::vector<std::optional<std::tuple<std::shared_ptr<Program>, uint32_t, bool>>>&
                 slots,
             const py::object& to_world) {
            std::vector<SlotDisplacement> native;
            for (const auto& slot : slots) {
              SlotDisplacement d;
              if (slot) {
                d.program = std::get<0>(*slot);
                d.output = std::get<1>(*slot);
                d.renormal = std::get<2>(*slot);
              }
              native.push_back(std::move(d));
            }
            const glm::mat4 matrix = matrix_from_numpy(to_world);
            py::gil_scoped_release release;
            return scene.displace(&mesh, std::move(native), matrix);
          },
          py::arg("mesh"), py::arg("slots"), py::arg("to_world"),
          "Moves a Mesh's vertices as Cycles' true displacement does (scene/displace.h), "
          "before set_mesh: `slots` per material slot, None (it moves nothing) or (Program, "
          "the register of its world displacement, whether the moved faces' vertex normals "
          "are made again: Displacement Only); `to_world` the object's 4x4 transform. Its "
          "images are this scene's textures. How many vertices moved.")
      .def(
          "set_instance",
          [](Scene& s, const std::string& name, const std::string& mesh, const py::object& to_world,
             std::vector<std::string> materials, uint32_t visibility, bool holdout,
             bool shadow_catcher, const std::optional<std::array<float, 9>>& info,
             const std::optional<std::tuple<float, float, std::vector<float>>>& cryptomatte,
             const std::vector<py::object>& motion,
             const std::tuple<uint8_t, uint8_t, uint64_t, uint64_t>& links,
             std::shared_ptr<VolumeObject> volume,
             const std::vector<std::array<float, 4>>& attributes) {
            Instance instance{mesh, matrix_from_numpy(to_world), std::move(materials),
                              visibility & kAllRayKinds, holdout};
            instance.shadow_catcher = shadow_catcher;
            instance.volume = std::move(volume);
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
            if (attributes.size() > kObjectAttributes) {
              throw std::invalid_argument("an instance carries at most " +
                                          std::to_string(kObjectAttributes) + " attributes");
            }
            for (const std::array<float, 4>& a : attributes) {
              for (float v : a) {
                if (!std::isfinite(v)) {
                  throw std::invalid_argument("instance attributes must be finite");
                }
              }
              instance.attributes.emplace_back(a[0], a[1], a[2], a[3]);
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
          py::arg("shadow_catcher") = false, py::arg("info") = py::none(),
          py::arg("cryptomatte") = py::none(), py::arg("motion") = std::vector<py::object>{},
          py::arg("links") = std::make_tuple(uint8_t{0}, uint8_t{0}, kAllLightSets, kAllLightSets),
          py::arg("volume") = py::none(),
          py::arg("attributes") = std::vector<std::array<float, 4>>{},
          "transform: 4x4 row-major object to world; materials: material name per slot "
          "('' for the default material); visibility: RayVisibility flags of the rays that see "
          "it; holdout: camera rays that meet it give colour 0 and alpha 0; shadow_catcher: camera "
          "rays that meet it show only the shadows the other objects cast on it; info: what the "
          "Object Info node reads, (x, y, z location, random, pass index, r, g, b, a colour) "
          "(None: the transform's location, random 0, index 0, white); cryptomatte: its "
          "Cryptomatte ids (object, asset, [material per slot]), floats (None: none); motion: "
          "its transforms (4x4 row-major) at evenly spaced times over the shutter, from its "
          "opening to its closing (motion blur; [] when it does not move); links: light linking, "
          "(light set, shadow set, light sets it lights, shadow sets that block it) as "
          "scene/light.h defines them; volume: a Volume object's VolumeObject, whose grids its "
          "materials read inside its mesh (None for a mesh); attributes: its Object and "
          "Instancer attributes (r, g, b, a), by the index its materials' programs read "
          "(IN_OBJECT_ATTRIBUTE + k, at most OBJECT_ATTRIBUTES).")
      .def(
          "set_world",
          [](Scene& s, const std::shared_ptr<Program>& program, uint32_t output,
             float ambient_strength) { s.set_world(program, output, ambient_strength); },
          py::arg("program"), py::arg("output") = 0, py::arg("ambient_strength") = 1.0f,
          "The world: rays that hit nothing see the program's register `output` (.xyz), "
          "evaluated by their direction; None: the constant background. With a program, the "
          "ambient light Ia is ambient_strength times the program's radiance averaged over "
          "the upper hemisphere with weight cos(theta)/pi (what a uniform sky's radiance "
          "equals; 24 x 24 directions).")
      .def(
          "set_world_light",
          [](Scene& s, bool on, const std::string& why, int width, int height, bool diffuse,
             bool glossy, int max_bounces, Vec3 sun_direction, float sun_angle) {
            WorldLightParams params;
            params.on = on;
            params.why = why;
            params.width = width;
            params.height = height;
            params.diffuse = diffuse;
            params.glossy = glossy;
            params.max_bounces = max_bounces;
            params.sun_direction = sun_direction;
            params.sun_angle = sun_angle;
            s.set_world_light(params);
          },
          py::arg("on"), py::arg("why") = "", py::arg("width") = 0, py::arg("height") = 0,
          py::arg("diffuse") = true, py::arg("glossy") = true, py::arg("max_bounces") = 1024,
          py::arg("sun_direction") = Vec3(0.0f, 0.0f, 1.0f), py::arg("sun_angle") = 0.0f,
          "The world as a light (native scene/world_light.h): `on`, feelers go to it from "
          "every shading point (`why`: the effects report's words either way); an importance "
          "map of width x height texels over directions (0 x 0: none, a world of one colour, "
          "drawn by the cosine); whether it lights diffuse lobes and shows in glossy ones; "
          "the bounces it lights; a sky's sun disc (unit direction towards it, angular "
          "diameter in radians, 0: none), sampled apart. Raises ValueError for a map over "
          "8192 a side or a non-finite sun.")
      .def(
          "set_world_visibility",
          [](Scene& s, bool camera, bool glossy, bool transmission) {
            s.set_world_visibility((camera ? kCameraRay : 0u) | (glossy ? kReflectionRay : 0u) |
                                   (transmission ? kRefractionRay : 0u));
          },
          py::arg("camera") = true, py::arg("glossy") = true, py::arg("transmission") = true,
          "Which rays see the world where they escape (World > Ray Visibility): camera rays, "
          "reflected (mirror and glossy) rays, refracted rays; the others see black.")
      .def_property_readonly(
          "world_light",
          [](const Scene& s) {
            const auto compiled = s.compile();
            py::dict out;
            const WorldLight* light = compiled->world_light.get();
            out["on"] = light != nullptr;
            out["why"] = compiled->world_light_params.why;
            out["map"] = light != nullptr && light->has_map()
                             ? py::object(py::make_tuple(compiled->world_light_params.width,
                                                         compiled->world_light_params.height))
                             : py::object(py::none());
            out["bytes"] = light != nullptr ? light->bytes() : size_t{0};
            return out;
          },
          "What the last compile built of the world light: {on, why, map: (width, height) "
          "or None, bytes}.")
      .def("set_world_medium", &Scene::set_world_medium, py::arg("medium"),
           "The world's Volume output: a material of no surface whose volume coefficients "
           "fill all space (a default Material: none).")
      .def("set_material", &Scene::set_material, py::arg("name"), py::arg("material"),
           "Adds or replaces the material instances name by this one.")
      .def("set_light", &Scene::set_light, py::arg("name"), py::arg("light"),
           "Adds or replaces the light of this name.")
      .def("set_texture", &Scene::set_texture, py::arg("name"), py::arg("texture"),
           "Adds or replaces the texture materials and programs name by this one.")
      .def("remove_mesh", &Scene::remove_mesh, py::arg("name"),
           "Removes the mesh of this name (ValueError if there is none).")
      .def("remove_instance", &Scene::remove_instance, py::arg("name"),
           "Removes the instance of this name (ValueError if there is none).")
      .def("remove_material", &Scene::remove_material, py::arg("name"),
           "Removes the material of this name (ValueError if there is none).")
      .def("remove_light", &Scene::remove_light, py::arg("name"),
           "Removes the light of this name (ValueError if there is none).")
      .def("remove_texture", &Scene::remove_texture, py::arg("name"),
           "Removes the texture of this name (ValueError if there is none).")
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
          "Ambient light Ia of a world without program; a material's ambient term is "
          "ka * Ia * kd. Read: the Ia a render uses (with a world program, set_world's).")
      .def_property_readonly("mesh_count", &Scene::mesh_count, "How many meshes it holds.")
      .def_property_readonly("instance_count", &Scene::instance_count,
                             "How many instances it holds.")
      .def_property_readonly("mesh_build_seconds", &Scene::mesh_build_seconds,
                             "Seconds spent in set_mesh building mesh BVHs, summed.")
      .def_property_readonly("top_level_builds", &Scene::top_level_builds,
                             "How many times this scene has built a top-level BVH: a render "
                             "after a camera, material, texture, light or world change reuses "
                             "the last one; a mesh or instance change builds a new one.")
      .def_property_readonly("world_light_builds", &Scene::world_light_builds,
                             "How many times this scene has built its world light (the "
                             "importance map): a change of the world, an image it reads or "
                             "set_world_light builds it anew at the next compile; any other "
                             "edit keeps it.");
}

}  // namespace whitted::python
