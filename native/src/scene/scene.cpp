#include "scene/scene.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
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

// Whether no primitive of `instance` has a surface: the material of every slot its mesh
// uses has none (Material::surface).
bool surfaceless(const std::vector<Material>& materials, const CompiledScene::Instance& instance) {
  const size_t slots = instance.mesh->slots;
  if (instance.materials.size() < slots) return false;  // the rest take the default material
  return std::all_of(instance.materials.begin(), instance.materials.begin() + slots,
                     [&](uint32_t m) { return !materials[m].surface; });
}

// Whether `instance` bounds a glowing medium (Material::glows): a slot of its mesh whose
// material has no surface and a volume that emits.
bool glowing_medium(const std::vector<Material>& materials,
                    const CompiledScene::Instance& instance) {
  const size_t slots = std::min(instance.mesh->slots, instance.materials.size());
  return std::any_of(instance.materials.begin(), instance.materials.begin() + slots,
                     [&](uint32_t m) { return !materials[m].surface && materials[m].glows(); });
}

// Extends *out by the eight corners of `box` (not empty) placed by `to_world`.
void extend_placed(const Box& box, const glm::mat4& to_world, Box* out) {
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p((corner & 1) != 0 ? box.upper.x : box.lower.x,
                 (corner & 2) != 0 ? box.upper.y : box.lower.y,
                 (corner & 4) != 0 ? box.upper.z : box.lower.z);
    const Vec3 placed = transform_point(to_world, p);
    out->lower = glm::min(out->lower, placed);
    out->upper = glm::max(out->upper, placed);
  }
}

