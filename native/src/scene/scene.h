// The scene, keyed by stable names so one mesh, instance, material or light can be
// replaced without rebuilding the rest; and the immutable snapshot a render reads.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include "accel/embree.h"
#include "scene/camera.h"
#include "scene/displace.h"
#include "scene/light.h"
#include "scene/material.h"
#include "scene/mesh.h"
#include "scene/motion.h"
#include "scene/texture.h"
#include "scene/volume_object.h"
#include "scene/world_light.h"

namespace whitted {

class MeshLights;

// to_world * (p, 1) without the fourth row, in glm's order of operations, (m0 x + m1 y) +
// (m2 z + m3), so the point is glm's to the bit.
inline Vec3 transform_point(const glm::mat4& m, const Vec3& p) {
  return (Vec3(m[0]) * p.x + Vec3(m[1]) * p.y) + (Vec3(m[2]) * p.z + Vec3(m[3]));
}

// A mesh together with its BVH; built once when the mesh is set, shared by instances.
struct MeshEntry {
  MeshEntry(std::shared_ptr<AccelDevice> device, Mesh m)
      : mesh(std::move(m)),
        accel(std::move(device), mesh),
        box(bounding_box(mesh)),
        bounds(bounding_sphere(mesh)),
        slots(slot_count(mesh)) {}
  Mesh mesh;
  MeshAccel accel;
  Box box;        // in object space
  Sphere bounds;  // in object space
  size_t slots;   // slot_count(mesh)
};

// What Blender's Object Info node reports of an instance.
struct InstanceInfo {
  Vec3 location{0.0f};
  float random = 0.0f;
  float pass_index = 0.0f;
  glm::vec4 color{1.0f};
};

// The Cryptomatte ids of an instance (float32 hashes of Blender's names, made by
// addon/cryptomatte.py): its object's, its asset's (the object's topmost parent) and
// its materials', by slot. 0 is no id.
struct CryptomatteIds {
  float object = 0.0f;
  float asset = 0.0f;
  std::vector<float> materials;
};

// An instance's light linking (light.h): its sets as a receiver and a blocker, and, when
// its material emits, the sets it lights and the shadow sets that cast its shadows.
struct InstanceLinks {
  uint8_t light_set = 0;
  uint8_t shadow_set = 0;
  uint64_t light_sets = kAllLightSets;
  uint64_t shadow_sets = kAllLightSets;
  bool linked() const {
    return light_set != 0 || shadow_set != 0 || light_sets != kAllLightSets ||
           shadow_sets != kAllLightSets;
  }
};

struct Instance {
  std::string mesh;
  glm::mat4 to_world{1.0f};
  std::vector<std::string> materials;  // by slot; "" is the default material
  uint32_t visibility = kAllRayKinds;  // RayKind bits of the rays that see it
  bool holdout = false;                // camera rays that meet it give colour 0, alpha 0
  // Camera rays that meet it show only the shadows the other objects cast on it
  // (integrator/catcher.h).
  bool shadow_catcher = false;
  InstanceInfo info;
  // Its Object and Instancer attributes (the Attribute node's), RGBA, by the index a
  // material's program reads (kInputObjectAttribute + k); those past the end read 0.
  std::vector<glm::vec4> attributes;
  CryptomatteIds cryptomatte;
  // Its transform over the shutter (motion blur), sampled at evenly spaced times from its
  // opening to its closing; empty (or all one transform) when it does not move.
  std::vector<glm::mat4> motion;
  InstanceLinks links;
  // A Volume object's grids, which its material reads at points inside the mesh (the
  // object's VolumeObject::bound_mesh); null for every other instance.
  std::shared_ptr<const VolumeObject> volume;
};

// Where a ray met a surface, in world space.
struct Interaction {
  Vec3 position;
  Vec3 position_error;    // bound on the rounding error of `position`, per axis
  Vec3 geometric_normal;  // unit, as the triangle winds
  Vec3 shading_normal;    // unit, interpolated corner normals (or the geometric normal)
  // Where shadow feelers start: on smooth meshes the point is lifted towards the curved
  // surface the corner normals describe, so a coarse mesh shows no stair-step terminator
  // (Hanika, "Hacking the Shadow Terminator", Ray Tracing Gems II ch. 4).
  Vec3 shadow_origin;
  const Material* material;
  uint32_t material_index;
  bool holdout;
  // Where on the mesh, for texture coordinates (CompiledScene::texture_point).
  uint32_t instance;
  uint32_t primitive;
  Vec3 local_position;    // object space
  glm::vec2 barycentric;  // weights of the triangle's vertices 1 and 2
  float time;             // of the ray that met it, in the shutter (Ray::time)
};

// Every Whitted field of a material at one hit, textures and program applied: what the
// integrator shades with.
struct SurfaceParams {
  Color diffuse;
  Color specular;
  float shininess;
  Color reflectivity;    // sigma_r before the Fresnel split (integrator/split.h)
  Color transmissivity;  // sigma_t before the Fresnel split
  float ior;
  Color emission;
  float alpha;  // clamped to [0, 1]
  Vec3 normal;  // unit shading normal, on the geometric normal's side (Interaction)
  float coat_specular;
  float coat_reflectivity;
  float coat_shininess;
  float coat_ior;
  Vec3 coat_normal;          // as `normal`: the interpolated normal unless a program drives it
  float diffuse_roughness;   // shapes a DiffuseModel::kBurley lobe; in [0, 1]
  float roughness;           // Blender's roughness of the reflection lobe, in [0, 1]
  float coat_roughness;      // the coat's, likewise
  float anisotropy;          // the reflection lobe's (Material::anisotropy)
  Vec3 tangent;              // the lobe's tangent (world); zero: none, the lobe is round
  Color sheen;               // the sheen lobe's weight (Material::sheen)
  float sheen_roughness;     // its sigma, in [0, 1]
  Color layer_reflectivity;  // the specular layer beneath the coat (Material::layer_*)
  float layer_ior;
};

// A material's fields before its textures and program: CompiledScene::material_constants
// (scene/surface.cpp).
SurfaceParams constant_surface(const Material& m);

// A medium's coefficients at one point, per Blender unit of length (a material's volume_*
// fields: integrator/volume.h, heterogeneous.h).
struct Medium {
  Color absorption{0.0f};   // sigma_a
  Color scattering{0.0f};   // sigma_s
  Color emission{0.0f};     // radiance emitted per unit of length
  float anisotropy = 0.0f;  // Henyey-Greenstein g
  // sigma_t = sigma_a + sigma_s.
  Color extinction() const { return absorption + scattering; }
  // Nothing to absorb, scatter or emit.
  bool empty() const { return is_black(absorption) && is_black(scattering) && is_black(emission); }
};

// The integrator's side of the rays a program traces from a hit (shader/program.h
// HitRays, made of this by scene/surface.cpp): its queries, counted, and its points.
class TracedRays {
 public:
  // Whether anything ray.kind sees meets `ray` (with `instance`, only that instance).
  virtual bool occluded(const Ray& ray, const uint32_t* instance) const = 0;
  // The closest hit of `ray` among what ray.kind sees (a bevel's probe).
  virtual bool intersect(const Ray& ray, Hit* hit) const = 0;
  // HitRays::point.
  virtual glm::vec2 point(int k, int count) const = 0;

