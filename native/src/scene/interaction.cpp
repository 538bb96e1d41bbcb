// Where a ray met a surface: CompiledScene::interaction for triangles, curves and points.
#include "scene/scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/matrix.hpp>
#include <variant>

#include "core/limits.h"
#include "scene/mesh_light.h"

namespace whitted {

namespace {

// The centre and radius of a Catmull-Rom segment through keys k0..k3 (x, y, z, radius) at
// u in [0, 1] (the uniform Catmull-Rom basis, as Embree evaluates it), and its tangent.
struct CurvePoint {
  Vec3 centre;
  Vec3 tangent;
  float radius;
};
CurvePoint catmull_rom(const float* k, float u) {
  const float u2 = u * u, u3 = u2 * u;
  // Weights of the four keys and their derivatives.
  const float w[4] = {0.5f * (-u3 + 2.0f * u2 - u), 0.5f * (3.0f * u3 - 5.0f * u2 + 2.0f),
                      0.5f * (-3.0f * u3 + 4.0f * u2 + u), 0.5f * (u3 - u2)};
  const float d[4] = {0.5f * (-3.0f * u2 + 4.0f * u - 1.0f), 0.5f * (9.0f * u2 - 10.0f * u),
                      0.5f * (-9.0f * u2 + 8.0f * u + 1.0f), 0.5f * (3.0f * u2 - 2.0f * u)};
  CurvePoint out{Vec3(0.0f), Vec3(0.0f), 0.0f};
  for (int i = 0; i < 4; ++i) {
    const Vec3 key(k[4 * i], k[4 * i + 1], k[4 * i + 2]);
    out.centre += w[i] * key;
    out.tangent += d[i] * key;
    out.radius += w[i] * k[4 * i + 3];
  }
  return out;
}

// The centre, radius and tangent of a linear segment from key k0 to k1 at u, clamped to
// the segment (beyond it lie the round joints).
CurvePoint linear_point(const float* k, float u) {
  const float w = std::clamp(u, 0.0f, 1.0f);
  const Vec3 a(k[0], k[1], k[2]), b(k[4], k[5], k[6]);
  return {(1.0f - w) * a + w * b, b - a, (1.0f - w) * k[3] + w * k[7]};
}

// The shading normal of a ribbon (a flat curve facing the ray, object space): the normal of
// the round tube it stands for where the tube's outline, seen along the ray, meets the hit.
// The hit lies `side` = its offset from the axis over the radius, -1 to 1, across the
// ribbon (along B = T x -d); the tube's normal there is side B plus sqrt(1 - side^2) towards
// the viewer (-d with its part along T taken out). Cycles' Ribbons shade so
// (curve_shader_setup); the side is measured here from the hit, not read from Embree.
Vec3 ribbon_normal(const CurvePoint& c, const Vec3& hit, const Vec3& direction) {
  const float tangent_length = glm::length(c.tangent);
  if (!(tangent_length > 0.0f)) return -direction;
  const Vec3 t = c.tangent / tangent_length;
  const Vec3 towards = -direction + glm::dot(direction, t) * t;  // -d across the axis
  const float towards_length = glm::length(towards);
  if (!(towards_length > 0.0f)) return -direction;  // looking along the strand
  const Vec3 facing = towards / towards_length;
  const Vec3 across = glm::cross(t, facing);
  const float side =
      c.radius > 0.0f ? std::clamp(glm::dot(hit - c.centre, across) / c.radius, -1.0f, 1.0f) : 0.0f;
  return side * across + std::sqrt(std::max(1.0f - side * side, 0.0f)) * facing;
}

}  // namespace

void CompiledScene::identify(const Ray& ray, const Hit& hit, const Vec3& local,
                             Interaction* out) const {
  const uint32_t material = material_index(hit.instance, hit.primitive);
  out->material = &materials[material];
  out->material_index = material;
  out->holdout = instances[hit.instance].holdout;
  out->instance = hit.instance;
  out->primitive = hit.primitive;
  out->local_position = local;
  out->barycentric = glm::vec2(hit.u, hit.v);
  out->time = ray.time;
}

// A hit on a curve segment or a point: round surfaces, whose normal points from the axis
// (or the centre) to the hit. The point is where the ray says (origin + t direction):
// Embree's curve intersection is iterative and finds it within a small share of the
// radius, so the offset that keeps secondary rays off the surface allows for 1e-3 of it
// besides float rounding. Shading normal = geometric normal; no UVs or corner layers.
// A flat curve (a ribbon) faces the ray: its geometric normal is -d, its shading normal
// the round tube's (ribbon_normal), as Cycles' Ribbons. Rays leave it from the hit, as in
// Cycles: Embree ignores a flat curve closer than twice its radius to a ray's origin, so
// a ray never meets the ribbon it leaves but within 30 degrees of a straight strand (or
// where a bent strand turns into its way): Cycles' ribbons self-shadow so too.
Interaction CompiledScene::round_interaction(const Ray& ray, const Hit& hit,
                                             const Placement& at) const {
  const Instance& instance = instances[hit.instance];
  const Mesh& mesh = instance.mesh->mesh;
  Interaction out;
  out.position = ray.origin + hit.t * ray.direction;
  // Object space by the inverse of the linear part (the transpose of the normal matrix).
  const glm::mat3 to_local = glm::transpose(at.normal_to_world);
  const Vec3 local = to_local * (out.position - Vec3(at.to_world[3]));
  Vec3 normal_local(0.0f);
  float radius = 0.0f;
  bool flat = false;
  const auto index = static_cast<size_t>(hit.primitive);
  if (mesh.kind(hit.primitive) == PrimitiveKind::kCurve) {
    const size_t segment = index - mesh.triangle_count();
    const float* keys = &mesh.curves.keys[4 * size_t{mesh.curves.segments[segment]}];
    // Linear: a cone from key to key with round joints, the normal from the nearest axis
    // point (u, clamped to the segment, gives it on the joints' spheres too). Catmull-Rom:
    // from the axis point at u, square to the tangent.
    const CurvePoint c = mesh.curves.linear ? linear_point(keys, hit.u) : catmull_rom(keys, hit.u);
    radius = c.radius;
    flat = mesh.curves.flat;
    if (flat) {
      normal_local = ribbon_normal(c, local, to_local * ray.direction);
    } else {
      normal_local = local - c.centre;
      const float tangent_length2 = glm::dot(c.tangent, c.tangent);
      if (!mesh.curves.linear && tangent_length2 > 0.0f) {
        normal_local -= glm::dot(normal_local, c.tangent) / tangent_length2 * c.tangent;
      }
    }
  } else {
    const float* sphere =
        &mesh.points.spheres[4 * (index - mesh.triangle_count() - mesh.curves.segment_count())];
    normal_local = local - Vec3(sphere[0], sphere[1], sphere[2]);
    radius = sphere[3];
  }
  const Vec3 facing = -glm::normalize(ray.direction);
  const Vec3 n = at.normal_to_world * normal_local;
  const float n_length = glm::length(n);
  const Vec3 round = n_length > 0.0f && std::isfinite(n_length) ? n / n_length : facing;
  out.geometric_normal = flat ? facing : round;
  out.shading_normal = round;
  // Rounding of o + t d, and the intersector's own tolerance, in world units.
  const float scale =
      max_component(glm::abs(ray.origin)) + hit.t * max_component(glm::abs(ray.direction));
  const float world_radius = radius * max_component(at.abs_linear * Vec3(1.0f));
  out.position_error = Vec3(gamma(8) * scale + 1e-3f * world_radius);
  out.shadow_origin = out.position;
  identify(ray, hit, local, &out);
  return out;
}

Interaction CompiledScene::interaction(const Ray& ray, const Hit& hit) const {
  const Instance& instance = instances[hit.instance];
  const Mesh& mesh = instance.mesh->mesh;
  // A moving instance is where the ray's time puts it, blended as Embree blends it.
  Placement moved;
  if (instance.motion) moved = Placement::of(instance.motion->at(ray.time));
  const Placement& at = instance.motion ? moved : instance.placement;
  if (mesh.kind(hit.primitive) != PrimitiveKind::kTriangle) return round_interaction(ray, hit, at);
  const uint32_t* tri = &mesh.triangles[3 * size_t{hit.primitive}];
  // A deforming mesh's triangle where the ray's time puts it.
  const Vec3 p0 = mesh.vertex_at(tri[0], ray.time);
  const Vec3 p1 = mesh.vertex_at(tri[1], ray.time);
  const Vec3 p2 = mesh.vertex_at(tri[2], ray.time);
  const float w0 = 1.0f - hit.u - hit.v;
  Interaction out;
  // The point from barycentrics on the triangle, not origin + t*direction: its error is
  // a few ulps of the coordinates, which is what the ray-origin offset assumes.
  const Vec3 local = w0 * p0 + hit.u * p1 + hit.v * p2;
  out.position = transform_point(at.to_world, local);
  // Error of the object-space point, carried through the transform (pbrt-v4 Transform):
  // |M| e (1 + gamma3) + gamma3 (|M| |p| + |t|). A moving instance's blended transform
  // may differ from Embree's by the blend's rounding (two operations an element): gamma5;
  // a deforming triangle's blended corners likewise (the local bound at gamma(9)).
  const float g = instance.motion ? gamma(5) : gamma(3);
  const Vec3 local_error = (mesh.deforms() ? gamma(9) / gamma(7) : 1.0f) *
                           barycentric_error(p0, p1, p2, w0, hit.u, hit.v);
  const Vec3 world_error = (1.0f + g) * (at.abs_linear * local_error) +
                           g * (at.abs_linear * glm::abs(local) + at.abs_translation);
  // Embree's intersector computes with all coordinates at once (relative to the ray
  // origin), so its error scales with the largest of them: use the largest bound on
  // every axis. A flat triangle exactly on a coordinate plane then still gets an offset.
  out.position_error = Vec3(max_component(world_error));
  Vec3 ng = at.normal_to_world * glm::cross(p1 - p0, p2 - p0);
  const float ng_length = glm::length(ng);
  // A degenerate (zero-area) triangle has no normal; face the ray instead.
  out.geometric_normal =
      ng_length > 0.0f && std::isfinite(ng_length) ? ng / ng_length : -ray.direction;
  out.shading_normal = out.geometric_normal;
  out.shadow_origin = out.position;
  Vec3 n0, n1, n2;
  if (mesh.corner_normals(hit.primitive, &n0, &n1, &n2)) {
    const Vec3 world = at.normal_to_world * (w0 * n0 + hit.u * n1 + hit.v * n2);
    const float length = glm::length(world);
    if (length > 0.0f && std::isfinite(length)) {
      out.shading_normal = world / length;
      // Project the point onto the tangent plane of each corner it lies below, and
      // blend: the lifted point lies on a smooth surface through the corners.
      const auto lift = [&](const Vec3& corner, const Vec3& normal) {
        const float below = std::min(0.0f, glm::dot(local - corner, normal));
        return -below * normal;
      };
      const Vec3 lifted = local + w0 * lift(p0, n0) + hit.u * lift(p1, n1) + hit.v * lift(p2, n2);
      const Vec3 world_lifted = transform_point(at.to_world, lifted);
      if (is_finite(world_lifted)) out.shadow_origin = world_lifted;
    }
  }
  identify(ray, hit, local, &out);
  return out;
}

}  // namespace whitted
