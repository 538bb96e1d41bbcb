// The only interface to Embree: a bottom-level BVH per mesh and a top-level BVH of
// instances. Embree 3 and 4 differ only inside embree.cpp.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "core/ray.h"
#include "scene/mesh.h"
#include "scene/motion.h"

namespace whitted {

struct Hit {
  float t = kInfinity;  // infinite: no hit
  // On a triangle, the barycentric weights of its vertices 1 and 2; on a curve segment, u
  // is the way along it (0 to 1); on a point, nothing.
  float u = 0.0f;
  float v = 0.0f;
  uint32_t instance = 0;
  uint32_t primitive = 0;  // in the mesh's one index space (Mesh::kind)
};

// An Embree device with its own error state; one per Scene (no globals).
class AccelDevice {
 public:
  AccelDevice();
  ~AccelDevice();
  AccelDevice(const AccelDevice&) = delete;
  AccelDevice& operator=(const AccelDevice&) = delete;
  void* handle() const { return device_; }
  // Throws std::runtime_error with Embree's message if a call this thread made on this
  // device failed since the last check; the error is cleared either way.
  void check(const char* what) const;

  // What Embree's error callback writes, in whichever thread failed, for check() to read.
  struct ErrorMessage {
    std::mutex mutex;
    std::string text;
  };

 private:
  void* device_ = nullptr;
  mutable ErrorMessage error_;
};

// A BVH over one mesh, in object space: its triangles, curves and points, each an Embree
// geometry of its own. Shares the mesh's arrays (the mesh must outlive it).
class MeshAccel {
 public:
  MeshAccel(std::shared_ptr<AccelDevice> device, const Mesh& mesh);
  ~MeshAccel();
  MeshAccel(const MeshAccel&) = delete;
  MeshAccel& operator=(const MeshAccel&) = delete;
  void* handle() const { return scene_; }
  // The mesh's primitive index (Mesh::kind) of Embree's primitive `id` of geometry
  // `geometry`.
  uint32_t primitive(uint32_t geometry, uint32_t id) const { return base_[geometry] + id; }

  static constexpr uint32_t kTriangleGeometry = 0;
  static constexpr uint32_t kCurveGeometry = 1;
  static constexpr uint32_t kPointGeometry = 2;

 private:
  std::shared_ptr<AccelDevice> device_;
  void* scene_ = nullptr;
  uint32_t base_[3] = {0, 0, 0};  // by geometry: where its primitives start
};

// One query as the integrator made it: a closest-hit or an any-hit (occlusion) ray.
// A render can record them so the same rays can be traced again by a bare Embree loop.
struct RayQuery {
  Ray ray;
  bool occlusion;
};

// Recorded queries in Embree's own ray layout (RTCRayHit, 80 bytes), ready for
// SceneAccel::trace_bare.
struct BareRays {
  struct alignas(16) Record {
    unsigned char bytes[80];
  };
  std::vector<Record> records;
  std::vector<uint8_t> occlusion;  // 1: an any-hit query (the record's ray part is used)
};

struct AccelInstance {
  // Shared, so the top-level BVH keeps alive the mesh BVHs (and the arrays they read) it
  // instances, however long a snapshot that shares it lives.
  std::shared_ptr<const MeshAccel> mesh;
  glm::mat4 to_world;
  uint32_t visibility;  // RayKind bits of the rays that see it
  // Its steps over the shutter (null: still), blended linearly at each ray's time.
  std::shared_ptr<const TransformMotion> motion;
};

// Shadow linking: what may block a shadow query, the instances whose shadow set (by
// instance index) is among `sets` (bit s: set s).
// Only Local (an Ambient Occlusion node's): `instance` alone may block.
struct Blockers {
  static constexpr uint32_t kEveryInstance = ~0u;
  const uint8_t* shadow_set = nullptr;  // null: no shadow sets
  uint64_t sets = ~uint64_t{0};
  uint32_t instance = kEveryInstance;
};

// The top-level BVH. Immutable once built; queries are thread-safe.
class SceneAccel {
 public:
  SceneAccel(std::shared_ptr<AccelDevice> device, const std::vector<AccelInstance>& instances);
  ~SceneAccel();
  SceneAccel(const SceneAccel&) = delete;
  SceneAccel& operator=(const SceneAccel&) = delete;

  // Closest hit in (ray.t_min, ray.t_max) among instances visible to ray.kind.
  bool intersect(const Ray& ray, Hit* hit) const;
  // Any hit in (ray.t_min, ray.t_max) among instances visible to ray.kind (and, given
  // `blockers`, among those it names).
  bool occluded(const Ray& ray, const Blockers* blockers = nullptr) const;
  // Closest hits of up to kIntersectPacketSize coherent rays (camera rays) traced together
  // as one packet (Embree walks the BVH once for all lanes); a miss leaves hits[i].t
  // infinite. Up to 4 rays go as a 4-wide packet, up to 8 as an 8-wide one, more as a
  // 16-wide one. This CPU has no AVX-512, yet 16-wide packets measured fastest per camera
  // ray (perf_camera_groups.py of commit d607207: demo, 2x2 samples, ns per camera ray
  // 95.4 single, 49.0 4-wide, 34.1 8-wide, 22.3 16-wide).
  static constexpr int kIntersectPacketSize = 16;
  void intersect_packet(const Ray* rays, int count, Hit* hits) const;
  // Any-hit tests of up to kPacketSize rays traced together: blocked[i] is what
  // occluded(rays[i]) answers. Shadow feelers leaving one point, or towards one light
  // from nearby points, share most of their BVH walk. A packet of up to 4 rays is traced
  // 4 wide (rtcOccluded4), a larger one 8 wide.
  static constexpr int kPacketSize = 8;
  void occluded_packet(const Ray* rays, int count, bool* blocked,
                       const Blockers* blockers = nullptr) const;

  // The benchmark baseline, in two steps so the conversion is not timed:
  // prepare_bare converts queries to Embree's layout, leaving out rays Embree cannot take
  // (see intersect); trace_bare traces them with a bare loop of single-ray Embree calls
  // (no shading, no checks) and returns how many it traced.
  static BareRays prepare_bare(const std::vector<RayQuery>& queries);
  size_t trace_bare(BareRays* rays) const;

 private:
  std::shared_ptr<AccelDevice> device_;
  std::vector<std::shared_ptr<const MeshAccel>> meshes_;
  void* scene_ = nullptr;
};

}  // namespace whitted
