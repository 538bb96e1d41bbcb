// The scene, keyed by stable names so one mesh, instance, material or light can be
// replaced without rebuilding the rest; and the immutable snapshot a render reads.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include "accel/embree.h"
#include "scene/camera.h"
#include "scene/light.h"
#include "scene/material.h"
#include "scene/mesh.h"
#include "scene/texture.h"

namespace whitted {

// A mesh together with its BVH; built once when the mesh is set, shared by instances.
struct MeshEntry {
  MeshEntry(std::shared_ptr<AccelDevice> device, Mesh m)
      : mesh(std::move(m)), accel(std::move(device), mesh) {}
  Mesh mesh;
  MeshAccel accel;
};

struct Instance {
  std::string mesh;
  glm::mat4 to_world{1.0f};
  std::vector<std::string> materials;  // by slot; "" is the default material
  uint32_t visibility = kAllRayKinds;  // RayKind bits of the rays that see it
  bool holdout = false;                // camera rays that meet it give colour 0, alpha 0
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
};

// A material's parameters at one point, textures applied.
struct SurfaceParams {
  Color diffuse;
  float alpha;
};

// What a render reads: resolved, immutable, safe to share between threads.
struct CompiledScene {
  struct Instance {
    std::shared_ptr<const MeshEntry> mesh;
    glm::mat4 to_world;
    glm::mat3 normal_to_world;        // inverse transpose of the linear part
    std::vector<uint32_t> materials;  // slot -> index into `materials`
    bool holdout;
    uint32_t visibility;  // RayKind bits
  };
  std::vector<Instance> instances;
  std::vector<Material> materials;  // index 0 is the default material
  std::vector<std::shared_ptr<const Texture>> textures;
  std::vector<Light> lights;
  Camera camera;
  Color background{0.0f};
  Color ambient{0.0f};
  std::unique_ptr<SceneAccel> accel;
  size_t degenerate_instances = 0;  // left out: transforms with (near) zero scale

  size_t triangle_count() const;
  Interaction interaction(const Ray& ray, const Hit& hit) const;
  // Texture coordinates at a hit; computed only for textured materials.
  TexturePoint texture_point(const Interaction& it) const;
  SurfaceParams surface(const Interaction& it) const;
};

class Scene {
 public:
  Scene();

  void set_mesh(const std::string& name, Mesh mesh);
  void set_instance(const std::string& name, Instance instance);
  void set_material(const std::string& name, const Material& material);
  void set_light(const std::string& name, const Light& light);
  void set_texture(const std::string& name, Texture texture);
  void remove_mesh(const std::string& name);
  void remove_instance(const std::string& name);
  void remove_material(const std::string& name);
  void remove_light(const std::string& name);
  void remove_texture(const std::string& name);

  Camera camera;
  Color background{0.05f};
  Color ambient{0.0f};

  // Resolves names and builds the top-level BVH; mesh BVHs were built by set_mesh.
  // Throws std::invalid_argument for an instance whose mesh or material is missing.
  std::shared_ptr<const CompiledScene> compile() const;

  size_t mesh_count() const { return meshes_.size(); }
  // Seconds spent copying meshes and building their BVHs in set_mesh, summed.
  double mesh_build_seconds() const { return mesh_build_seconds_; }
  size_t instance_count() const { return instances_.size(); }

 private:
  std::shared_ptr<AccelDevice> device_;
  // Ordered maps: the compiled order, and so the image, does not depend on insertion order.
  std::map<std::string, std::shared_ptr<const MeshEntry>> meshes_;
  std::map<std::string, Instance> instances_;
  std::map<std::string, Material> materials_;
  std::map<std::string, Light> lights_;
  std::map<std::string, std::shared_ptr<const Texture>> textures_;
  double mesh_build_seconds_ = 0.0;
};

}  // namespace whitted
