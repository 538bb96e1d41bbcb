#include "scene/scene.h"

#include <array>
#include <chrono>
#include <glm/matrix.hpp>
#include <stdexcept>
#include <variant>

#include "core/limits.h"
#include "scene/mesh_light.h"

namespace whitted {
namespace {

template <typename Map>
void erase_or_throw(Map* map, const std::string& name, const char* kind) {
  if (map->erase(name) == 0) {
    throw std::invalid_argument(std::string("no ") + kind + " named '" + name + "'");
  }
}

// Embree traces an instance by moving the ray into object space with the inverse
// transform; a singular or near-singular transform (an object scaled to zero), or one
// absurdly far away, would make that ray invalid, which Embree's assertions turn into an
// abort. Such an instance shows nothing worth rendering, so it is left out (the bounds and
// their reason: core/limits.h).
bool safely_invertible(const glm::mat4& m) {
  constexpr float kLinearLimit = limits::kMaxInstanceLinear;
  constexpr float kTranslationLimit = limits::kMaxInstanceTranslation;
  const glm::mat3 linear(m);
  const glm::mat3 inverse = glm::inverse(linear);
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) {
      if (!(std::fabs(inverse[c][r]) <= kLinearLimit) ||
          !(std::fabs(linear[c][r]) <= kLinearLimit)) {
        return false;
      }
    }
    if (!(std::fabs(m[3][c]) <= kTranslationLimit)) return false;
  }
  return std::fabs(glm::determinant(linear)) > 0.0f;
}

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

// A material's fields before its textures and program: CompiledScene::material_constants.
SurfaceParams constant_surface(const Material& m) {
  return {m.diffuse,        m.specular,      m.shininess,         m.reflectivity,
          m.transmissivity, m.ior,           m.emission,          clamp_alpha(m.alpha),
          Vec3(0.0f),       m.coat_specular, m.coat_reflectivity, m.coat_shininess,
          m.coat_ior,       Vec3(0.0f),      m.diffuse_roughness, m.roughness,
          m.coat_roughness};
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

// The texture slots of a program resolved to scene textures (null for one that is not an
// image, which only a slot not sampled as an image may be).
std::vector<const ImageTexture*> resolve_images(
    const Program& program, const std::map<std::string, std::shared_ptr<const Texture>>& textures,
    const std::string& owner) {
  std::vector<const ImageTexture*> images;
  for (size_t slot = 0; slot < program.textures().size(); ++slot) {
    const std::string& name = program.textures()[slot];
    auto found = textures.find(name);
    if (found == textures.end()) {
      throw std::invalid_argument(owner + " uses missing texture '" + name + "'");
    }
    const auto* image = std::get_if<ImageTexture>(&found->second->source);
    if (image == nullptr && program.samples_image(slot)) {
      throw std::invalid_argument(owner + " samples texture '" + name +
                                  "' as an image, but it is a checker");
    }
    images.push_back(image);
  }
  return images;
}

}  // namespace

Scene::Scene() : device_(std::make_shared<AccelDevice>()) {}

Scene::Scene(const Scene& other) : camera(other.camera), device_(other.device_) {
  std::lock_guard lock(other.mutex_);
  state_ = other.state_;
}

void Scene::changed(bool geometry) {
  state_.snapshot.reset();
  if (geometry) {
    state_.accel.reset();
    state_.accel_masks.clear();
  }
}

void Scene::set_mesh(const std::string& name, Mesh mesh) {
  // The BVH is built outside the lock: it is the slow part, and touches no scene state.
  const auto t0 = std::chrono::steady_clock::now();
  auto entry = std::make_shared<const MeshEntry>(device_, std::move(mesh));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::lock_guard lock(mutex_);
  state_.meshes[name] = std::move(entry);
  state_.mesh_build_seconds += seconds;
  changed(true);
}

void Scene::set_instance(const std::string& name, Instance instance) {
  bool finite = is_finite(instance.to_world);
  for (const glm::mat4& m : instance.motion) finite = finite && is_finite(m);
  if (!finite) {
    throw std::invalid_argument("instance '" + name + "' has a NaN or infinite transform");
  }
  std::lock_guard lock(mutex_);
  state_.instances[name] = std::move(instance);
  changed(true);
}

