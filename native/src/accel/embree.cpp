// All Embree calls live here. Written for Embree 3 (Debian's); for Embree 4 change the
// include, the query calls (rtcIntersect1/rtcOccluded1 take optional arguments instead of
// an RTCIntersectContext) and set the geometry mask explicitly.
#include "accel/embree.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/type_ptr.hpp>
#include <mutex>
#include <stdexcept>

#include "core/limits.h"

namespace whitted {
namespace {

RTCDevice as_device(void* p) {
  return static_cast<RTCDevice>(p);
}
RTCScene as_scene(void* p) {
  return static_cast<RTCScene>(p);
}

// Embree reports errors through this callback, in the thread whose call failed; the
// latest message is kept for AccelDevice::check.
void on_error(void* user, RTCError code, const char* message) {
  auto* error = static_cast<AccelDevice::ErrorMessage*>(user);
  std::lock_guard lock(error->mutex);
  error->text = "Embree error " + std::to_string(static_cast<int>(code)) + ": " +
                (message != nullptr ? message : "");
}

// Embree asserts (and so aborts the whole process, Blender with it) on a ray whose
// origin or direction has a NaN or a component above FLT_LARGE (1.8e18), or whose
// interval is NaN (RayK::valid in Embree's kernels), also after an instance has moved the
// ray into object space. Such rays come only from absurd scenes: past
// limits::kMaxRayComponent from the origin they hit nothing here (instances are bounded
// too, scene.cpp; core/limits.h).
bool valid_for_embree(const Ray& ray) {
  constexpr float kLimit = limits::kMaxRayComponent;
  for (int i = 0; i < 3; ++i) {
    if (!(std::fabs(ray.origin[i]) <= kLimit) || !(std::fabs(ray.direction[i]) <= kLimit)) {
      return false;
    }
  }
  return !std::isnan(ray.t_min) && !std::isnan(ray.t_max) && ray.t_min >= 0.0f;
}

void to_embree(const Ray& ray, RTCRay* r) {
  r->org_x = ray.origin.x;
  r->org_y = ray.origin.y;
  r->org_z = ray.origin.z;
  r->dir_x = ray.direction.x;
  r->dir_y = ray.direction.y;
  r->dir_z = ray.direction.z;
  r->tnear = ray.t_min;
  r->tfar = ray.t_max;
  r->time = ray.time;
  r->mask = ray.kind;
  r->id = 0;
  r->flags = 0;
}

// An occlusion query's context under shadow linking: Embree hands the filter a pointer
// to `base`, the first member, for every hit it finds; hits on instances outside the
// blockers are turned down and the walk goes on.
struct BlockersContext {
  RTCIntersectContext base;
  Blockers blockers;
};

void skip_non_blockers(const RTCFilterFunctionNArguments* args) {
  const Blockers& blockers = reinterpret_cast<const BlockersContext*>(args->context)->blockers;
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const unsigned instance = RTCHitN_instID(args->hit, args->N, i, 0);
    if (blockers.instance != Blockers::kEveryInstance && instance != blockers.instance) {
      args->valid[i] = 0;
    } else if (blockers.shadow_set != nullptr &&
               ((blockers.sets >> blockers.shadow_set[instance]) & 1u) == 0) {
      args->valid[i] = 0;
    }
  }
}

// The context of an occlusion query: plain, or filtering by `blockers` when given.
BlockersContext occlusion_context(const Blockers* blockers) {
  BlockersContext context;
  rtcInitIntersectContext(&context.base);
  if (blockers != nullptr) {
    context.blockers = *blockers;
    context.base.filter = skip_non_blockers;
  }
  return context;
}

}  // namespace

static_assert(sizeof(BareRays::Record) == sizeof(RTCRayHit) &&
              alignof(BareRays::Record) >= alignof(RTCRayHit));

