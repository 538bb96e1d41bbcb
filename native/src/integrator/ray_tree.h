// The ray tree of one pixel, as the inspector records it (issue 17): every ray the
// Whitted recursion traced, or would have traced but cut, with what each one adds to the
// pixel on its own. The contributions of all nodes sum to the pixel's value.
#pragma once

#include <cstdint>
#include <vector>

#include "core/ray.h"
#include "integrator/medium.h"
#include "integrator/settings.h"
#include "scene/camera.h"

namespace whitted {

struct CompiledScene;

enum class TreeRayKind {
  kCamera,
  kShadow,                   // a shadow ray towards one light sample
  kReflection,               // the mirror ray, sigma_r
  kRefraction,               // the refracted ray, sigma_t
  kTotalInternalReflection,  // the mirror ray of a transmissive surface that could not refract
  kTransparent,  // straight on: behind a cut-out, through a false interface or a volume bound
  kGlossy,       // a ray drawn from a glossy reflection lobe, its share of sigma_r
  kVolume,       // a ray's segment inside media (volume.h): its feelers scatter light along it
  // A ray an Ambient Occlusion node traced from the surface its parent met (no weight:
  // it brings no light; its transmittance 0 where something lay within its length).
  kAmbientOcclusion,
  // A probe of a Bevel node near the surface its parent met (no weight), to where it met
  // a surface (its transmittance 0) or to its end.
  kBevel,
};

// Why a ray of the tree was not traced (or, for a shadow ray, not sent).
enum class TreeCut {
  kNone,
  kDepth,       // the maximum depth
  kCutoff,      // its weight on the pixel fell below the cutoff
  kBackfacing,  // shadow ray: the light is behind the surface
  kUnlit,       // shadow ray: no light arrives (outside a spot's cone, behind an area light)
  kUnshadowed,  // shadow ray: not sent, the light counted as visible (no shadows, or its
                // whole contribution is below the cutoff)
};

struct RayTreeNode {
  TreeRayKind kind = TreeRayKind::kCamera;
  int depth = 0;      // bounces from the camera (continuations keep their ray's depth)
  int parent = -1;    // the node whose surface (or segment) spawned it; -1 for a camera ray
  int sample = 0;     // the camera sample it belongs to
  Vec3 origin{0.0f};  // a camera ray's: its point on the lens (the camera's, for a pinhole)
  Vec3 direction{0.0f};
  float time = 0.0f;      // in the shutter, 0 to 1 (motion blur; 0 where nothing moves)
  bool hit = false;       // the ray ended on a surface or volume bound (a shadow ray: on a blocker)
  Vec3 end{0.0f};         // where it ended, when `hit`; a segment's and a feeler's far end
  int32_t instance = -1;  // CompiledScene::instances index of what it hit or was blocked by
  int32_t material = -1;  // CompiledScene::materials index of that surface
  int32_t light = -1;     // shadow rays to a lamp: CompiledScene::lights index
  int32_t emitter = -1;   // shadow rays to an emissive mesh: CompiledScene::instances index
  // Its share of the pixel: a ray's radiance times `weight` is what it brings to the pixel
  // (the product of the anti-aliasing weight, the coverage of cut-outs in front and the
  // sigma_r / sigma_t of every surface on the way).
  Color weight{0.0f};
  TreeCut cut = TreeCut::kNone;
  // What this node adds to the pixel itself; its children add theirs. A ray that hits a
  // surface adds the surface's emission and ambient term; a ray that misses adds the
  // background; a segment in media adds their emission; a shadow ray adds its light's
  // diffuse and specular terms, or from a point in a medium the light scattered there,
  // times what gets through (`transmittance`).
  Color emission{0.0f};
  Color ambient{0.0f};
  Color background{0.0f};
  Color diffuse{0.0f};    // shadow rays: the Phong diffuse term of the light, unshadowed
  Color specular{0.0f};   // shadow rays: the Phong specular term, unshadowed
  Color scattered{0.0f};  // shadow rays from a segment: the light scattered, unshadowed
  // Shadow rays: what got through. A segment: what its media let through (it scales
  // nothing of its own: its diffuse, specular and scattered terms are 0).
  Color transmittance{1.0f};
  int steps = 0;  // a segment: the points a heterogeneous medium's program ran at
  Color contribution() const {
    return emission + ambient + background + (diffuse + specular + scattered) * transmittance;
  }
};

// What the kernel's TreeRecorder (tree_recorder.h) writes (one pixel, one thread: no locking).
struct RayTree {
  std::vector<RayTreeNode> nodes;
  // The pixel (or the one sample) traced: its value, as the render computes it, and its
  // coverage. The nodes' contributions sum to `pixel`.
  Color pixel{0.0f};
  float alpha = 0.0f;
  // The recursion's position: the node whose surface is being shaded, the weight a
  // surface term gets on the pixel there, and the kind of the next ray it traces.
  int current = -1;
  Color scale{1.0f};
  TreeRayKind next_kind = TreeRayKind::kCamera;

  int roots = 0;  // camera rays so far: each starts a camera sample

  // Appends `node` under `parent` (-1: a camera ray, the root of a new sample).
  int add(RayTreeNode node, int parent) {
    node.parent = parent;
    node.sample = parent >= 0 ? nodes[static_cast<size_t>(parent)].sample : roots++;
    nodes.push_back(node);
    return static_cast<int>(nodes.size()) - 1;
  }

  // The recursion's position set for a while (shading a surface, tracing a child ray) and
  // put back when the scope ends.
  class Scope {
   public:
    Scope(RayTree* tree, int current, const Color& scale,
          TreeRayKind next_kind = TreeRayKind::kCamera)
        : tree_(tree), current_(tree->current), scale_(tree->scale), next_kind_(tree->next_kind) {
      tree->current = current;
      tree->scale = scale;
      tree->next_kind = next_kind;
    }
    ~Scope() {
      tree_->current = current_;
      tree_->scale = scale_;
      tree_->next_kind = next_kind_;
    }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    RayTree* tree_;
    int current_;
    Color scale_;
    TreeRayKind next_kind_;
  };
  Color total() const {
    Color sum(0.0f);
    for (const RayTreeNode& node : nodes) sum += node.contribution();
    return sum;
  }
};

// Pixel (x, y) (from the bottom-left) traced again, alone, as a render with these scene,
// settings and camera would (inside `camera_media`, with that render's packet choice), recording
// its ray tree: every camera sample weighted as in the pixel, or with `sample` >= 0 that grid
// sample alone (weight 1). Reads only immutable data, so it may run beside a render of the same
// scene. Throws std::out_of_range for a pixel or sample outside the image, std::invalid_argument
// for a single sample of adaptive anti-aliasing (its samples are not a grid).
RayTree inspect_pixel(const CompiledScene& scene, const Settings& settings, const Camera& camera,
                      const MediumStack& camera_media, bool packets, int x, int y, int sample = -1);

}  // namespace whitted
