// The inspector's ray tree as plain Python data: names instead of indices, colours and
// points as lists, what a feeler found as "blocked", a feeler to the world as "world", a
// ray's segment inside media as a "volume" node, the parent of its scatter points' feelers.
#include "integrator/ray_tree.h"

#include "bindings.h"
#include "scene/scene.h"

namespace whitted::python {
namespace {

const char* kind_name(TreeRayKind kind) {
  switch (kind) {
    case TreeRayKind::kCamera:
      return "camera";
    case TreeRayKind::kShadow:
      return "shadow";
    case TreeRayKind::kReflection:
      return "reflection";
    case TreeRayKind::kRefraction:
      return "refraction";
    case TreeRayKind::kTotalInternalReflection:
      return "tir";
    case TreeRayKind::kTransparent:
      return "transparent";
    case TreeRayKind::kGlossy:
      return "glossy";
    case TreeRayKind::kVolume:
      return "volume";
    case TreeRayKind::kAmbientOcclusion:
      return "ambient_occlusion";
    case TreeRayKind::kBevel:
      return "bevel";
  }
  return "camera";
}

py::object cut_name(TreeCut cut) {
  switch (cut) {
    case TreeCut::kNone:
      return py::none();
    case TreeCut::kDepth:
      return py::str("depth");
    case TreeCut::kCutoff:
      return py::str("cutoff");
    case TreeCut::kBackfacing:
      return py::str("backfacing");
    case TreeCut::kUnlit:
      return py::str("unlit");
    case TreeCut::kUnshadowed:
      return py::str("unshadowed");
  }
  return py::none();
}

py::list list3(const Vec3& v) {
  return py::cast(std::vector<float>{v.x, v.y, v.z});
}

template <class Names>
py::object name_at(const Names& names, int32_t index) {
  if (index < 0 || static_cast<size_t>(index) >= names.size()) return py::none();
  return py::str(names[static_cast<size_t>(index)]);
}

}  // namespace

py::dict ray_tree_dict(const RayTree& tree, const CompiledScene& scene) {
  std::vector<std::string> instances;
  instances.reserve(scene.instances.size());
  for (const auto& instance : scene.instances) instances.push_back(instance.name);
  py::list rays;
  for (const RayTreeNode& node : tree.nodes) {
    py::dict ray;
    const bool feeler = node.kind == TreeRayKind::kShadow;
    const bool segment = node.kind == TreeRayKind::kVolume;
    const bool occlusion =
        node.kind == TreeRayKind::kAmbientOcclusion || node.kind == TreeRayKind::kBevel;
    ray["kind"] = kind_name(node.kind);
    ray["depth"] = node.depth;
    ray["parent"] = node.parent;
    ray["sample"] = node.sample;
    ray["origin"] = list3(node.origin);
    ray["direction"] = list3(node.direction);
    ray["time"] = node.time;
    // A feeler ends at its light sample (none for the sun) or on what blocks it, a segment
    // where its ray meets a surface or bound (none where it goes on without end), an
    // ambient occlusion ray at its distance.
    const bool ends = node.hit || ((feeler || segment || occlusion) && node.end != Vec3(0.0f));
    ray["end"] = ends ? py::object(list3(node.end)) : py::none();
    ray["object"] = name_at(instances, node.instance);
    ray["material"] = name_at(scene.material_names, node.material);
    ray["light"] = name_at(scene.light_names, node.light);
    ray["emitter"] = name_at(instances, node.emitter);  // a feeler to an emissive mesh
    // A feeler to neither a lamp nor an emitter goes to the world (scene/world_light.h).
    ray["world"] = feeler && node.light < 0 && node.emitter < 0;
    ray["weight"] = list3(node.weight);
    ray["contribution"] = list3(node.contribution());
    ray["cut"] = cut_name(node.cut);
    if (feeler) {
      const bool sent = node.cut == TreeCut::kNone;
      ray["blocked"] = sent ? py::object(py::bool_(is_black(node.transmittance))) : py::none();
      ray["transmittance"] = list3(node.transmittance);
      ray["diffuse"] = list3(node.diffuse);
      ray["specular"] = list3(node.specular);
      // A feeler from a scatter point of a segment: the light the medium scatters there.
      ray["scatter"] = node.parent >= 0 &&
                       tree.nodes[static_cast<size_t>(node.parent)].kind == TreeRayKind::kVolume;
      ray["scattered"] = list3(node.scattered);
    } else if (occlusion) {
      ray["blocked"] = is_black(node.transmittance);  // something within its length
      ray["transmittance"] = list3(node.transmittance);
    } else if (segment) {
      ray["blocked"] = py::none();
      ray["emission"] = list3(node.emission);  // the media's own, along the segment
      ray["transmittance"] = list3(node.transmittance);
      ray["steps"] = node.steps;
    } else {
      ray["blocked"] = py::none();
      ray["emission"] = list3(node.emission);
      ray["ambient"] = list3(node.ambient);
      ray["background"] = list3(node.background);
    }
    rays.append(ray);
  }
  py::dict out;
  out["pixel"] = list3(tree.pixel);
  out["alpha"] = tree.alpha;
  out["rays"] = rays;
  return out;
}

}  // namespace whitted::python