AccelDevice::AccelDevice() {
  RTCDevice device = rtcNewDevice(nullptr);
  if (device == nullptr) {
    throw std::runtime_error("Embree could not create a device (error " +
                             std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  }
  rtcSetDeviceErrorFunction(device, on_error, &error_);
  device_ = device;
}

AccelDevice::~AccelDevice() {
  rtcReleaseDevice(as_device(device_));
}

void AccelDevice::check(const char* what) const {
  // Embree keeps an error code per thread and device; rtcGetDeviceError returns the first
  // error since its last call and clears it (Embree 3 manual, rtcGetDeviceError), so a
  // later check cannot report this error again, nor one another thread caused.
  const RTCError code = rtcGetDeviceError(as_device(device_));
  if (code == RTC_ERROR_NONE) return;
  std::string message;
  {
    std::lock_guard lock(error_.mutex);
    message.swap(error_.text);
  }
  // The message is the latest any thread reported: the code is exact, the text is only
  // ours unless two threads failed at once.
  if (message.empty()) message = "Embree error " + std::to_string(static_cast<int>(code));
  throw std::runtime_error(std::string(what) + ": " + message);
}

MeshAccel::MeshAccel(std::shared_ptr<AccelDevice> device, const Mesh& mesh)
    : device_(std::move(device)) {
  RTCDevice d = as_device(device_->handle());
  RTCScene scene = rtcNewScene(d);
  // Robust mode: watertight-leaning intersectors, so rays do not slip through shared edges.
  // The context filter serves shadow linking (skip_non_blockers): Embree checks for it on
  // the scene whose geometry is hit, the mesh's, not the top level's alone.
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  if (mesh.triangle_count() > 0) {
    RTCGeometry geometry = rtcNewGeometry(d, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Shared buffers: Embree reads the mesh's own arrays (positions are padded by one float).
    if (mesh.deforms()) {
      // Deformation motion blur: one vertex buffer per time step, blended at the ray's time.
      const auto steps = static_cast<unsigned>(mesh.motion_positions.size());
      rtcSetGeometryTimeStepCount(geometry, steps);
      for (unsigned step = 0; step < steps; ++step) {
        rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, step, RTC_FORMAT_FLOAT3,
                                   mesh.motion_positions[step].data(), 0, 3 * sizeof(float),
                                   mesh.vertex_count());
      }
    } else {
      rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                 mesh.positions.data(), 0, 3 * sizeof(float), mesh.vertex_count());
    }
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                               mesh.triangles.data(), 0, 3 * sizeof(uint32_t),
                               mesh.triangle_count());
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(scene, geometry, kTriangleGeometry);
    rtcReleaseGeometry(geometry);  // the scene holds its own reference
  }
  if (mesh.curves.segment_count() > 0) {
    // Curves through the keys (x, y, z, radius): Catmull-Rom (Cycles' Thick), or linear
    // (Thick Linear); round, or flat ribbons facing the ray (Cycles' Ribbons), which Embree
    // keeps from meeting a ray within twice their radius of its origin (scene.cpp).
    const RTCGeometryType type =
        mesh.curves.flat ? (mesh.curves.linear ? RTC_GEOMETRY_TYPE_FLAT_LINEAR_CURVE
                                               : RTC_GEOMETRY_TYPE_FLAT_CATMULL_ROM_CURVE)
                         : (mesh.curves.linear ? RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE
                                               : RTC_GEOMETRY_TYPE_ROUND_CATMULL_ROM_CURVE);
    RTCGeometry curves = rtcNewGeometry(d, type);
    rtcSetSharedGeometryBuffer(curves, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                               mesh.curves.keys.data(), 0, 4 * sizeof(float),
                               mesh.curves.keys.size() / 4);
    rtcSetSharedGeometryBuffer(curves, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT,
                               mesh.curves.segments.data(), 0, sizeof(uint32_t),
                               mesh.curves.segment_count());
    rtcCommitGeometry(curves);
    rtcAttachGeometryByID(scene, curves, kCurveGeometry);
    rtcReleaseGeometry(curves);
  }
  if (mesh.points.count() > 0) {
    RTCGeometry points = rtcNewGeometry(d, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    rtcSetSharedGeometryBuffer(points, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                               mesh.points.spheres.data(), 0, 4 * sizeof(float),
                               mesh.points.count());
    rtcCommitGeometry(points);
    rtcAttachGeometryByID(scene, points, kPointGeometry);
    rtcReleaseGeometry(points);
  }
  // Hits number a mesh's primitives in one space: triangles, then segments, then points.
  base_[kTriangleGeometry] = 0;
  base_[kCurveGeometry] = static_cast<uint32_t>(mesh.triangle_count());
  base_[kPointGeometry] =
      static_cast<uint32_t>(mesh.triangle_count() + mesh.curves.segment_count());
  rtcCommitScene(scene);
  scene_ = scene;
  device_->check("building a mesh BVH");
}