// The world box of `instance`'s mesh wherever the shutter takes it: its world_box, and
// the box placed by each step of its motion.
Box box_over_shutter(const CompiledScene::Instance& instance) {
  Box out = instance.world_box;
  const Box& box = instance.mesh->box;
  if (!instance.motion || box.empty()) return out;
  for (const glm::mat4& m : instance.motion->steps()) extend_placed(box, m, &out);
  return out;
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

void Scene::world_changed() {
  changed(false);
  state_.world_light.reset();
  state_.world_light_built = false;
}

size_t Scene::displace(Mesh* mesh, std::vector<SlotDisplacement> slots,
                       const glm::mat4& to_world) const {
  // The textures are shared: a copy of the map keeps them alive outside the lock.
  std::map<std::string, std::shared_ptr<const Texture>> textures;
  {
    std::lock_guard lock(mutex_);
    textures = state_.textures;
  }
  std::vector<const SlotDisplacement*> by_slot;
  for (SlotDisplacement& slot : slots) {
    if (slot.program) {
      slot.images = resolve_images(*slot.program, textures, "a displacement");
    }
    by_slot.push_back(slot.program ? &slot : nullptr);
  }
  return whitted::displace(mesh, by_slot, to_world);
}

bool Scene::world_reads(const std::string& texture) const {
  if (!state_.world) return false;
  const std::vector<std::string>& names = state_.world->textures();
  return std::find(names.begin(), names.end(), texture) != names.end();
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
  if (world_reads(name)) world_changed();
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
  if (world_reads(name)) world_changed();
}
void Scene::set_background(const Color& background) {
  std::lock_guard lock(mutex_);
  state_.background = background;
  world_changed();
}
void Scene::set_ambient(const Color& ambient) {
  std::lock_guard lock(mutex_);
  state_.ambient = ambient;
  changed(false);
}
void Scene::set_world(std::shared_ptr<const Program> program, uint32_t output,
                      float ambient_strength) {
  if (!std::isfinite(ambient_strength)) {
    throw std::invalid_argument("the world's ambient strength must be finite");
  }
  if (program && output >= program->register_count()) {
    throw std::invalid_argument("world output register " + std::to_string(output) +
                                " out of range (" + std::to_string(program->register_count()) +
                                " registers)");
  }
  std::lock_guard lock(mutex_);
  state_.world = std::move(program);
  state_.world_output = output;
  state_.world_ambient_strength = ambient_strength;
  world_changed();
}
void Scene::set_world_light(const WorldLightParams& params) {
  if (params.width < 0 || params.height < 0 || params.width > kMaxWorldMap ||
      params.height > kMaxWorldMap) {
    throw std::invalid_argument("the world light's map must be 0 to " +
                                std::to_string(kMaxWorldMap) + " texels a side");
  }
  if (!std::isfinite(params.sun_angle) || !is_finite(params.sun_direction)) {
    throw std::invalid_argument("the world's sun must have a finite direction and size");
  }
  WorldLightParams checked = params;
  checked.sun_angle = std::clamp(params.sun_angle, 0.0f, kPi);
  if (checked.sun_angle > 0.0f) {
    const float length = glm::length(params.sun_direction);
    if (!(length > 0.0f)) throw std::invalid_argument("the world's sun needs a direction");
    checked.sun_direction = params.sun_direction / length;
  }
  checked.max_bounces = std::max(0, params.max_bounces);
  std::lock_guard lock(mutex_);
  state_.world_light_params = checked;
  world_changed();
}
void Scene::set_world_visibility(uint32_t kinds) {
  std::lock_guard lock(mutex_);
  state_.world_visibility = kinds & (kCameraRay | kReflectionRay | kRefractionRay);
  changed(false);
}
void Scene::set_world_medium(const Material& medium) {
  std::lock_guard lock(mutex_);
  state_.world_medium = medium;
  changed(false);
}
WorldLightParams Scene::world_light_params() const {
  std::lock_guard lock(mutex_);
  return state_.world_light_params;
}
Color Scene::background() const {
  std::lock_guard lock(mutex_);
  return state_.background;
}
Color Scene::ambient() const {
  return compile()->ambient;
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
uint64_t Scene::world_light_builds() const {
  std::lock_guard lock(mutex_);
  return state_.world_light_builds;
}

std::shared_ptr<const CompiledScene> Scene::compile(bool* built_top_level,
                                                    double* world_light_seconds) const {
  std::lock_guard lock(mutex_);
  if (built_top_level != nullptr) *built_top_level = false;
  if (world_light_seconds != nullptr) *world_light_seconds = 0.0;
  if (state_.snapshot) return state_.snapshot;
  auto compiled = std::make_shared<CompiledScene>();
  compiled->background = state_.background;
  compiled->ambient = state_.ambient;
  if (state_.world) {
    compiled->world = state_.world;
    compiled->world_output = state_.world_output;
    compiled->world_images = resolve_images(*state_.world, state_.textures, "the world");
    compiled->ambient = state_.world_ambient_strength * compiled->world_upward_mean();
  }
  // The world light's map is evaluated once per world: kept across the snapshots of
  // other edits (the viewport's), rebuilt when the world, its images or its settings change.
  if (!state_.world_light_built) {
    const auto t0 = std::chrono::steady_clock::now();
    state_.world_light = WorldLight::build(*compiled, state_.world_light_params);
    state_.world_light_built = true;
    state_.world_light_builds += 1;
    if (world_light_seconds != nullptr) {
      *world_light_seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
  }
  compiled->world_light = state_.world_light;
  compiled->world_light_params = state_.world_light_params;
  compiled->world_visibility = state_.world_visibility;
  compiled->world_medium = state_.world_medium;
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
  // Index 0 is the default material, what an empty slot renders with: the material set
  // as "" (Blender 5.0+'s default surface, export/material.py), else Material{}.
  std::map<std::string, uint32_t> material_index;
  compiled->materials.push_back(Material{});
  compiled->material_names.emplace_back();
  for (const auto& [name, material] : state_.materials) {
    const bool default_material = name.empty();
    if (!default_material) {
      material_index[name] = static_cast<uint32_t>(compiled->materials.size());
    }
    Material resolved = material;
    resolved.diffuse_texture_index = resolve_texture(name, material.diffuse_texture);
    resolved.alpha_texture_index = resolve_texture(name, material.alpha_texture);
    if (material.program) {
      resolved.program_images =
          resolve_images(*material.program, state_.textures, "material '" + name + "'");
    }
    if (default_material) {
      compiled->materials[0] = std::move(resolved);
      continue;
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
    if (light.has_shape()) compiled->lamps_visibility |= light.visibility;
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
    if (const Box& box = out.mesh->box; !box.empty()) {
      extend_placed(box, instance.to_world, &out.world_box);
    }
    // Motion whose every sample can be inverted (Embree inverts the blend); a sample of
    // zero scale (an object shrinking to nothing) leaves it at the frame's transform.
    bool invertible = true;
    for (const glm::mat4& m : instance.motion) invertible = invertible && safely_invertible(m);
    if (invertible && instance.motion.size() > 1) {
      auto motion = std::make_shared<const TransformMotion>(instance.motion);
      if (motion->moves()) out.motion = std::move(motion);
    }
    out.holdout = instance.holdout;
    out.shadow_catcher = instance.shadow_catcher;
    out.visibility = instance.visibility;
    out.info = instance.info;
    out.attributes = instance.attributes;
    out.name = name;
    out.cryptomatte = instance.cryptomatte;
    out.volume = instance.volume;
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
    // A mesh without any surface (the bounds of a volume) stays in the scene, seen by no
    // ray: every ray passes through it untouched, and none pays for it.
    if (surfaceless(compiled->materials, out)) out.visibility = 0;
    // Shadow feelers meet opaque and translucent instances in separate queries (ray.h).
    uint32_t mask = out.visibility;
    if ((mask & kShadowRay) != 0) {
      bool translucent = false;
      for (uint32_t index : out.materials) translucent |= compiled->materials[index].translucent();
      mask |= translucent ? kTranslucentShadowRay : kOpaqueShadowRay;
      // A catcher's feelers with the catchers alone (integrator/catcher.h) meet it.
      if (out.shadow_catcher) mask |= kCatcherShadowRay;
    }
    // The bounds of a medium without a surface: found by the queries of scenes with media.
    for (uint32_t index : out.materials) {
      const Material& material = compiled->materials[index];
      if (!material.surface && material.participating()) mask |= kVolumeBoundRay;
    }
    // Aliasing pointer: the mesh BVH, keeping its whole entry (the arrays) alive.
    accel_instances.push_back({std::shared_ptr<const MeshAccel>(out.mesh, &out.mesh->accel),
                               out.placement.to_world, mask, out.motion});
    masks.push_back(mask);
    compiled->shadow_sets.push_back(out.links.shadow_set);
    compiled->light_linking = compiled->light_linking || out.links.linked();
    compiled->moves = compiled->moves || out.motion != nullptr || out.mesh->mesh.deforms();
    if (glowing_medium(compiled->materials, out)) {
      const Box box = box_over_shutter(out);
      const Vec3 centre = 0.5f * (box.lower + box.upper);
      compiled->glowing.push_back({static_cast<uint32_t>(compiled->instances.size()), centre,
                                   0.5f * glm::length(box.upper - box.lower)});
    }
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

}  // namespace whitted
