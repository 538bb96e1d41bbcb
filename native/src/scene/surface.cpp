// A hit's Whitted fields: the material's constants, or its textures and shader program
// run at the hit (CompiledScene::surface), and the world's radiance by direction.
#include "scene/scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <variant>

#include <glm/matrix.hpp>

#include "core/limits.h"
#include "scene/mesh_light.h"

namespace whitted {
namespace {

// The barycentric blend of a corner layer (`width` floats a corner) at a point of triangle
// `primitive`; barycentric holds the weights of corners 1 and 2.
glm::vec4 interpolate_corners(const std::vector<float>& layer, size_t width, uint32_t primitive,
                              glm::vec2 barycentric) {
  const float* c = &layer[3 * width * size_t{primitive}];
  const float w0 = 1.0f - barycentric.x - barycentric.y;
  glm::vec4 out(0.0f);
  for (size_t k = 0; k < width; ++k) {
    out[static_cast<int>(k)] =
        w0 * c[k] + barycentric.x * c[width + k] + barycentric.y * c[2 * width + k];
  }
  return out;
}

// Coverage as the integrator reads it: in [0, 1], NaN (from a program) opaque.
float clamp_alpha(float alpha) {
  return std::isnan(alpha) ? 1.0f : std::clamp(alpha, 0.0f, 1.0f);
}

// The Light Path inputs of a program (and 0 for any other mode).
glm::vec4 light_path_input(uint32_t mode, const Ray& ray, const RayContext& context) {
  const auto flag = [](bool on) { return glm::vec4(on ? 1.0f : 0.0f); };
  switch (mode) {
    case kInputIsCameraRay:
      return flag(ray.kind == kCameraRay);
    case kInputIsShadowRay:
      return flag((ray.kind & (kShadowRay | kOpaqueShadowRay | kTranslucentShadowRay)) != 0);
    case kInputIsReflectionRay:
      return flag(ray.kind == kReflectionRay);
    case kInputIsTransmissionRay:
      return flag(ray.kind == kRefractionRay);
    case kInputRayDepth:
      return glm::vec4(static_cast<float>(context.depth));
    case kInputIsSingularRay:
      return flag(ray.kind != kCameraRay);  // every Whitted bounce is a perfect mirror or lens
    default:                                // is diffuse ray: Whitted traces none
      return glm::vec4(0.0f);
  }
}

}  // namespace

// A material's fields before its textures and program (declared in scene.h).
SurfaceParams constant_surface(const Material& m) {
  return {m.diffuse,           m.specular,
          m.shininess,         m.reflectivity,
          m.transmissivity,    m.ior,
          m.emission,          clamp_alpha(m.alpha),
          Vec3(0.0f),          m.coat_specular,
          m.coat_reflectivity, m.coat_shininess,
          m.coat_ior,          Vec3(0.0f),
          m.diffuse_roughness, m.roughness,
          m.coat_roughness,    m.anisotropy,
          Vec3(0.0f),          m.sheen,
          m.sheen_roughness,   m.layer_reflectivity,
          m.layer_ior};
}

TexturePoint CompiledScene::texture_point(const Interaction& it) const {
  const Mesh& mesh = instances[it.instance].mesh->mesh;
  TexturePoint tp;
  tp.object = it.local_position;
  const Vec3 local = mesh.undisplaced_point(it.primitive, it.barycentric, it.local_position);
  tp.generated = mesh.generated(local);
  if (!mesh.uvs.empty() && mesh.kind(it.primitive) == PrimitiveKind::kTriangle) {
    tp.uv = glm::vec2(interpolate_corners(mesh.uvs, 2, it.primitive, it.barycentric));
  }
  return tp;
}

namespace {

// The INPUT modes of the grids (shader/ops.h kInputGrid + role, named by role in
// kOpNumbers) follow GridRole's order.
static_assert(static_cast<int>(GridRole::kDensity) == 0 &&
              static_cast<int>(GridRole::kColor) == 1 &&
              static_cast<int>(GridRole::kTemperature) == 2 &&
              static_cast<int>(GridRole::kFlame) == 3 && kGridRoles == 4);

// Where a program reads a surface hit, or a point inside a medium (`inside`: no surface,
// no primitive; its corner layers read 0): the inputs it asks for, computed on demand.
struct SurfaceHit {
  const CompiledScene& scene;
  const Interaction& it;
  const Ray& ray;
  const RayContext& context;
  const ProgramHit& hit;
  bool inside = false;
  // Inside a Volume object: its grids at the point (kInputGrid); null elsewhere.
  const VolumeSample* grids = nullptr;

