// What the Whitted kernel (kernel.h) tells a recorder as it traces: NoRecorder's
// hooks, every one empty. A render without passes runs the kernel with NoRecorder itself,
// so the hooks compile to nothing; a recorder derives from it and hides the hooks it
// listens to: PassRecorder (passes.h) for the passes, TreeRecorder (tree_recorder.h) for
// the ray-tree inspector.
#pragma once

#include <cstdint>

#include "core/math.h"
#include "core/ray.h"
#include "integrator/ray_tree.h"
#include "integrator/shading_point.h"
#include "scene/light.h"
#include "scene/scene.h"

namespace whitted {

class WhittedIntegrator;
struct CaughtLight;
struct SampleRecord;
struct SegmentLight;
struct Split;

// The indirect light pass of the camera hit (passes.h) that the rays being traced
// feed: none at the camera's depth, Glossy Indirect under its reflected term,
// Transmission Indirect under its refracted term.
enum class IndirectPass : uint8_t { kNone, kGlossy, kTransmission };

// What a ray carries on its sample's passes besides its weight (PassRecorder, passes.h):
// the indirect pass it feeds, and, while the path from the camera has met only
// near-specular surfaces, its part in the denoising guides: the tint those surfaces put
// on the albedo (the weights of the branches followed, times the coverage of
// cut-outs) and its share of the normal (each branch's weight as a fraction of the
// surface's branches' sum). Both 0 once the guides of its path are written.
struct PassPath {
  IndirectPass indirect = IndirectPass::kNone;
  Color guide_tint{0.0f};
  float guide_share = 0.0f;
};

// Every hook gets what the recorder needs of the kernel's step, and the recursion's
// depth where it matters; the recorder keeps its own position in the recursion (a node
// of its tree, a weight on the sample) through the scopes cover() and branch() return.
struct NoRecorder {
  // A ray as the recorder knows it (a node of its tree), handed back to its hooks.
  struct Node {};
  // The recorder's position while the kernel shades a surface or traces a child ray:
  // set when made, put back when it ends.
  struct Scope {};
  // What a feeler a wave queues (wave.h) carries for the recorder until its answer is
  // known: nothing here.
  struct Queued {};
  // Whether the feelers of a sized light may go to Embree as packets (the inspector
  // records each alone).
  static constexpr bool kBatchesFeelers = true;
  // Whether escaped() wants the world where a transparent film hides it.
  static constexpr bool kHiddenWorld = false;

  NoRecorder() = default;
  NoRecorder(const WhittedIntegrator& /*integrator*/, SampleRecord* /*record*/) {}