void Scene::set_material(const std::string& name, const Material& material) {
  std::lock_guard lock(mutex_);
  state_.materials[name] = material;
  changed(false);
}
void Scene::set_light(const std::string& name, const Light& light) {
  std::lock_guard lock(mutex_);
  state_.lights[name] = light;
  changed(false);
}
void Scene::set_texture(const std::string& name, Texture texture) {
  auto shared = std::make_shared<const Texture>(std::move(texture));
  std::lock_guard lock(mutex_);
  state_.textures[name] = std::move(shared);
  changed(false);
}
void Scene::remove_mesh(const std::string& name) {
  std::lock_guard lock(mutex_);
  erase_or_throw(&state_.meshes, name, "mesh");
  changed(true);
}
void Scene::remove_instance(const std::string& name) {
  std::lock_guard lock(mutex_);
  erase_or_throw(&state_.instances, name, "instance");
  changed(true);
}
void Scene::remove_material(const std::string& name) {
  std::lock_guard lock(mutex_);
  erase_or_throw(&state_.materials, name, "material");
  changed(false);
}
void Scene::remove_light(const std::string& name) {
  std::lock_guard lock(mutex_);
  erase_or_throw(&state_.lights, name, "light");
  changed(false);
}
void Scene::remove_texture(const std::string& name) {
  std::lock_guard lock(mutex_);
  erase_or_throw(&state_.textures, name, "texture");
  changed(false);
}
void Scene::set_background(const Color& background) {
  std::lock_guard lock(mutex_);
  state_.background = background;
  changed(false);
}
void Scene::set_ambient(const Color& ambient) {
  std::lock_guard lock(mutex_);
  state_.ambient = ambient;
  changed(false);
}
void Scene::set_world(std::shared_ptr<const Program> program, uint32_t output) {
  if (program && output >= program->register_count()) {
    throw std::invalid_argument("world output register " + std::to_string(output) +
                                " out of range (" + std::to_string(program->register_count()) +
                                " registers)");
  }
  std::lock_guard lock(mutex_);
  state_.world = std::move(program);
  state_.world_output = output;
  changed(false);
}
Color Scene::background() const {
  std::lock_guard lock(mutex_);
  return state_.background;
}
Color Scene::ambient() const {
  std::lock_guard lock(mutex_);
  return state_.ambient;
}
size_t Scene::mesh_count() const {
  std::lock_guard lock(mutex_);
  return state_.meshes.size();
}
double Scene::mesh_build_seconds() const {
  std::lock_guard lock(mutex_);
  return state_.mesh_build_seconds;
}
size_t Scene::instance_count() const {
  std::lock_guard lock(mutex_);
  return state_.instances.size();
}
uint64_t Scene::top_level_builds() const {
  std::lock_guard lock(mutex_);
  return state_.top_level_builds;
}