  glm::vec4 input(uint32_t mode) const {
    const CompiledScene::Instance& instance = scene.instances[it.instance];
    const Mesh& mesh = instance.mesh->mesh;
    const auto vec = [](const Vec3& v) { return glm::vec4(v, 0.0f); };
    // Corner layers are a triangle's: a curve or a point reads 0 from them.
    const bool triangle = !inside && mesh.kind(it.primitive) == PrimitiveKind::kTriangle;
    const auto layer = [&](const std::vector<std::vector<float>>& layers, size_t k, size_t width) {
      return triangle && k < layers.size()
                 ? interpolate_corners(layers[k], width, it.primitive, it.barycentric)
                 : glm::vec4(0.0f);
    };
    if (mode >= kInputTangent && mode < kInputObjectNormal) {
      return layer(mesh.tangents, mode - kInputTangent, 4);
    }
    if (mode >= kInputAttribute && mode < kInputPublicEnd) {
      return layer(mesh.attributes, mode - kInputAttribute, 4);
    }
    if (mode >= kInputObjectAttribute && mode < kInputObjectAttribute + kObjectAttributes) {
      const size_t k = mode - kInputObjectAttribute;
      return k < instance.attributes.size() ? instance.attributes[k] : glm::vec4(0.0f);
    }
    if (mode >= kInputGridTemperatureVoxel && mode < kInputGridVoxelWeight + kGridVoxels) {
      if (!grids) return glm::vec4(0.0f);
      const bool weight = mode >= kInputGridVoxelWeight;
      const uint32_t k = mode - (weight ? kInputGridVoxelWeight : kInputGridTemperatureVoxel);
      const VolumeGrid::Cell& cell = grids->temperature_cell;
      return glm::vec4(weight ? cell.weight(static_cast<int>(k)) : cell.values[k]);
    }
    if (mode >= kInputUvSet && mode < kInputAttribute) {
      if (triangle && mesh.uv_sets.empty() && mode == kInputUvSet && !mesh.uvs.empty()) {
        return interpolate_corners(mesh.uvs, 2, it.primitive, it.barycentric);
      }
      return layer(mesh.uv_sets, mode - kInputUvSet, 2);
    }
    switch (mode) {
      case kInputPosition:
        return vec(it.position);
      case kInputNormal:
        return vec(hit.normal);
      case kInputTrueNormal:
        return vec(hit.backfacing ? -it.geometric_normal : it.geometric_normal);
      case kInputIncoming:
        return vec(hit.incoming);
      case kInputGenerated:
        return vec(generated(mesh));
      case kInputObject:
        return vec(it.local_position);
      case kInputCamera:
        return vec(camera_space());
      case kInputWindow:
        return vec(window());
      case kInputReflection:
        return vec(2.0f * glm::dot(hit.normal, hit.incoming) * hit.normal - hit.incoming);
      case kInputBackfacing:
        return glm::vec4(hit.backfacing ? 1.0f : 0.0f);
      case kInputObjectSpaceNormal: {
        // Normals go back to object space by the transpose of the linear part.
        const Vec3 n = glm::transpose(glm::mat3(instance.placement.to_world)) * hit.normal;
        const float length = glm::length(n);
        return vec(length > 0.0f ? n / length : n);
      }
      case kInputObjectNormalScale:
        return glm::vec4(
            glm::length(glm::transpose(glm::mat3(instance.placement.to_world)) * hit.normal));
      case kInputRadialTangent:
      case kInputRadialTangent + 1:
      case kInputRadialTangent + 2:
        return vec(radial_tangent(mesh, instance, mode - kInputRadialTangent));
      case kInputObjectLocation:
        return vec(instance.info.location);
      case kInputObjectRandom:
        return glm::vec4(instance.info.random);
      case kInputObjectIndex:
        return glm::vec4(instance.info.pass_index);
      case kInputObjectColor:
        return instance.info.color;
      case kInputGrid + static_cast<uint32_t>(GridRole::kDensity):
        return glm::vec4(grids ? grids->density : 0.0f);
      case kInputGrid + static_cast<uint32_t>(GridRole::kColor):
        return grids ? glm::vec4(grids->color, 0.0f) : glm::vec4(0.0f);
      case kInputGrid + static_cast<uint32_t>(GridRole::kTemperature):
        return glm::vec4(grids ? grids->temperature : 0.0f);
      case kInputGrid + static_cast<uint32_t>(GridRole::kFlame):
        return glm::vec4(grids ? grids->flame : 0.0f);
      case kInputVolumeDensity:
        return glm::vec4(inside && instance.volume ? instance.volume->density_scale() : 1.0f);
      case kInputObjectNormal:
        return vec(object_normal(mesh));
      case kInputTriangleVertex:
      case kInputTriangleVertex + 1:
      case kInputTriangleVertex + 2: {
        // Where the corner is when the ray meets the triangle (a moving or deforming
        // mesh's too), as the hit's own position.
        if (!triangle) return glm::vec4(0.0f);
        const uint32_t corner =
            mesh.triangles[3 * size_t{it.primitive} + (mode - kInputTriangleVertex)];
        const glm::mat4 to_world =
            instance.motion ? instance.motion->at(it.time) : instance.placement.to_world;
        return glm::vec4(Vec3(to_world * glm::vec4(mesh.vertex_at(corner, it.time), 1.0f)), 0.0f);
      }
      case kInputRayLength:
        // Cycles starts a camera ray at its near clip distance (Whitted's t_min; 0 for
        // every other ray) and measures the hit's distance from there.
        return glm::vec4(glm::length(it.position - ray.origin) - ray.t_min);
      default:
        return light_path_input(mode, ray, context);
    }
  }