 protected:
  ~TracedRays() = default;
};

// What the integrator knows of a ray beyond the ray itself, for the inputs of a program:
// the render's camera (camera and window coordinates) and the ray's depth in its tree.
struct RayContext {
  const Camera* camera;
  int depth;
  // Where the integrator lets a program trace rays from the hit (its ray-traced nodes);
  // null elsewhere.
  const TracedRays* rays = nullptr;
};

// What a render reads: resolved, immutable, safe to share between threads. The camera is
// not part of it (a render takes its own), so moving the camera recompiles nothing.
// Where an instance is at one moment: its transform and what hits carried through it
// read, made once per transform.
struct Placement {
  glm::mat4 to_world{1.0f};
  glm::mat3 normal_to_world{1.0f};  // inverse transpose of the linear part
  // |linear part| and |translation|, element by element: the error bound of every hit
  // point carried through to_world reads them (interaction).
  glm::mat3 abs_linear{1.0f};
  Vec3 abs_translation{0.0f};
  static Placement of(const glm::mat4& to_world);
};

// The largest world light map a side, texels (Cycles' Map Resolution goes to 8192).
inline constexpr int kMaxWorldMap = 8192;

struct CompiledScene {
  struct Instance {
    std::shared_ptr<const MeshEntry> mesh;
    Placement placement;  // at the shutter's opening (the frame's, without motion blur)
    // Its motion over the shutter; null when it does not move.
    std::shared_ptr<const TransformMotion> motion;
    std::vector<uint32_t> materials;  // slot -> index into `materials`
    bool holdout;
    bool shadow_catcher;  // the Instance's
    // RayKind bits: the Instance's, or 0 (seen by no ray) when none of its primitives has
    // a surface (Material::surface): a volume's bounds, in its BVH still.
    uint32_t visibility;
    InstanceInfo info;
    std::string name;  // the Scene's key, for what reports name it (the inspector)
    // The Instance's attributes.
    std::vector<glm::vec4> attributes;
    CryptomatteIds cryptomatte;
    InstanceLinks links;
    // Its mesh's box carried to the world (the box of the eight corners placed): where a
    // medium it bounds can be, and its marching step (integrator/heterogeneous.h).
    Box world_box;
    std::shared_ptr<const VolumeObject> volume;  // the Instance's
  };
  std::vector<Instance> instances;
  bool moves = false;               // whether any instance moves or deforms within the shutter
  std::vector<Material> materials;  // index 0 is the default material
  // By material: its fields as constants, alpha clamped, normals unset; surface() starts
  // from these, so a material without textures or program costs a copy per hit.
  std::vector<SurfaceParams> material_constants;
  std::vector<std::string> material_names;  // by index; "" for the default material
  std::vector<std::string> light_names;     // by index into `lights`
  std::vector<std::shared_ptr<const Texture>> textures;
  std::vector<Light> lights;
  // The RayKind bits of the rays that see some lamp's shape (Light::visibility of those
  // with one): 0 where none does, and no ray looks for lamps.
  uint32_t lamps_visibility = 0;
  // The media that glow (Material::glows, in a mesh without a surface), each by the
  // sphere around its instance's box over the shutter: where a surface's glow feelers
  // aim (integrator/lights.h).
  struct Glow {
    uint32_t instance;
    Vec3 centre;
    float radius;
  };
  std::vector<Glow> glowing;
  // The emissive meshes shadow feelers sample (scene/mesh_light.h); never null.
  std::shared_ptr<const MeshLights> mesh_lights;
  Color background{0.0f};  // where there is no world program
  // Ia of the Phong ambient term: the scene's, or with a world program its strength
  // times world_upward_mean().
  Color ambient{0.0f};
  // The world: a program whose register `world_output` is the radiance of a ray that
  // misses, by direction (null: `background`); its images resolved like a material's.
  std::shared_ptr<const Program> world;
  uint32_t world_output = 0;
  std::vector<const ImageTexture*> world_images;
  // The world as a light (scene/world_light.h): null where it lights nothing (then the
  // ambient term stands for it); `world_light_params` as the exporter asked, its `why`
  // the report's reason.
  std::shared_ptr<const WorldLight> world_light;
  WorldLightParams world_light_params;
  // The RayKind bits of the rays that see the world where they escape (World > Ray
  // Visibility: Camera, Glossy for reflected rays, Transmission for refracted ones);
  // the others see black.
  uint32_t world_visibility = kCameraRay | kReflectionRay | kRefractionRay;
  // The world's Volume output (Scene::set_world_medium): a medium filling all space,
  // added to whatever media a point is inside (integrator/transmittance.h), where it is
  // participating().
  Material world_medium;
  // Shared by successive snapshots while no mesh or instance changes.
  std::shared_ptr<const SceneAccel> accel;
  size_t degenerate_instances = 0;  // left out: transforms with (near) zero scale
  // Light linking: whether any lamp or instance is linked (light.h), and each instance's
  // shadow set, for the shadow queries of a light that only some sets block.
  bool light_linking = false;
  std::vector<uint8_t> shadow_sets;

