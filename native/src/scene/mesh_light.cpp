#include "scene/mesh_light.h"

#include <algorithm>
#include <cmath>

#include "scene/camera.h"
#include "scene/scene.h"

namespace whitted {
namespace {

// The power a triangle's emission stands for, per unit area: the mean of its channels
// (a saturated colour is not nearly dark, as its luminance would make it).
float strength(const Color& emission) {
  return (emission.r + emission.g + emission.b) / 3.0f;
}

// Whether a material's emission is the same everywhere: no program or texture can
// change it, or its alpha.
bool constant_emission(const Material& m) {
  return !m.driven(kEmissionField) && !m.driven(kAlphaField) && m.alpha_texture_index < 0;
}

// Whether a material may emit at all, by its constants and what its program drives.
bool may_emit(const Material& m) {
  if (m.emission_sampling == EmissionSampling::kNone) return false;
  if (m.driven(kEmissionField)) return true;
  return !is_black(m.emission) && m.alpha > 0.0f;
}

// The world-space corners of an instance's triangle `primitive` at shutter time `time`,
// with its front normal as interaction() finds it (the object-space winding's normal
// carried by the normal matrix: a mirroring transform keeps the outside out), its area
// and unit normal; false for a degenerate triangle, which sends no light.
bool place(const CompiledScene::Instance& instance, uint32_t primitive, float time,
           EmissiveTriangle* t) {
  const Mesh& mesh = instance.mesh->mesh;
  const uint32_t* tri = &mesh.triangles[3 * size_t{primitive}];
  const Vec3 a = mesh.vertex_at(tri[0], time);
  const Vec3 b = mesh.vertex_at(tri[1], time);
  const Vec3 c = mesh.vertex_at(tri[2], time);
  const Placement moved =
      instance.motion ? Placement::of(instance.motion->at(time)) : instance.placement;
  t->p0 = transform_point(moved.to_world, a);
  t->e1 = transform_point(moved.to_world, b) - t->p0;
  t->e2 = transform_point(moved.to_world, c) - t->p0;
  t->area = 0.5f * glm::length(glm::cross(t->e1, t->e2));
  const Vec3 front = moved.normal_to_world * glm::cross(b - a, c - a);
  const float front_length = glm::length(front);
  if (!(t->area > 0.0f) || !std::isfinite(t->area) || !(front_length > 0.0f) ||
      !std::isfinite(front_length)) {
    return false;
  }
  t->normal = front / front_length;
  return true;
}

}  // namespace

Color emitted(const CompiledScene& scene, const EmissiveTriangle& triangle,
              const glm::vec2& barycentric, const Ray& ray, const RayContext& context) {
  const uint32_t material = scene.material_index(triangle.instance, triangle.primitive);
  if (constant_emission(scene.materials[material])) {
    const SurfaceParams& constants = scene.material_constants[material];
    return constants.emission * constants.alpha;
  }
  Hit hit;
  hit.t = ray.t_max;
  hit.u = barycentric.x;
  hit.v = barycentric.y;
  hit.instance = triangle.instance;
  hit.primitive = triangle.primitive;
  const Interaction it = scene.interaction(ray, hit);
  const SurfaceParams surface = scene.surface(it, ray, context);
  return surface.emission * surface.alpha;
}

std::shared_ptr<const MeshLights> MeshLights::build(const CompiledScene& scene) {
  auto out = std::make_shared<MeshLights>();
  out->first_.assign(scene.instances.size(), -1);
  out->triangles_of_.assign(scene.instances.size(), 0);
  std::vector<double> power;
  // Programs may read the camera; at build time there is none: a default one stands in
  // (only the power estimate reads it, never a pixel).
  const Camera camera;
  const RayContext context{&camera, 0};
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    const CompiledScene::Instance& instance = scene.instances[i];
    if (instance.holdout) continue;
    bool any = false;
    for (uint32_t m : instance.materials) any |= may_emit(scene.materials[m]);
    if (instance.materials.empty()) any = may_emit(scene.materials[0]);
    if (!any) continue;
    const Mesh& mesh = instance.mesh->mesh;
    const size_t count = mesh.triangle_count();
    out->triangles_of_[i] = static_cast<uint32_t>(count);
    const auto first = static_cast<int64_t>(out->lookup_.size());
    out->lookup_.resize(out->lookup_.size() + count, -1);
    const size_t before = out->triangles_.size();
    // A tenth of each driven material's mean power per area floors its triangles'.
    std::vector<double> driven_sum(scene.materials.size(), 0.0);
    std::vector<double> driven_area(scene.materials.size(), 0.0);
    std::vector<uint32_t> material_of;
    for (uint32_t p = 0; p < count; ++p) {
      const uint32_t mi = scene.material_index(i, p);
      const Material& material = scene.materials[mi];
      if (!may_emit(material)) continue;
      // Its power is measured where the shutter opens (the frame, without motion blur).
      EmissiveTriangle t;
      if (!place(instance, p, 0.0f, &t)) continue;  // degenerate: it sends no light
      t.instance = i;
      t.primitive = p;
      t.sides = material.emission_sampling;
      // The emission at its centre, seen along its front normal.
      const glm::vec2 centre(1.0f / 3.0f, 1.0f / 3.0f);
      const Vec3 point = t.p0 + centre.x * t.e1 + centre.y * t.e2;
      const Ray ray{point + t.normal, -t.normal, 0.0f, 1.0f, 0u};
      const double per_area = std::max(0.0f, strength(emitted(scene, t, centre, ray, context)));
      if (!constant_emission(material)) {
        driven_sum[mi] += per_area * t.area;
        driven_area[mi] += t.area;
      } else if (!(per_area > 0.0)) {
        continue;  // a constant emission of zero strength
      }
      out->lookup_[static_cast<size_t>(first + p)] = static_cast<int32_t>(out->triangles_.size());
      out->triangles_.push_back(t);
      power.push_back(per_area * t.area);
      material_of.push_back(mi);
    }
    for (size_t k = before; k < out->triangles_.size(); ++k) {
      const uint32_t mi = material_of[k - before];
      if (driven_area[mi] > 0.0) {
        const double floor = 0.1 * driven_sum[mi] / driven_area[mi];
        power[k] = std::max(power[k], floor * out->triangles_[k].area);
      }
    }
    if (out->triangles_.size() > before) {
      out->first_[i] = first;
      out->objects_ += 1;
      out->moves_ = out->moves_ || instance.motion != nullptr || mesh.deforms();
    } else {
      out->lookup_.resize(static_cast<size_t>(first));
    }
  }
  // A textured emitter black everywhere at its centres has no power: it sends none.
  double total = 0.0;
  for (double p : power) total += p;
  if (!(total > 0.0) || !std::isfinite(total)) return std::make_shared<MeshLights>();
  out->cdf_.reserve(power.size());
  double sum = 0.0;
  for (double p : power) {
    sum += p;
    out->cdf_.push_back(static_cast<float>(sum / total));
  }
  out->cdf_.back() = 1.0f;
  return out;
}

