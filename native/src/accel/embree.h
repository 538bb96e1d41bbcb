// The only interface to Embree: a bottom-level BVH per mesh and a top-level BVH of
// instances. Embree 3 and 4 differ only inside embree.cpp.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "core/ray.h"
#include "scene/mesh.h"

namespace whitted {

struct Hit {
  float t = kInfinity;
  float u = 0.0f;  // barycentric weight of vertex 1
  float v = 0.0f;  // barycentric weight of vertex 2
  uint32_t instance = 0;
  uint32_t primitive = 0;
};

// An Embree device with its own error state; one per Scene (no globals).
class AccelDevice {
 public:
  AccelDevice();
  ~AccelDevice();
  AccelDevice(const AccelDevice&) = delete;
  AccelDevice& operator=(const AccelDevice&) = delete;
  void* handle() const { return device_; }
  // Throws std::runtime_error with Embree's message if an error was recorded.
  void check(const char* what) const;

 private:
  void* device_ = nullptr;
  std::string error_;
};

// A BVH over one mesh, in object space. Shares the mesh's arrays (the mesh must outlive it).
class MeshAccel {
 public:
  MeshAccel(std::shared_ptr<AccelDevice> device, const Mesh& mesh);
  ~MeshAccel();
  MeshAccel(const MeshAccel&) = delete;
  MeshAccel& operator=(const MeshAccel&) = delete;
  void* handle() const { return scene_; }

 private:
  std::shared_ptr<AccelDevice> device_;
  void* scene_ = nullptr;
};

struct AccelInstance {
  const MeshAccel* mesh;
  glm::mat4 to_world;
  uint32_t visibility;  // RayKind bits of the rays that see it
};

// The top-level BVH. Queries are thread-safe.
class SceneAccel {
 public:
  SceneAccel(std::shared_ptr<AccelDevice> device, const std::vector<AccelInstance>& instances);
  ~SceneAccel();
  SceneAccel(const SceneAccel&) = delete;
  SceneAccel& operator=(const SceneAccel&) = delete;

  // Closest hit in (ray.t_min, ray.t_max) among instances visible to ray.kind.
  bool intersect(const Ray& ray, Hit* hit) const;
  // Any hit in (ray.t_min, ray.t_max) among instances visible to ray.kind.
  bool occluded(const Ray& ray) const;

 private:
  std::shared_ptr<AccelDevice> device_;
  void* scene_ = nullptr;
};

}  // namespace whitted
