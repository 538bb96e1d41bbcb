// Emissive meshes as lights: every triangle of an instance whose material emits (after
// its program) and whose Emission Sampling samples a side is a patch of light, like an
// area light's. Shadow feelers pick a triangle by its emitted power from a power table
// (a cumulative sum searched in O(log n), 4 bytes a triangle beside the triangle's own
// 64), then a point uniformly on it; the triangle's emission there, seen from the
// shading point, is what the feeler brings if nothing blocks it.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec2.hpp>

#include "core/ray.h"
#include "scene/material.h"

namespace whitted {

struct CompiledScene;
struct RayContext;

// One emitting triangle, in world space.
struct EmissiveTriangle {
  Vec3 p0{0.0f};
  Vec3 e1{0.0f};      // p1 - p0
  Vec3 e2{0.0f};      // p2 - p0
  Vec3 normal{0.0f};  // unit, its front side (as the mesh's faces wind)
  float area = 0.0f;
  uint32_t instance = 0;  // CompiledScene::instances index
  uint32_t primitive = 0;
  EmissionSampling sides = EmissionSampling::kBoth;

  // Whether a point on the side `towards` points to (from the triangle) is lit by its
  // sampled sides.
  bool lights(const Vec3& towards) const {
    const bool front = glm::dot(towards, normal) > 0.0f;
    return sides == EmissionSampling::kBoth || (front && sides == EmissionSampling::kFront) ||
           (!front && sides == EmissionSampling::kBack);
  }
};

// The emissive meshes of a compiled scene, with the power table that picks among them.
class MeshLights {
 public:
  // Every sampled triangle of positive area and emission; a triangle's power is its area
  // times the luminance of its emission at its centre (for emission a program or
  // texture drives, at least a tenth of its material's mean, so that no emitting part
  // of a textured emitter has probability 0).
  static std::shared_ptr<const MeshLights> build(const CompiledScene& scene);

  struct Sample {
    EmissiveTriangle triangle;  // where it is at the sample's time
    glm::vec2 barycentric;      // weights of the triangle's vertices 1 and 2
    Vec3 point;                 // world space
    float density;              // per unit area: the triangle's probability over its area
  };
  // The sample of two numbers in [0, 1) at shutter time `time`: u picks a triangle by
  // power (and, rescaled within its share, with v, the point: uniform over the triangle
  // where it is at `time`). Not on empty().
  Sample sample(const CompiledScene& scene, float u, float v, float time) const;

  // The index of the sampled triangle an instance's primitive is, or -1.
  int32_t find(uint32_t instance, uint32_t primitive) const;
  // Triangle `index` where it is at shutter time `time`: a moving or deforming
  // emitter's triangle moved there (its power share stays the shutter opening's), the
  // others' as built.
  EmissiveTriangle at(const CompiledScene& scene, uint32_t index, float time) const;
  // The density sample() draws a point of triangle `index`, found at `triangle`, with.
  float density(uint32_t index, const EmissiveTriangle& triangle) const;

  bool empty() const { return triangles_.empty(); }
  const std::vector<EmissiveTriangle>& triangles() const { return triangles_; }
  size_t objects() const { return objects_; }  // instances with a sampled triangle

 private:
  std::vector<EmissiveTriangle> triangles_;
  std::vector<float> cdf_;  // cdf_[i]: the probability of triangles 0..i; the last is 1
  // By instance: where its primitives start in `lookup_` (-1: none emit).
  std::vector<int64_t> first_;
  std::vector<int32_t> lookup_;         // primitive -> triangle index, or -1
  std::vector<uint32_t> triangles_of_;  // by instance: its mesh's triangle count
  size_t objects_ = 0;
  bool moves_ = false;  // whether an emitting instance moves or deforms within the shutter
};

// The radiance a mesh light sends from `barycentric` on `triangle` along `ray` (which
// ends there), alpha applied: the material's constant emission, or its program's and
// textures' at that point.
Color emitted(const CompiledScene& scene, const EmissiveTriangle& triangle,
              const glm::vec2& barycentric, const Ray& ray, const RayContext& context);

}  // namespace whitted