  // A ray traced at `depth`: the camera's or a child's (`in_front` none), or a ray's
  // continuation behind the cut-out or volume bound `in_front`; `behind` is the share of
  // its weight not covered by the cut-outs in front, `through` what the media in front
  // let through (1 in a scene without media).
  Node ray(const Ray& /*ray*/, int /*depth*/, Node /*in_front*/, float /*behind*/,
           const Color& /*through*/) {
    return {};
  }
  // The ray met this surface.
  void hit(Node /*node*/, const Interaction& /*it*/) {}
  // The ray crossed this volume's bound (a mesh without a surface) and goes on behind it.
  void crossed(Node /*node*/, const Interaction& /*it*/) {}
  // The ray's segment inside media (volume.h, heterogeneous.h), from its start to its hit
  // or as far as it goes (`length`, maybe infinite), at the ray's `behind` share times
  // `through`: while the scope lives the media's scattering is estimated along it.
  Scope segment(Node /*node*/, const Ray& /*segment*/, float /*length*/, float /*behind*/,
                const Color& /*through*/) {
    return {};
  }
  // A feeler from a point of that segment towards a light sample (of a lamp, an emissive
  // mesh, or the world: -1 for the others), before anything is known of it: `unshadowed`
  // is what the medium there sends back along the segment's ray per unit of its weight
  // if all of the light arrives. unsent() and shadow() tell what became of it.
  Node scatter(const Ray& /*feeler*/, const Color& /*unshadowed*/, int32_t /*light*/,
               int32_t /*emitter*/, int /*depth*/) {
    return {};
  }
  // What that segment, at `depth`, sends back along the ray and lets through.
  void segment_light(int /*depth*/, const SegmentLight& /*light*/) {}
  // The shapes of the lamps the ray passes before what it meets send `radiance` back
  // (Kernel::lamps) to the `behind` share of the ray, through media letting `through`
  // through.
  void lamps(int /*depth*/, float /*behind*/, const Color& /*through*/, const Color& /*radiance*/) {
  }
  // The ray escaped to `world`, shown unless the film is transparent there; `through` is
  // what the media on its way let through.
  void escaped(Node /*node*/, int /*depth*/, float /*behind*/, const Color& /*through*/,
               const Color& /*world*/, bool /*shown*/) {}
  // A program run at the surface `node` met traced `ray` (`kind`: an Ambient Occlusion
  // node's or a Bevel node's probe), which something `blocked` within its length or not.
  void program_ray(Node /*node*/, const Ray& /*ray*/, int /*depth*/, TreeRayKind /*kind*/,
                   bool /*blocked*/) {}
  // The surface the ray met is shaded, covering `a` of the `behind` share of the ray,
  // seen through media that let `through` through.
  Scope cover(Node /*node*/, float /*behind*/, float /*a*/, const Color& /*through*/) { return {}; }
  // A camera ray's hit on a shadow catcher (catcher.h), in that surface's scope: the
  // light on it, and the share of the sample it covers.
  void caught(const CaughtLight& /*light*/, float /*coverage*/) const {}
  // That surface, as seen along `ray` (for the camera's surface data).
  void surface(int /*depth*/, const Ray& /*ray*/, const Interaction& /*it*/,
               const SurfaceParams& /*surface*/) {}
  // The shadow ray towards light sample `ls` (of a lamp, CompiledScene::lights, or an
  // emissive mesh, instances; -1 for the other), before anything is known of it.
  Node feeler(const Interaction& /*it*/, const LightSample& /*ls*/, int32_t /*light*/,
              int32_t /*emitter*/, int /*depth*/) {
    return {};
  }
  // It (or a scatter() feeler) was not sent: the light is behind the surface, or sends
  // nothing here.
  void unsent(Node /*node*/, TreeCut /*why*/) {}
  // Its terms, unshadowed, before the shadow ray is sent (if it is).
  void unshadowed(Node /*node*/, const ShadingPoint& /*p*/, const LightTerms& /*t*/,
                  const LightSample& /*ls*/) {}
  // The shadow ray was sent and let `transmittance` through.
  void shadow(Node /*node*/, const Ray& /*ray*/, const Color& /*transmittance*/) {}
  // A light sample's terms once `light_in` of it arrived.
  void arrived(const ShadingPoint& /*p*/, const LightTerms& /*t*/, const Color& /*light_in*/) {}
  // In a wave, its feeler is queued instead, with these terms (unshadowed) and this
  // irradiance: what the wave hands back, with the feeler's answer, to its sample's record.
  Queued queued(const ShadingPoint& /*p*/, const LightTerms& /*t*/, const Color& /*irradiance*/,
                int /*depth*/) {
    return {};
  }
  // The surface being shaded splits its weight into `split`'s sigma_r and sigma_t (split.h),
  // its rays drawn from its glossy lobes where `glossy` (the glossy effect is on).
  void split(const ShadingPoint& /*p*/, const Split& /*split*/, bool /*glossy*/) {}
  // The local term of the surface being shaded: its emission, its ambient term, and
  // emission + the whole local term as the kernel summed it.
  void local(const ShadingPoint& /*p*/, int /*depth*/, const Color& /*emission*/,
             const Color& /*ambient*/, const Color& /*total*/) {}
  // The reflected term of the surface being shaded, sigma_r times what its rays bring
  // back, is traced while the scope lives (the refracted term, sigma_t times..., likewise).
  Scope reflected(int /*depth*/, const Color& /*sigma_r*/) { return {}; }
  Scope refracted(int /*depth*/, const Color& /*sigma_t*/) { return {}; }
  // A child ray of `weight` (relative to the surface being shaded) times `share` (of
  // its lobe, for a ray drawn from a glossy lobe) is traced while the scope lives.
  Scope branch(const Color& /*weight*/, float /*share*/, TreeRayKind /*kind*/) { return {}; }
  // Such a ray, at `depth`, was not traced.
  void cut(const Ray& /*ray*/, int /*depth*/, TreeRayKind /*kind*/, const Color& /*weight*/,
           float /*share*/, TreeCut /*why*/) {}
  // What a child ray of `weight` times `share` carries on the passes (PassPath), handed to
  // those a wave queues (wave.h).
  PassPath path(const Color& /*weight*/, float /*share*/) const { return {}; }
  // A ray a wave queued takes up the position the recursion would have had there: its
  // sample's record, its factor on the sample, what it carries on the passes.
  void resume(SampleRecord* /*record*/, const Color& /*factor*/, const PassPath& /*path*/) {}
};

}  // namespace whitted
