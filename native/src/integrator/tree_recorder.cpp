#include "integrator/tree_recorder.h"

#include <cmath>

#include "integrator/whitted.h"

namespace whitted {

TreeRecorder::TreeRecorder(const WhittedIntegrator& integrator, SampleRecord* /*record*/)
    : scene_(integrator.scene()), tree_(integrator.tree()) {}

int TreeRecorder::add(const Ray& ray, int depth, TreeRayKind kind, int parent, const Color& share) {
  RayTreeNode node;
  node.kind = kind;
  node.depth = depth;
  node.origin = ray.origin;
  node.direction = ray.direction;
  node.time = ray.time;
  node.weight = tree_->scale * share;
  return tree_->add(node, parent);
}

TreeRecorder::Node TreeRecorder::ray(const Ray& ray, int depth, Node in_front, float behind,
                                     const Color& through) {
  if (in_front.index < 0) {
    return {add(ray, depth, tree_->next_kind, tree_->current, share(behind, through))};
  }
  return {add(ray, depth, TreeRayKind::kTransparent, in_front.index, share(behind, through))};
}

void TreeRecorder::hit(Node node, const Interaction& it) {
  RayTreeNode& n = at(node);
  n.hit = true;
  n.end = it.position;
  n.instance = static_cast<int32_t>(it.instance);
  n.material = static_cast<int32_t>(it.material_index);
}

void TreeRecorder::program_ray(Node node, const Ray& ray, int depth, TreeRayKind kind,
                               bool blocked) {
  const int index = add(ray, depth, kind, node.index, Color(0.0f));
  RayTreeNode& n = tree_->nodes[static_cast<size_t>(index)];
  n.transmittance = Color(blocked ? 0.0f : 1.0f);
  if (std::isfinite(ray.t_max)) n.end = ray.origin + ray.t_max * ray.direction;
}

TreeRecorder::Scope TreeRecorder::segment(Node node, const Ray& segment, float length, float behind,
                                          const Color& through) {
  const int index =
      add(segment, at(node).depth, TreeRayKind::kVolume, node.index, share(behind, through));
  RayTreeNode& n = tree_->nodes[static_cast<size_t>(index)];
  if (std::isfinite(length)) n.end = segment.origin + length * segment.direction;
  return {tree_, index, n.weight};
}

TreeRecorder::Node TreeRecorder::scatter(const Ray& feeler, const Color& unshadowed, int32_t light,
                                         int32_t emitter, int depth) {
  const int index = add(feeler, depth, TreeRayKind::kShadow, tree_->current, Color(1.0f));
  RayTreeNode& n = tree_->nodes[static_cast<size_t>(index)];
  n.light = light;
  n.emitter = emitter;
  n.scattered = n.weight * unshadowed;
  n.cut = TreeCut::kUnshadowed;  // until its feeler is sent
  if (std::isfinite(feeler.t_max)) n.end = feeler.origin + feeler.t_max * feeler.direction;
  return {index};
}

void TreeRecorder::segment_light(int /*depth*/, const SegmentLight& light) {
  RayTreeNode& n = tree_->nodes[static_cast<size_t>(tree_->current)];
  n.emission = tree_->scale * light.emitted;
  n.transmittance = light.transmittance;
  n.steps = light.steps;
}

void TreeRecorder::escaped(Node node, int /*depth*/, float behind, const Color& through,
                           const Color& world, bool shown) {
  RayTreeNode& n = at(node);
  if (shown) n.background = tree_->scale * share(behind, through) * world;
}

TreeRecorder::Scope TreeRecorder::cover(Node node, float behind, float a, const Color& through) {
  return {tree_, node.index, tree_->scale * share(behind, through) * a};
}

TreeRecorder::Node TreeRecorder::feeler(const Interaction& it, const LightSample& ls, int32_t light,
                                        int32_t emitter, int depth) {
  RayTreeNode node;
  node.kind = TreeRayKind::kShadow;
  node.depth = depth;
  node.origin = it.shadow_origin;
  node.direction = ls.wi;
  node.time = it.time;
  node.light = light;
  node.emitter = emitter;
  node.weight = tree_->scale;
  if (!std::isinf(ls.distance)) node.end = it.shadow_origin + ls.wi * ls.distance;
  return {tree_->add(node, tree_->current)};
}

void TreeRecorder::unsent(Node node, TreeCut why) {
  at(node).cut = why;
}

void TreeRecorder::unshadowed(Node node, const ShadingPoint& p, const LightTerms& t,
                              const LightSample& ls) {
  RayTreeNode& n = at(node);
  const Color arriving = tree_->scale * ls.irradiance;
  n.diffuse = arriving * (t.lit * kInvPi * t.fade) * p.surface.diffuse +
              arriving * (t.lit * t.loss) * p.multiscatter;
  n.specular = arriving * (t.lit * p.phong_norm * t.lobe * p.surface.specular + Color(t.coat));
  if (p.alpha > 0.0f) n.specular += arriving * t.glossy * p.surface.reflectivity * p.energy;
  if (t.sheen > 0.0f) n.specular += arriving * sheen_share(p, t);
  if (t.layer > 0.0f) n.specular += arriving * t.layer * p.layer_tint;
  n.cut = TreeCut::kUnshadowed;
}

void TreeRecorder::shadow(Node node, const Ray& ray, const Color& transmittance) {
  RayTreeNode& n = at(node);
  n.cut = TreeCut::kNone;
  n.transmittance = transmittance;
  Hit blocker;
  if (transmittance != Color(1.0f) && scene_.accel->intersect(ray, &blocker)) {
    hit(node, scene_.interaction(ray, blocker));
  }
}

void TreeRecorder::local(const ShadingPoint& /*p*/, int /*depth*/, const Color& emission,
                         const Color& ambient, const Color& /*total*/) {
  RayTreeNode& n = tree_->nodes[static_cast<size_t>(tree_->current)];
  n.emission = tree_->scale * emission;
  n.ambient = tree_->scale * ambient;
}

TreeRecorder::Scope TreeRecorder::branch(const Color& weight, float share, TreeRayKind kind) {
  return {tree_, tree_->current, tree_->scale * (weight * share), kind};
}

void TreeRecorder::cut(const Ray& ray, int depth, TreeRayKind kind, const Color& weight,
                       float share, TreeCut why) {
  const int node = add(ray, depth, kind, tree_->current, weight * share);
  tree_->nodes[static_cast<size_t>(node)].cut = why;
}

}  // namespace whitted