std::shared_ptr<const CompiledScene> Scene::compile(bool* built_top_level) const {
  std::lock_guard lock(mutex_);
  if (built_top_level != nullptr) *built_top_level = false;
  if (state_.snapshot) return state_.snapshot;
  auto compiled = std::make_shared<CompiledScene>();
  compiled->background = state_.background;
  compiled->ambient = state_.ambient;
  if (state_.world) {
    compiled->world = state_.world;
    compiled->world_output = state_.world_output;
    compiled->world_images = resolve_images(*state_.world, state_.textures, "the world");
  }
  std::map<std::string, int32_t> texture_index;
  for (const auto& [name, texture] : state_.textures) {
    texture_index[name] = static_cast<int32_t>(compiled->textures.size());
    compiled->textures.push_back(texture);
  }
  const auto resolve_texture = [&](const std::string& material, const std::string& texture) {
    if (texture.empty()) return -1;
    auto found = texture_index.find(texture);
    if (found == texture_index.end()) {
      throw std::invalid_argument("material '" + material + "' uses missing texture '" + texture +
                                  "'");
    }
    return found->second;
  };
  std::map<std::string, uint32_t> material_index;
  compiled->materials.push_back(Material{});
  compiled->material_names.emplace_back();
  for (const auto& [name, material] : state_.materials) {
    material_index[name] = static_cast<uint32_t>(compiled->materials.size());
    Material resolved = material;
    resolved.diffuse_texture_index = resolve_texture(name, material.diffuse_texture);
    resolved.alpha_texture_index = resolve_texture(name, material.alpha_texture);
    if (material.program) {
      resolved.program_images =
          resolve_images(*material.program, state_.textures, "material '" + name + "'");
    }
    compiled->materials.push_back(std::move(resolved));
    compiled->material_names.push_back(name);
  }
  for (const Material& material : compiled->materials) {
    compiled->material_constants.push_back(constant_surface(material));
  }
  for (const auto& [name, light] : state_.lights) {
    compiled->light_linking = compiled->light_linking || light.light_sets != kAllLightSets ||
                              light.shadow_sets != kAllLightSets;
    compiled->lights.push_back(light);
    compiled->light_names.push_back(name);
  }

  // Instances are resolved anew each time (cheap); their order and the set left out
  // depend only on meshes and instances, so an existing top-level BVH still matches.
  std::vector<AccelInstance> accel_instances;
  std::vector<uint32_t> masks;
  for (const auto& [name, instance] : state_.instances) {
    auto mesh = state_.meshes.find(instance.mesh);
    if (mesh == state_.meshes.end()) {
      throw std::invalid_argument("instance '" + name + "' uses missing mesh '" + instance.mesh +
                                  "'");
    }
    CompiledScene::Instance out;
    out.mesh = mesh->second;
    out.placement = Placement::of(instance.to_world);
    // Motion whose every sample can be inverted (Embree inverts the blend); a sample of
    // zero scale (an object shrinking to nothing) leaves it at the frame's transform.
    bool invertible = true;
    for (const glm::mat4& m : instance.motion) invertible = invertible && safely_invertible(m);
    if (invertible && instance.motion.size() > 1) {
      auto motion = std::make_shared<const TransformMotion>(instance.motion);
      if (motion->moves()) out.motion = std::move(motion);
    }
    out.holdout = instance.holdout;
    out.visibility = instance.visibility;
    out.info = instance.info;
    out.name = name;
    out.cryptomatte = instance.cryptomatte;
    out.links = instance.links;
    for (const std::string& material : instance.materials) {
      if (material.empty()) {
        out.materials.push_back(0);
        continue;
      }
      auto found = material_index.find(material);
      if (found == material_index.end()) {
        throw std::invalid_argument("instance '" + name + "' uses missing material '" + material +
                                    "'");
      }
      out.materials.push_back(found->second);
    }
    if (out.mesh->mesh.primitive_count() == 0) continue;  // nothing to hit
    if (!safely_invertible(instance.to_world)) {
      compiled->degenerate_instances += 1;
      continue;
    }
    // Shadow feelers meet opaque and translucent instances in separate queries (ray.h).
    uint32_t mask = instance.visibility;
    if ((mask & kShadowRay) != 0) {
      bool translucent = false;
      for (uint32_t index : out.materials) translucent |= compiled->materials[index].translucent();
      mask |= translucent ? kTranslucentShadowRay : kOpaqueShadowRay;
    }
    // Aliasing pointer: the mesh BVH, keeping its whole entry (the arrays) alive.
    accel_instances.push_back({std::shared_ptr<const MeshAccel>(out.mesh, &out.mesh->accel),
                               out.placement.to_world, mask, out.motion});
    masks.push_back(mask);
    compiled->shadow_sets.push_back(out.links.shadow_set);
    compiled->light_linking = compiled->light_linking || out.links.linked();
    compiled->moves = compiled->moves || out.motion != nullptr || out.mesh->mesh.deforms();
    compiled->instances.push_back(std::move(out));
  }
  if (!state_.accel || masks != state_.accel_masks) {
    state_.accel = std::make_shared<const SceneAccel>(device_, accel_instances);
    state_.accel_masks = std::move(masks);
    state_.top_level_builds += 1;
    if (built_top_level != nullptr) *built_top_level = true;
  }
  compiled->accel = state_.accel;
  compiled->mesh_lights = MeshLights::build(*compiled);
  state_.snapshot = compiled;
  return compiled;
}

Placement Placement::of(const glm::mat4& to_world) {
  Placement p;
  p.to_world = to_world;
  p.normal_to_world = glm::transpose(glm::inverse(glm::mat3(to_world)));
  for (int c = 0; c < 3; ++c) p.abs_linear[c] = glm::abs(Vec3(to_world[c]));
  p.abs_translation = glm::abs(Vec3(to_world[3]));
  return p;
}