MeshLights::Sample MeshLights::sample(const CompiledScene& scene, float u, float v,
                                      float time) const {
  const auto found = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  const auto index =
      static_cast<uint32_t>(std::min<ptrdiff_t>(found - cdf_.begin(), cdf_.size() - 1));
  const float low = index == 0 ? 0.0f : cdf_[index - 1];
  const float width = cdf_[index] - low;
  // u rescaled within the triangle's share: a second uniform number for the point.
  const float w = width > 0.0f ? std::clamp((u - low) / width, 0.0f, 1.0f) : 0.5f;
  const float root = std::sqrt(w);
  const glm::vec2 barycentric(root * (1.0f - v), root * v);
  const EmissiveTriangle t = at(scene, index, time);
  return {t, barycentric, t.p0 + barycentric.x * t.e1 + barycentric.y * t.e2, width / t.area};
}

EmissiveTriangle MeshLights::at(const CompiledScene& scene, uint32_t index, float time) const {
  const EmissiveTriangle& built = triangles_[index];
  if (!moves_) return built;
  const CompiledScene::Instance& instance = scene.instances[built.instance];
  if (!instance.motion && !instance.mesh->mesh.deforms()) return built;
  EmissiveTriangle moved = built;
  // Degenerate at this time (squashed flat mid-shutter): it keeps its opening's place,
  // a sample of which then finds nothing there and adds nothing.
  return place(instance, built.primitive, time, &moved) ? moved : built;
}

int32_t MeshLights::find(uint32_t instance, uint32_t primitive) const {
  if (instance >= first_.size() || first_[instance] < 0) return -1;
  // Past its triangles (a curve or a point of the same mesh): not sampled.
  if (primitive >= triangles_of_[instance]) return -1;
  return lookup_[static_cast<size_t>(first_[instance]) + primitive];
}

float MeshLights::density(uint32_t index, const EmissiveTriangle& triangle) const {
  const float low = index == 0 ? 0.0f : cdf_[index - 1];
  return (cdf_[index] - low) / triangle.area;
}

}  // namespace whitted
