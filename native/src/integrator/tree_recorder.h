// The inspector's recorder (issue 17): every ray the kernel traces, or would have traced
// but cut, written into a RayTree with what it adds to the pixel on its own.
#pragma once

#include <cstdint>

#include "integrator/kernel_recorder.h"
#include "integrator/ray_tree.h"

namespace whitted {

// Its position in the recursion is the tree's (RayTree::current, scale, next_kind): the
// node whose surface is being shaded, the weight a term there gets on the pixel, and the
// kind of the next child ray. A node's weight is the tree's scale times its share of it
// (the part not covered by cut-outs in front, or the sigma_r / sigma_t of the surface
// being shaded).
class TreeRecorder : public NoRecorder {
 public:
  struct Node {
    int index = -1;  // in RayTree::nodes; -1: none
  };
  using Scope = RayTree::Scope;
  static constexpr bool kBatchesFeelers = false;  // each feeler its own node

  TreeRecorder(const WhittedIntegrator& integrator, SampleRecord* record);

  Node ray(const Ray& ray, int depth, Node in_front, float behind, const Color& through);
  void hit(Node node, const Interaction& it);
  void crossed(Node node, const Interaction& it) { hit(node, it); }
  void program_ray(Node node, const Ray& ray, int depth, TreeRayKind kind, bool blocked);
  // A segment is a kVolume node under its ray, the parent of its scatter() feelers.
  Scope segment(Node node, const Ray& segment, float length, float behind, const Color& through);
  Node scatter(const Ray& feeler, const Color& unshadowed, int32_t light, int32_t emitter,
               int depth);
  void segment_light(int depth, const SegmentLight& light);
  void escaped(Node node, int depth, float behind, const Color& through, const Color& world,
               bool shown);
  Scope cover(Node node, float behind, float a, const Color& through);
  Node feeler(const Interaction& it, const LightSample& ls, int32_t light, int32_t emitter,
              int depth);
  void unsent(Node node, TreeCut why);
  // The sample's diffuse and specular terms, unshadowed (the coat's highlight counts as
  // specular); counted as unshadowed until its shadow ray is sent.
  void unshadowed(Node node, const ShadingPoint& p, const LightTerms& t, const LightSample& ls);
  // What got through, and the first surface in the shadow ray's way, if any.
  void shadow(Node node, const Ray& ray, const Color& transmittance);
  void local(const ShadingPoint& p, int depth, const Color& emission, const Color& ambient,
             const Color& total);
  Scope branch(const Color& weight, float share, TreeRayKind kind);
  void cut(const Ray& ray, int depth, TreeRayKind kind, const Color& weight, float share,
           TreeCut why);

 private:
  // A ray of `kind` under `parent`, its weight the tree's scale times `share`.
  int add(const Ray& ray, int depth, TreeRayKind kind, int parent, const Color& share);
  // The share of the tree's scale a layer of a ray has: the part `behind` the cut-outs in
  // front, times what the media in front let `through`.
  static Color share(float behind, const Color& through) { return Color(behind) * through; }
  RayTreeNode& at(Node node) { return tree_->nodes[static_cast<size_t>(node.index)]; }

  const CompiledScene& scene_;
  RayTree* tree_;
};

}  // namespace whitted