  // The hit in the camera's frame (Blender ignores the camera's scale): looking down -Z.
  Vec3 camera_space() const {
    const glm::mat4& m = context.camera->to_world;
    const Vec3 d = it.position - Vec3(m[3]);
    return {glm::dot(d, glm::normalize(Vec3(m[0]))), glm::dot(d, glm::normalize(Vec3(m[1]))),
            glm::dot(d, glm::normalize(Vec3(m[2])))};
  }
  // Where the hit lands in the camera's image, [0,1]^2 from its bottom-left corner.
  Vec3 window() const {
    const Camera& camera = *context.camera;
    Vec3 p = camera_space();
    if (camera.projection == Projection::kPanoramic) {
      // The panorama's own [0,1]^2 point looking at the hit (Cycles' camera_world_to_ndc:
      // no shift).
      const float length = glm::length(p);
      const glm::vec2 uv = camera.panorama.image_point(length > 0.0f ? p / length : p);
      return {uv.x, uv.y, 0.0f};
    }
    if (camera.projection == Projection::kPerspective) {
      const float depth = -p.z;
      p = depth != 0.0f ? p / depth : Vec3(0.0f);
    }
    return {(p.x - camera.window[0]) / (camera.window[1] - camera.window[0]),
            (p.y - camera.window[2]) / (camera.window[3] - camera.window[2]), 0.0f};
  }
  // The object's position mapped to [0, 1] over its texture space (the mesh's bounds).
  Vec3 generated(const Mesh& mesh) const {
    const Vec3 local =
        inside ? it.local_position
               : mesh.undisplaced_point(it.primitive, it.barycentric, it.local_position);
    return mesh.generated(local);
  }
  // Cycles' radial tangent about object axis `axis` (0, 1, 2: X, Y, Z) at the hit: the
  // generated coordinates' offset from their centre turned a quarter about the axis
  // (about Z: (-(y - 0.5), x - 0.5, 0)), to the world as a normal is, then made
  // perpendicular to the shading normal: N x normalize(T x N). Zero where it has no
  // direction (on the axis).
  Vec3 radial_tangent(const Mesh& mesh, const CompiledScene::Instance& instance,
                      uint32_t axis) const {
    const Vec3 g = generated(mesh) - Vec3(0.5f);
    const Vec3 object = axis == 0   ? Vec3(0.0f, -g.z, g.y)
                        : axis == 1 ? Vec3(-g.z, 0.0f, g.x)
                                    : Vec3(-g.y, g.x, 0.0f);
    return tangent_across(instance.placement.normal_to_world * object, hit.normal);
  }
  // The object-space normal a tangent-space normal map bends: the interpolated corner
  // normals, not normalised, or the face's normal on a flat mesh.
  Vec3 object_normal(const Mesh& mesh) const {
    if (inside || mesh.kind(it.primitive) != PrimitiveKind::kTriangle) {
      // A curve's or a point's own round normal (a ribbon's too), back in object space.
      const glm::mat3 linear(scene.instances[it.instance].placement.to_world);
      return glm::transpose(linear) * it.shading_normal;
    }
    Vec3 n0, n1, n2;
    const float u = it.barycentric.x, v = it.barycentric.y;
    if (mesh.corner_normals(it.primitive, &n0, &n1, &n2))
      return (1.0f - u - v) * n0 + u * n1 + v * n2;
    const uint32_t* tri = &mesh.triangles[3 * size_t{it.primitive}];
    const Vec3 p0 = mesh.vertex(tri[0]);
    const Vec3 n = glm::cross(mesh.vertex(tri[1]) - p0, mesh.vertex(tri[2]) - p0);
    const float length = glm::length(n);
    return length > 0.0f ? n / length : n;
  }
};

// `n` turned towards the geometric normal `ng` in their common plane just enough that
// the mirror image of the unit view vector `wo` about it leaves the surface at least as
// steeply as min(0.9 ng.wo, 0.01) (Cycles 3.x ensure_valid_reflection). With n' =
// x X + z ng, x = sqrt(1 - z^2), the condition 2 (n'.wo) z - wo.z = t is a quadratic in
// z^2; of its roots in (0, 1] the one whose reflection rises least (but rises) is taken.
Vec3 valid_reflection(const Vec3& ng, const Vec3& wo, const Vec3& n) {
  const float threshold = std::fmin(0.9f * glm::dot(ng, wo), 0.01f);
  if (glm::dot(ng, 2.0f * glm::dot(n, wo) * n - wo) >= threshold) return n;
  const Vec3 along = n - glm::dot(n, ng) * ng;
  const float along_length = glm::length(along);
  if (!(along_length > 0.0f)) return ng;
  const Vec3 x_axis = along / along_length;
  const float wx = glm::dot(wo, x_axis), wz = glm::dot(wo, ng);
  const float a = wx * wx + wz * wz;
  const float b = std::sqrt(std::fmax(wx * wx * (a - threshold * threshold), 0.0f));
  const float c = wz * threshold + a;
  const float z2[2] = {0.5f * (c + b) / a, 0.5f * (c - b) / a};
  const auto usable = [](float v) { return v > 1e-5f && v <= 1.0f + 1e-5f; };
  // The root's normal (x, z) and the height of its reflection.
  const auto root = [&](float v) {
    const float z = std::sqrt(std::fmax(v, 0.0f)), x = std::sqrt(std::fmax(1.0f - v, 0.0f));
    return std::array<float, 3>{x, z, 2.0f * (x * wx + z * wz) * z - wz};
  };
  std::array<float, 3> chosen;
  if (usable(z2[0]) && usable(z2[1])) {
    const auto r1 = root(z2[0]), r2 = root(z2[1]);
    const bool rises1 = r1[2] >= 1e-5f, rises2 = r2[2] >= 1e-5f;
    chosen = rises1 && rises2 ? (r1[2] < r2[2] ? r1 : r2) : (r1[2] > r2[2] ? r1 : r2);
  } else if (usable(z2[0]) || usable(z2[1])) {
    chosen = root(usable(z2[0]) ? z2[0] : z2[1]);
  } else {
    return ng;
  }
  return chosen[0] * x_axis + chosen[1] * ng;
}

// How far the height of a Bump node is read from the hit: limits::kBumpStep of the hit's
// distance from the camera (the Bump's result does not depend on the step to first order).
// Two offsets along the surface (perpendicular to the geometric normal, a right-handed
// frame with it) for the Bump node's differences.
void bump_offsets(const Interaction& it, const RayContext& context, ProgramHit* hit) {
  const Vec3& n = it.geometric_normal;
  // Duff et al. 2017, "Building an Orthonormal Basis, Revisited".
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  const Vec3 t(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
  const Vec3 bitangent(b, sign + n.y * n.y * a, -n.y);
  const float distance = glm::length(it.position - Vec3(context.camera->to_world[3]));
  const float step = limits::kBumpStep * std::fmax(distance, limits::kBumpMinDistance);
  hit->bump_dx = step * t;
  hit->bump_dy = step * bitangent;
}

// The hit moved by `offset` (world, along its triangle's plane): position, object-space
// point and barycentrics (outside the triangle they extrapolate its interpolation).
Interaction moved(const CompiledScene& scene, const Interaction& it, const Vec3& offset) {
  const CompiledScene::Instance& instance = scene.instances[it.instance];
  const Mesh& mesh = instance.mesh->mesh;
  if (mesh.kind(it.primitive) != PrimitiveKind::kTriangle) {
    Interaction out = it;  // a round surface: moved along, its parameters kept
    out.position += offset;
    out.local_position += glm::transpose(instance.placement.normal_to_world) * offset;
    return out;
  }
  const uint32_t* tri = &mesh.triangles[3 * size_t{it.primitive}];
  const Vec3 p0 = mesh.vertex(tri[0]);
  const Vec3 e1 = mesh.vertex(tri[1]) - p0;
  const Vec3 e2 = mesh.vertex(tri[2]) - p0;
  // The inverse of the linear part is the transpose of its inverse transpose.
  const Vec3 local = glm::transpose(instance.placement.normal_to_world) * offset;
  const float d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
  const float b1 = glm::dot(local, e1), b2 = glm::dot(local, e2);
  const float det = d11 * d22 - d12 * d12;
  Interaction out = it;
  out.position += offset;
  out.local_position += local;
  if (det > 0.0f && std::isfinite(det)) {
    out.barycentric += glm::vec2(d22 * b1 - d12 * b2, d11 * b2 - d12 * b1) / det;
  }
  return out;
}

// The rays a program traces from a surface hit (HitRays), through the integrator's
// TracedRays: each ambient occlusion ray leaves the hit off its surface by its rounding
// error, on the side it goes towards, and sees what a shadow ray sees (Cycles' opaque
// shadow visibility), or with Only Local every face of the hit's own instance; a bevel's
// probes meet every face, those of the hit's instance kept.
struct SurfaceRays final : HitRays {
  // A probe steps past other objects' faces and its object's, at most this many times.
  static constexpr int kMaxSteps = 16;
  const CompiledScene& scene;
  const Interaction& it;
  const TracedRays& traced;
  SurfaceRays(const CompiledScene& scene, const Interaction& it, const TracedRays& traced)
      : scene(scene), it(it), traced(traced) {}
  int surfaces(const Vec3& origin, const Vec3& direction, float length,
               Surface* out) const override {
    Ray ray{origin,
            direction,
            0.0f,
            length,
            RayKind(kAllRayKinds | kOpaqueShadowRay | kTranslucentShadowRay),
            it.time};
    int count = 0;
    for (int step = 0; step < kMaxSteps && count < kMaxSurfaces; ++step) {
      Hit hit;
      if (!traced.intersect(ray, &hit)) break;
      if (hit.instance == it.instance) {
        const Interaction at = scene.interaction(ray, hit);
        out[count++] = {at.position, at.geometric_normal, at.shading_normal};
      }
      ray.t_min = next_float_up(hit.t);
    }
    return count;
  }
  bool occluded(const Vec3& direction, float distance, bool local) const override {
    const auto kind = RayKind(local ? kAllRayKinds | kOpaqueShadowRay | kTranslucentShadowRay
                                    : kOpaqueShadowRay | kTranslucentShadowRay);
    const Ray ray = spawn_ray(it.position, it.position_error, it.geometric_normal, it.time,
                              direction, kind, distance);
    return traced.occluded(ray, local ? &it.instance : nullptr);
  }
  glm::vec2 point(int k, int count) const override { return traced.point(k, count); }
};

// The register file of one evaluation lives here, on the stack, and is gone before the
// integrator recurses.
using Registers = std::array<glm::vec4, Program::kMaxRegisters + 1>;
using Inputs = std::array<glm::vec4, Program::kMaxInputs>;

}  // namespace

SurfaceParams CompiledScene::surface(const Interaction& it, const Ray& ray,
                                     const RayContext& context) const {
  const Material& m = *it.material;
  SurfaceParams out = material_constants[it.material_index];
  out.normal = it.shading_normal;
  out.coat_normal = it.shading_normal;
  // Not on curves, as Cycles: a ribbon's round normal leans far from its geometric
  // normal (-d) by design, and a tube's is its geometric normal.
  const bool lifts = m.valid_reflection &&
                     instances[it.instance].mesh->mesh.kind(it.primitive) != PrimitiveKind::kCurve;
  if (lifts && !m.driven(kNormalField)) {
    // Cycles 3.x lifts the interpolated normal too (every closure's), on the side the
    // ray comes from, where the view's mirror would fall below the surface.
    const float side = glm::dot(ray.direction, it.geometric_normal) > 0.0f ? -1.0f : 1.0f;
    out.normal = side * valid_reflection(side * it.geometric_normal, -ray.direction,
                                         side * it.shading_normal);
    out.coat_normal = out.normal;
  }
  if (m.diffuse_texture_index < 0 && m.alpha_texture_index < 0 && !m.program) return out;
  out.alpha = m.alpha;  // clamped once textures and program have applied
  if (m.diffuse_texture_index >= 0 || m.alpha_texture_index >= 0) {
    const TexturePoint tp = texture_point(it);
    if (m.diffuse_texture_index >= 0) {
      out.diffuse *= Color(textures[m.diffuse_texture_index]->evaluate(tp));
    }
    if (m.alpha_texture_index >= 0) {
      out.alpha *= textures[m.alpha_texture_index]->evaluate(tp).w;
    }
  }
  if (m.program) {
    const CompiledScene::Instance& instance = instances[it.instance];
    ProgramHit hit;
    hit.incoming = -ray.direction;
    hit.backfacing = glm::dot(ray.direction, it.geometric_normal) > 0.0f;
    hit.normal = hit.backfacing ? -it.shading_normal : it.shading_normal;
    hit.to_world = glm::mat3(instance.placement.to_world);
    hit.normal_to_world = instance.placement.normal_to_world;
    hit.images = m.program_images.data();
    std::optional<SurfaceRays> rays;
    if (m.program->traces() && context.rays != nullptr) {
      hit.rays = &rays.emplace(*this, it, *context.rays);
    }
    const SurfaceHit source{*this, it, ray, context, hit};
    Inputs inputs;
    if (m.program->bumps()) {
      bump_offsets(it, context, &hit);
      const Interaction at_x = moved(*this, it, hit.bump_dx);
      const Interaction at_y = moved(*this, it, hit.bump_dy);
      const SurfaceHit source_x{*this, at_x, ray, context, hit};
      const SurfaceHit source_y{*this, at_y, ray, context, hit};
      for (size_t i = 0; i < m.program->inputs().size(); ++i) {
        const uint32_t mode = m.program->inputs()[i];
        const uint32_t base = mode & ~(kInputBumpX | kInputBumpY);
        inputs[i] = base == mode                ? source.input(mode)
                    : (mode & kInputBumpX) != 0 ? source_x.input(base)
                                                : source_y.input(base);
      }
    } else {
      for (size_t i = 0; i < m.program->inputs().size(); ++i) {
        inputs[i] = source.input(m.program->inputs()[i]);
      }
    }
    hit.inputs = inputs.data();
    Registers r;
    m.program->run(hit, r.data());
    const auto field = [&](Field f) { return r[static_cast<size_t>(m.outputs[f])]; };
    if (m.driven(kDiffuseField)) out.diffuse = Color(field(kDiffuseField));
    if (m.driven(kSpecularField)) out.specular = Color(field(kSpecularField));
    if (m.driven(kShininessField)) out.shininess = std::fmax(field(kShininessField).x, 0.0f);
    if (m.driven(kReflectivityField)) out.reflectivity = Color(field(kReflectivityField));
    if (m.driven(kTransmissivityField)) out.transmissivity = Color(field(kTransmissivityField));
    if (m.driven(kIorField)) {
      // An index that is not positive and finite keeps the material's own.
      const float ior = field(kIorField).x;
      if (ior > 0.0f && std::isfinite(ior)) out.ior = ior;
    }
    if (m.driven(kEmissionField)) out.emission = Color(field(kEmissionField));
    if (m.driven(kAlphaField)) out.alpha = field(kAlphaField).x;
    // A normal on the geometric normal's side, as the interpolated normal is: the
    // integrator turns it towards the ray. A zero or non-finite one keeps `n`.
    const auto normal = [&](Field f, Vec3* n) {
      if (!m.driven(f)) return;
      const Vec3 v(field(f));
      const float length = glm::length(v);
      if (length > 0.0f && std::isfinite(length)) {
        *n = glm::dot(v, it.geometric_normal) < 0.0f ? -v / length : v / length;
      }
    };
    // Turned towards the geometric normal on the side the ray comes from, as Cycles'
    // shading frame is.
    const auto lift = [&](Vec3* n) {
      const float side = hit.backfacing ? -1.0f : 1.0f;
      *n = side * valid_reflection(side * it.geometric_normal, hit.incoming, side * *n);
    };
    normal(kNormalField, &out.normal);
    if (lifts && m.driven(kNormalField)) lift(&out.normal);
    normal(kCoatNormalField, &out.coat_normal);
    // The coat's normal too, mapped or the interpolated one beside a mapped base normal
    // (Cycles 3.x lifts its Clearcoat Normal as it lifts Normal).
    if (lifts && (m.driven(kCoatNormalField) || m.driven(kNormalField))) lift(&out.coat_normal);
    if (m.driven(kCoatSpecularField)) out.coat_specular = field(kCoatSpecularField).x;
    if (m.driven(kCoatReflectivityField)) out.coat_reflectivity = field(kCoatReflectivityField).x;
    if (m.driven(kCoatShininessField)) {
      out.coat_shininess = std::fmax(field(kCoatShininessField).x, 0.0f);
    }
    if (m.driven(kCoatIorField)) {
      const float ior = field(kCoatIorField).x;
      if (ior > 0.0f && std::isfinite(ior)) out.coat_ior = ior;
    }
    if (m.driven(kLayerReflectivityField)) {
      out.layer_reflectivity = glm::max(Color(field(kLayerReflectivityField)), Color(0.0f));
    }
    if (m.driven(kLayerIorField)) {
      const float ior = field(kLayerIorField).x;
      if (ior > 0.0f && std::isfinite(ior)) out.layer_ior = ior;
    }
    if (m.driven(kDiffuseRoughnessField)) {
      const float roughness = field(kDiffuseRoughnessField).x;  // NaN: the material's own
      if (!std::isnan(roughness)) out.diffuse_roughness = std::clamp(roughness, 0.0f, 1.0f);
    }
    if (m.driven(kRoughnessField)) {
      const float roughness = field(kRoughnessField).x;  // NaN: the material's own
      if (!std::isnan(roughness)) out.roughness = std::clamp(roughness, 0.0f, 1.0f);
    }
    if (m.driven(kCoatRoughnessField)) {
      const float roughness = field(kCoatRoughnessField).x;
      if (!std::isnan(roughness)) out.coat_roughness = std::clamp(roughness, 0.0f, 1.0f);
    }
    if (m.driven(kAnisotropyField)) {
      const float anisotropy = field(kAnisotropyField).x;  // NaN: the material's own
      if (!std::isnan(anisotropy)) out.anisotropy = std::clamp(anisotropy, -0.99f, 0.99f);
    }
    if (m.driven(kTangentField)) {
      // Made perpendicular to the lobe's normal where the lobe is built (GgxLobe); a
      // non-finite one is none.
      const Vec3 tangent(field(kTangentField));
      if (is_finite(tangent)) out.tangent = tangent;
    }
    if (m.driven(kSheenField)) out.sheen = glm::max(Color(field(kSheenField)), Color(0.0f));
    if (m.driven(kSheenRoughnessField)) {
      const float sigma = field(kSheenRoughnessField).x;  // NaN: the material's own
      if (!std::isnan(sigma)) out.sheen_roughness = std::clamp(sigma, 0.0f, 1.0f);
    }
  }
  out.alpha = clamp_alpha(out.alpha);
  return out;
}

Medium CompiledScene::medium(uint32_t material, uint32_t instance, const Vec3& x, const Ray& ray,
                             const RayContext& context) const {
  const Material& m = materials[material];
  Medium out{m.volume_absorption, m.volume_scattering, m.volume_emission, m.volume_anisotropy};
  if (!m.heterogeneous()) return out;
  const Placement& placement = instances[instance].placement;
  // A moving object carries its medium (motion blur): the point is read where it stood
  // in the object at the ray's time, carried back to the frame's placement, which the
  // object coordinates and the grids (VolumeObject::sample) are read from.
  Vec3 at = x;
  if (const auto& motion = instances[instance].motion) {
    at = transform_point(placement.to_world * glm::inverse(motion->at(ray.time)), x);
  }
  // A point inside a volume as Cycles shades it (shader_setup_from_volume): its normals
  // and its incoming direction are all the ray's reversed, it has no surface and no
  // primitive. Object space: the inverse of the transform's linear part is the transpose
  // of its inverse transpose; Generated is that point in the mesh's texture space, as on
  // its surface (Cycles' generated transform of a volume mesh: the same texture space).
  Interaction it{};
  it.position = x;
  it.geometric_normal = -ray.direction;
  it.shading_normal = -ray.direction;
  it.material = &m;
  it.material_index = material;
  it.instance = instance;
  it.local_position =
      glm::transpose(placement.normal_to_world) * (at - Vec3(placement.to_world[3]));
  it.time = ray.time;
  ProgramHit hit;
  hit.incoming = -ray.direction;
  hit.normal = -ray.direction;
  hit.to_world = glm::mat3(placement.to_world);
  hit.normal_to_world = placement.normal_to_world;
  hit.images = m.program_images.data();
  // A Volume object's grids, read once for every input that reads one.
  const VolumeObject* volume = instances[instance].volume.get();
  const VolumeSample grids = volume ? volume->sample(at) : VolumeSample{};
  const SurfaceHit source{*this, it, ray, context, hit, /*inside=*/true, volume ? &grids : nullptr};
  Inputs inputs;
  for (size_t i = 0; i < m.program->inputs().size(); ++i) {
    // A Bump's offsets lie along a surface: inside a medium it reads the point itself.
    inputs[i] = source.input(m.program->inputs()[i] & ~(kInputBumpX | kInputBumpY));
  }
  hit.inputs = inputs.data();
  Registers r;
  m.program->run(hit, r.data());
  // Coefficients at least 0 and finite (NaN: 0), as the material's own are.
  const auto coefficient = [&](Field f, Color* c) {
    if (!m.driven(f)) return;
    const glm::vec4& v = r[static_cast<size_t>(m.outputs[f])];
    for (int k = 0; k < 3; ++k) {
      (*c)[k] = std::isnan(v[k]) ? 0.0f : std::clamp(v[k], 0.0f, limits::kMaxCoefficient);
    }
  };
  coefficient(kVolumeAbsorptionField, &out.absorption);
  coefficient(kVolumeScatteringField, &out.scattering);
  coefficient(kVolumeEmissionField, &out.emission);
  if (m.driven(kVolumeAnisotropyField)) {
    const float g = r[static_cast<size_t>(m.outputs[kVolumeAnisotropyField])].x;
    if (!std::isnan(g)) out.anisotropy = std::clamp(g, -0.999f, 0.999f);  // as the material's
  }
  return out;
}

namespace {

// The world program's radiance towards unit `direction`, its Light Path inputs given by
// `light_path(mode)`.
template <class LightPath>
Color run_world(const CompiledScene& scene, const Vec3& direction, const LightPath& light_path) {
  ProgramHit hit;
  hit.incoming = -direction;
  hit.normal = -direction;
  hit.images = scene.world_images.data();
  Inputs inputs;
  for (size_t i = 0; i < scene.world->inputs().size(); ++i) {
    const uint32_t mode = scene.world->inputs()[i];
    const bool along = mode == kInputPosition || mode == kInputNormal || mode == kInputGenerated ||
                       mode == kInputObject;
    inputs[i] = along                    ? glm::vec4(direction, 0.0f)
                : mode == kInputIncoming ? glm::vec4(hit.incoming, 0.0f)
                                         : light_path(mode);
  }
  hit.inputs = inputs.data();
  Registers r;
  scene.world->run(hit, r.data());
  return Color(r[scene.world_output]);
}

}  // namespace

Color CompiledScene::world_radiance(const Ray& ray, const RayContext& context) const {
  if (!world) return background;
  return run_world(*this, ray.direction,
                   [&](uint32_t mode) { return light_path_input(mode, ray, context); });
}

Color CompiledScene::world_light_radiance(const Vec3& direction, int depth) const {
  if (!world) return background;
  const auto light_path = [depth](uint32_t mode) {
    if (mode == kInputRayDepth) return glm::vec4(static_cast<float>(depth));
    return glm::vec4(mode == kInputIsDiffuseRay ? 1.0f : 0.0f);
  };
  return run_world(*this, direction, light_path);
}

Color CompiledScene::world_upward_mean() const {
  if (!world) return background;
  // Malley's method: the cells' centres of the unit square mapped onto the upper
  // hemisphere with density cos(theta)/pi, so the plain mean is the weighted one. Each
  // direction is read as a diffuse ray one bounce deep would see it.
  const auto light_path = [](uint32_t mode) {
    return glm::vec4(mode == kInputIsDiffuseRay || mode == kInputRayDepth ? 1.0f : 0.0f);
  };
  glm::dvec3 sum(0.0);
  for (int i = 0; i < kAmbientCells; ++i) {
    const double u1 = (i + 0.5) / kAmbientCells;
    const double radius = std::sqrt(u1);
    const double z = std::sqrt(1.0 - u1);
    for (int j = 0; j < kAmbientCells; ++j) {
      const double phi = 2.0 * std::numbers::pi * (j + 0.5) / kAmbientCells;
      const Vec3 direction(radius * std::cos(phi), radius * std::sin(phi), z);
      sum += glm::dvec3(run_world(*this, direction, light_path));
    }
  }
  return Color(sum / static_cast<double>(kAmbientCells * kAmbientCells));
}

}  // namespace whitted