size_t CompiledScene::triangle_count() const {
  size_t n = 0;
  for (const Instance& instance : instances) n += instance.mesh->mesh.triangle_count();
  return n;
}

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

TexturePoint CompiledScene::texture_point(const Interaction& it) const {
  const Mesh& mesh = instances[it.instance].mesh->mesh;
  TexturePoint tp;
  tp.object = it.local_position;
  tp.generated = (it.local_position - mesh.texspace_location + mesh.texspace_size) /
                 (2.0f * mesh.texspace_size);
  if (!mesh.uvs.empty() && mesh.kind(it.primitive) == PrimitiveKind::kTriangle) {
    tp.uv = glm::vec2(interpolate_corners(mesh.uvs, 2, it.primitive, it.barycentric));
  }
  return tp;
}

namespace {

// Where a program reads a surface hit: the inputs it asks for, computed on demand.
struct SurfaceHit {
  const CompiledScene& scene;
  const Interaction& it;
  const Ray& ray;
  const RayContext& context;
  const ProgramHit& hit;

  glm::vec4 input(uint32_t mode) const {
    const CompiledScene::Instance& instance = scene.instances[it.instance];
    const Mesh& mesh = instance.mesh->mesh;
    const auto vec = [](const Vec3& v) { return glm::vec4(v, 0.0f); };
    // Corner layers are a triangle's: a curve or a point reads 0 from them.
    const bool triangle = mesh.kind(it.primitive) == PrimitiveKind::kTriangle;
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
        return vec((it.local_position - mesh.texspace_location + mesh.texspace_size) /
                   (2.0f * mesh.texspace_size));
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
      case kInputObjectLocation:
        return vec(instance.info.location);
      case kInputObjectRandom:
        return glm::vec4(instance.info.random);
      case kInputObjectIndex:
        return glm::vec4(instance.info.pass_index);
      case kInputObjectColor:
        return instance.info.color;
      case kInputObjectNormal:
        return vec(object_normal(mesh));
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
  // The object-space normal a tangent-space normal map bends: the interpolated corner
  // normals, not normalised, or the face's normal on a flat mesh.
  Vec3 object_normal(const Mesh& mesh) const {
    if (mesh.kind(it.primitive) != PrimitiveKind::kTriangle) {
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
    normal(kNormalField, &out.normal);
    if (lifts && m.driven(kNormalField)) {
      // On the side the ray comes from, as Cycles' shading frame is.
      const float side = hit.backfacing ? -1.0f : 1.0f;
      out.normal =
          side * valid_reflection(side * it.geometric_normal, hit.incoming, side * out.normal);
    }
    normal(kCoatNormalField, &out.coat_normal);
    if (m.driven(kCoatSpecularField)) out.coat_specular = field(kCoatSpecularField).x;
    if (m.driven(kCoatReflectivityField)) out.coat_reflectivity = field(kCoatReflectivityField).x;
    if (m.driven(kCoatShininessField)) {
      out.coat_shininess = std::fmax(field(kCoatShininessField).x, 0.0f);
    }
    if (m.driven(kCoatIorField)) {
      const float ior = field(kCoatIorField).x;
      if (ior > 0.0f && std::isfinite(ior)) out.coat_ior = ior;
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
  }
  out.alpha = clamp_alpha(out.alpha);
  return out;
}

Color CompiledScene::world_radiance(const Ray& ray, const RayContext& context) const {
  if (!world) return background;
  ProgramHit hit;
  hit.incoming = -ray.direction;
  hit.normal = -ray.direction;
  hit.images = world_images.data();
  Inputs inputs;
  for (size_t i = 0; i < world->inputs().size(); ++i) {
    const uint32_t mode = world->inputs()[i];
    const bool direction = mode == kInputPosition || mode == kInputNormal ||
                           mode == kInputGenerated || mode == kInputObject;
    inputs[i] = direction                ? glm::vec4(ray.direction, 0.0f)
                : mode == kInputIncoming ? glm::vec4(hit.incoming, 0.0f)
                                         : light_path_input(mode, ray, context);
  }
  hit.inputs = inputs.data();
  Registers r;
  world->run(hit, r.data());
  return Color(r[world_output]);
}

}  // namespace whitted