  size_t triangle_count() const;
  // The `materials` index of an instance's triangle (its slot's, 0 past the slots).
  uint32_t material_index(uint32_t instance, uint32_t primitive) const {
    const Instance& in = instances[instance];
    const size_t slot = in.mesh->mesh.slot(primitive);
    return slot < in.materials.size() ? in.materials[slot] : 0;
  }
  Interaction interaction(const Ray& ray, const Hit& hit) const;
  // interaction() of a hit on a curve segment or a point, the instance placed `at`.
  Interaction round_interaction(const Ray& ray, const Hit& hit, const Placement& at) const;
  // What every interaction() says of its hit besides the geometry: the material, the
  // instance and primitive, the object-space point `local`, the barycentrics, the time.
  void identify(const Ray& ray, const Hit& hit, const Vec3& local, Interaction* out) const;
  // Texture coordinates at a hit; computed only for textured materials.
  TexturePoint texture_point(const Interaction& it) const;
  // The material's fields at a hit of `ray`: its constants, unless textures or a program
  // drive them (then evaluated here, once).
  SurfaceParams surface(const Interaction& it, const Ray& ray, const RayContext& context) const;
  // The medium that material `material` fills, inside instance `instance`'s mesh, at world
  // point `x` of `ray`: the material's constants, or where its program drives them
  // (Material::heterogeneous) the program run at x (scene/surface.cpp). The one question
  // the integrator asks of a medium at a point.
  Medium medium(uint32_t material, uint32_t instance, const Vec3& x, const Ray& ray,
                const RayContext& context) const;
  // Radiance arriving along a ray that hits nothing.
  Color world_radiance(const Ray& ray, const RayContext& context) const;
  // The world's radiance averaged over the upper hemisphere (+Z) with weight cos(theta)/pi:
  // E/pi of a surface facing up, which a uniform sky's radiance equals. Quadrature over
  // kAmbientCells^2 directions, each read as a diffuse ray one bounce deep sees it.
  Color world_upward_mean() const;
  // The world's radiance towards `direction` as a diffuse ray `depth` bounces deep sees
  // it: what a feeler to the world brings (scene/world_light.h).
  Color world_light_radiance(const Vec3& direction, int depth) const;
  static constexpr int kAmbientCells = 24;
};

// Every method may be called from any thread (Python calls some without the GIL): the
// scene's state is guarded by one mutex. The camera is a plain value, read by whoever
// starts a render, and no part of the compiled snapshot.
class Scene {
 public:
  Scene();
  // A copy shares the meshes (immutable) and starts from the same compile cache and count.
  Scene(const Scene& other);
  Scene& operator=(const Scene&) = delete;