MeshAccel::~MeshAccel() {
  rtcReleaseScene(as_scene(scene_));
}

SceneAccel::SceneAccel(std::shared_ptr<AccelDevice> device,
                       const std::vector<AccelInstance>& instances)
    : device_(std::move(device)) {
  meshes_.reserve(instances.size());
  for (const AccelInstance& instance : instances) meshes_.push_back(instance.mesh);
  RTCDevice d = as_device(device_->handle());
  RTCScene scene = rtcNewScene(d);
  // The context filter serves shadow linking (skip_non_blockers).
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  for (size_t i = 0; i < instances.size(); ++i) {
    RTCGeometry geometry = rtcNewGeometry(d, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(geometry, as_scene(instances[i].mesh->handle()));
    // Ray masks implement per-kind visibility: a ray sees an instance when the masks meet.
    rtcSetGeometryMask(geometry, instances[i].visibility);
    // glm matrices are column-major 4x4: exactly RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR. A
    // moving instance has one per time step; Embree blends neighbouring steps linearly
    // at the ray's time (TransformMotion::at does the same for the hit's shading).
    if (instances[i].motion) {
      const std::vector<glm::mat4>& steps = instances[i].motion->steps();
      rtcSetGeometryTimeStepCount(geometry, static_cast<unsigned>(steps.size()));
      for (size_t step = 0; step < steps.size(); ++step) {
        rtcSetGeometryTransform(geometry, static_cast<unsigned>(step),
                                RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, glm::value_ptr(steps[step]));
      }
    } else {
      rtcSetGeometryTransform(geometry, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR,
                              glm::value_ptr(instances[i].to_world));
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(scene, geometry, static_cast<unsigned>(i));
    rtcReleaseGeometry(geometry);
  }
  rtcCommitScene(scene);
  scene_ = scene;
  device_->check("building the scene BVH");
}

SceneAccel::~SceneAccel() {
  rtcReleaseScene(as_scene(scene_));
}

bool SceneAccel::intersect(const Ray& ray, Hit* hit) const {
  if (!valid_for_embree(ray)) return false;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  to_embree(ray, &rh.ray);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(as_scene(scene_), &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  hit->t = rh.ray.tfar;
  hit->u = rh.hit.u;
  hit->v = rh.hit.v;
  hit->instance = rh.hit.instID[0];
  hit->primitive = meshes_[hit->instance]->primitive(rh.hit.geomID, rh.hit.primID);
  return true;
}

bool SceneAccel::occluded(const Ray& ray, const Blockers* blockers) const {
  if (!valid_for_embree(ray)) return false;
  BlockersContext context = occlusion_context(blockers);
  RTCRay r;
  to_embree(ray, &r);
  rtcOccluded1(as_scene(scene_), &context.base, &r);
  // Embree sets tfar to -inf when the ray is blocked.
  return r.tfar < 0.0f;
}

namespace {

// Embree's packet rays (RTCRay4, 8 or 16), filled from up to K of ours; lanes past
// `count` and rays Embree cannot take (valid_for_embree) stay inactive.
template <int K, class Packet>
void to_embree_packet(const Ray* rays, int count, Packet* packet, int* valid) {
  for (int i = 0; i < K; ++i) {
    const Ray& ray = rays[std::min(i, count - 1)];
    valid[i] = i < count && valid_for_embree(ray) ? -1 : 0;
    packet->org_x[i] = ray.origin.x;
    packet->org_y[i] = ray.origin.y;
    packet->org_z[i] = ray.origin.z;
    packet->dir_x[i] = ray.direction.x;
    packet->dir_y[i] = ray.direction.y;
    packet->dir_z[i] = ray.direction.z;
    packet->tnear[i] = ray.t_min;
    packet->tfar[i] = ray.t_max;
    packet->time[i] = ray.time;
    packet->mask[i] = ray.kind;
    packet->id[i] = 0;
    packet->flags[i] = 0;
  }
}

// The first hits of up to K rays as one Embree packet (RTCRayHit4, 8 or 16).
template <int K, class PacketHit, class Intersect>
void intersect_k(RTCScene scene, const std::vector<std::shared_ptr<const MeshAccel>>& meshes,
                 const Ray* rays, int count, Hit* hits, Intersect intersect) {
  alignas(64) int valid[K];
  PacketHit rh;
  to_embree_packet<K>(rays, count, &rh.ray, valid);
  for (int i = 0; i < K; ++i) {
    rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
  }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  intersect(valid, scene, &context, &rh);
  for (int i = 0; i < count; ++i) {
    hits[i] = Hit{};
    if (valid[i] == 0 || rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) continue;
    hits[i].t = rh.ray.tfar[i];
    hits[i].u = rh.hit.u[i];
    hits[i].v = rh.hit.v[i];
    hits[i].instance = rh.hit.instID[0][i];
    hits[i].primitive = meshes[hits[i].instance]->primitive(rh.hit.geomID[i], rh.hit.primID[i]);
  }
}

}  // namespace

void SceneAccel::intersect_packet(const Ray* rays, int count, Hit* hits) const {
  static_assert(kIntersectPacketSize <= 16, "the widest packet below is RTCRayHit16");
  // The narrowest packet that holds them: in a wider one the idle lanes would go through
  // every node test.
  if (count <= 4) {
    intersect_k<4, RTCRayHit4>(as_scene(scene_), meshes_, rays, count, hits, rtcIntersect4);
  } else if (count <= 8) {
    intersect_k<8, RTCRayHit8>(as_scene(scene_), meshes_, rays, count, hits, rtcIntersect8);
  } else {
    intersect_k<16, RTCRayHit16>(as_scene(scene_), meshes_, rays, count, hits, rtcIntersect16);
  }
}

void SceneAccel::occluded_packet(const Ray* rays, int count, bool* blocked,
                                 const Blockers* blockers) const {
  static_assert(kPacketSize == 8, "the widest packet below is RTCRay8");
  BlockersContext linked = occlusion_context(blockers);
  RTCIntersectContext* context = &linked.base;
  // An inactive lane is left unblocked, as occluded() answers for a ray it cannot take.
  if (count <= 4) {
    alignas(16) int valid[4];
    RTCRay4 r;
    to_embree_packet<4>(rays, count, &r, valid);
    rtcOccluded4(valid, as_scene(scene_), context, &r);
    for (int i = 0; i < count; ++i) blocked[i] = valid[i] != 0 && r.tfar[i] < 0.0f;
  } else {
    alignas(32) int valid[8];
    RTCRay8 r;
    to_embree_packet<8>(rays, count, &r, valid);
    rtcOccluded8(valid, as_scene(scene_), context, &r);
    for (int i = 0; i < count; ++i) blocked[i] = valid[i] != 0 && r.tfar[i] < 0.0f;
  }
}

BareRays SceneAccel::prepare_bare(const std::vector<RayQuery>& queries) {
  BareRays out;
  out.records.reserve(queries.size());
  out.occlusion.reserve(queries.size());
  for (const RayQuery& q : queries) {
    if (!valid_for_embree(q.ray)) continue;
    auto* rh = reinterpret_cast<RTCRayHit*>(&out.records.emplace_back());
    to_embree(q.ray, &rh->ray);
    rh->hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    out.occlusion.push_back(q.occlusion ? 1 : 0);
  }
  return out;
}

size_t SceneAccel::trace_bare(BareRays* rays) const {
  RTCScene scene = as_scene(scene_);
  const size_t n = rays->records.size();
  for (size_t i = 0; i < n; ++i) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    auto* rh = reinterpret_cast<RTCRayHit*>(&rays->records[i]);
    if (rays->occlusion[i] != 0) {
      rtcOccluded1(scene, &context, &rh->ray);
    } else {
      rtcIntersect1(scene, &context, rh);
    }
  }
  return n;
}

}  // namespace whitted