  // A mesh or instance change invalidates the top-level BVH; a material, texture, light,
  // background, world or ambient change only the snapshot, which the next compile() resolves
  // again around the existing top-level BVH.
  void set_mesh(const std::string& name, Mesh mesh);
  // Moves `mesh`'s vertices by `slots` (scene/displace.h displace, a slot without a
  // program moves none), the images their programs sample resolved among this scene's
  // textures (SlotDisplacement::images filled here); how many vertices moved. Throws
  // std::invalid_argument for a texture the scene does not have.
  size_t displace(Mesh* mesh, std::vector<SlotDisplacement> slots, const glm::mat4& to_world) const;
  void set_instance(const std::string& name, Instance instance);
  void set_material(const std::string& name, const Material& material);
  void set_light(const std::string& name, const Light& light);
  void set_texture(const std::string& name, Texture texture);
  void remove_mesh(const std::string& name);
  void remove_instance(const std::string& name);
  void remove_material(const std::string& name);
  void remove_light(const std::string& name);
  void remove_texture(const std::string& name);
  void set_background(const Color& background);
  // The world program and the register holding its radiance (null: the background);
  // throws std::invalid_argument for a register out of range. With a program, the
  // ambient light is `ambient_strength` times its upward mean (CompiledScene).
  void set_world(std::shared_ptr<const Program> program, uint32_t output,
                 float ambient_strength = 1.0f);
  // Whether and how the world lights surfaces (scene/world_light.h); its map is built by
  // the next compile() and kept while neither the world, its textures nor these change.
  void set_world_light(const WorldLightParams& params);
  // Which rays see the world (CompiledScene::world_visibility): RayKind bits among
  // camera, reflection and refraction; others are ignored.
  void set_world_visibility(uint32_t kinds);
  // The world's Volume output as a material of no surface whose volume_* coefficients
  // fill all space (a default Material: none).
  void set_world_medium(const Material& medium);
  WorldLightParams world_light_params() const;
  // The ambient light Ia of a world without program.
  void set_ambient(const Color& ambient);
  Color background() const;
  // The ambient light a render uses: set_ambient's, or the world program's (compiles).
  Color ambient() const;

  Camera camera;

  // The snapshot a render reads: the last one again while nothing changed since, else
  // names resolved anew, the top-level BVH rebuilt only when a mesh or instance changed
  // or an instance's shadow mask did (a material turned translucent or opaque); mesh
  // BVHs were built by set_mesh. `built_top_level`, when given, says whether this call
  // built one; `world_light_seconds`, the seconds it spent building the world light's
  // map (0 when it kept the last one). Throws std::invalid_argument for an instance whose
  // mesh or material is missing (and keeps nothing of that attempt).
  std::shared_ptr<const CompiledScene> compile(bool* built_top_level = nullptr,
                                               double* world_light_seconds = nullptr) const;

  size_t mesh_count() const;
  // Seconds spent copying meshes and building their BVHs in set_mesh, summed.
  double mesh_build_seconds() const;
  size_t instance_count() const;
  // How many times compile() has built a top-level BVH for this scene.
  uint64_t top_level_builds() const;
  // How many times compile() has built the world light (scene/world_light.h): once per
  // world, its images and its settings, whatever else changes.
  uint64_t world_light_builds() const;

 private:
  // Marks the snapshot stale, and with `geometry` the top-level BVH too. Needs mutex_.
  void changed(bool geometry);
  // Marks the snapshot and the world light's map stale. Needs mutex_.
  void world_changed();
  // Whether the world's program reads texture `name`. Needs mutex_.
  bool world_reads(const std::string& name) const;

  std::shared_ptr<AccelDevice> device_;
  mutable std::mutex mutex_;  // guards state_
  struct State {
    // Ordered maps: the compiled order, and so the image, does not depend on insertion
    // order.
    std::map<std::string, std::shared_ptr<const MeshEntry>> meshes;
    std::map<std::string, Instance> instances;
    std::map<std::string, Material> materials;
    std::map<std::string, Light> lights;
    std::map<std::string, std::shared_ptr<const Texture>> textures;
    Color background{0.05f};
    Color ambient{0.0f};
    std::shared_ptr<const Program> world;
    uint32_t world_output = 0;
    float world_ambient_strength = 1.0f;
    WorldLightParams world_light_params;
    uint32_t world_visibility = kCameraRay | kReflectionRay | kRefractionRay;
    Material world_medium;
    std::shared_ptr<const WorldLight> world_light;  // the last one built (null: stale)
    bool world_light_built = false;
    double mesh_build_seconds = 0.0;
    // The compile cache: the last snapshot (null once anything changed), and the
    // top-level BVH with the instance masks it was built with (null once geometry changed).
    std::shared_ptr<const CompiledScene> snapshot;
    std::shared_ptr<const SceneAccel> accel;
    std::vector<uint32_t> accel_masks;
    uint64_t top_level_builds = 0;
    uint64_t world_light_builds = 0;
  };
  mutable State state_;  // mutable: compile(), const to its callers, fills the cache
};

}  // namespace whitted
