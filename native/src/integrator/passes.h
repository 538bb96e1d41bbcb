// Render passes beyond Combined: which ones a film can keep, and the record of what one
// camera sample's ray tree contributed to them, filled by the kernel's PassRecorder only
// when passes are requested. docs/PASSES.md defines every pass.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <string_view>

#include "core/math.h"
#include "integrator/kernel_recorder.h"
#include "integrator/settings.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace whitted {

// The film passes a render may keep besides Combined and the ray cost, in this order.
enum class FilmPass : uint32_t {
  kEmission,
  kEnvironment,
  kDiffuseDirect,
  kDiffuseIndirect,
  kDiffuseColor,
  kGlossyDirect,
  kGlossyIndirect,
  kGlossyColor,
  kTransmissionDirect,
  kTransmissionIndirect,
  kTransmissionColor,
  // Cycles' Volume Direct and Indirect: the light media scatter once towards the camera
  // ray (integrator/volume.h); Indirect always 0, as Cycles' with Volume Bounces 0.
  kVolumeDirect,
  kVolumeIndirect,
  kDepth,
  kMist,
  kNormal,
  kPosition,
  kUV,
  kObjectIndex,
  kMaterialIndex,
  kContributions,  // per depth of the ray tree: RGB for depths 0 .. N-1, then N and beyond
  kCutWeight,
  // Cycles' Denoising Albedo and Normal: the guides of the denoiser (addon/denoise.py),
  // from the first rough surface along each path, through mirrors and clear glass.
  kDenoisingAlbedo,
  kDenoisingNormal,
  // Cycles' Shadow Catcher: per channel, the light on the shadow catchers the camera sees
  // with every object over that with the catchers alone (integrator/catcher.h), 1 off the
  // catchers, over white by the pixel's alpha with the catchers in it. Kept, it takes the
  // catchers out of Combined (transparent there), as Cycles' pass does.
  kShadowCatcher,
  // Camera samples the pixel took (Cycles' Sample Count debug pass): the film's own count,
  // not recorded by the kernel.
  kSampleCount,
  kCount,
};
inline constexpr size_t kFilmPassCount = static_cast<size_t>(FilmPass::kCount);
// Each film pass's name (Settings.passes, whitted_native.FILM_PASSES) and its floats per
// pixel (Contributions: per depth bin, of which it keeps contribution_depth + 1), in
// FilmPass order: the one definition of both (the add-on's passes are checked against it).
struct FilmPassInfo {
  std::string_view name;
  int channels;
};
inline constexpr std::array<FilmPassInfo, kFilmPassCount> kFilmPasses = {{
    {"emission", 3},
    {"environment", 3},
    {"diffuse_direct", 3},
    {"diffuse_indirect", 3},
    {"diffuse_color", 3},
    {"glossy_direct", 3},
    {"glossy_indirect", 3},
    {"glossy_color", 3},
    {"transmission_direct", 3},
    {"transmission_indirect", 3},
    {"transmission_color", 3},
    {"volume_direct", 3},
    {"volume_indirect", 3},
    {"depth", 1},
    {"mist", 1},
    {"normal", 3},
    {"position", 3},
    {"uv", 3},
    {"object_index", 1},
    {"material_index", 1},
    {"contributions", 3},
    {"cut_weight", 1},
    {"denoising_albedo", 3},
    {"denoising_normal", 3},
    {"shadow_catcher", 3},
    {"sample_count", 1},
}};
inline constexpr std::array<std::string_view, kFilmPassCount> kFilmPassNames = [] {
  std::array<std::string_view, kFilmPassCount> names{};
  for (size_t p = 0; p < kFilmPassCount; ++p) names[p] = kFilmPasses[p].name;
  return names;
}();

constexpr uint32_t pass_bit(FilmPass pass) {
  return 1u << static_cast<uint32_t>(pass);
}

// The passes by what they ask of the kernel, so a render pays only for the groups it
// keeps: the Light panel's split each camera hit's light into its terms, the Data
// panel's read the first surface the camera sees, Contributions sums every node by its
// depth, Cut Weight sums the rays not traced, the denoising guides follow the camera rays
// through near-specular surfaces.
inline constexpr uint32_t kLightPasses =
    pass_bit(FilmPass::kDepth) - 1;  // kEmission .. kVolumeIndirect
inline constexpr uint32_t kDataPasses =
    pass_bit(FilmPass::kContributions) - pass_bit(FilmPass::kDepth);  // kDepth .. kMaterialIndex
inline constexpr uint32_t kGuidePasses =
    pass_bit(FilmPass::kDenoisingAlbedo) | pass_bit(FilmPass::kDenoisingNormal);
// The passes the kernel records into a SampleRecord (all but Sample Count, which the film
// counts): a render keeping none of them runs the kernels that record nothing.
inline constexpr uint32_t kRecordedPasses = pass_bit(FilmPass::kSampleCount) - 1;

// Depth where a camera sample sees no surface (as Cycles' Depth pass shows the sky).
inline constexpr float kNoDepth = 1e10f;
// The GGX alpha at or below which a lobe is near-specular for the denoising guides, as
// Cycles' (film/denoising_passes.h: a closure whose alpha_x * alpha_y exceeds 0.075^2 is
// rough).
inline constexpr float kSharpGuideAlpha = 0.075f;

// The light on a shadow catcher's point (integrator/catcher.h), per channel: its local
// term with every object (`with`) and with the catchers alone (`without`), as Cycles'
// two paths split at the catcher; or either summed over a pixel's catcher hits.
struct CaughtLight {
  Color with{0.0f};
  Color without{0.0f};

  // What the other objects leave, with / without per channel; 1 where even the catchers
  // alone get no light (Cycles' safe_divide_shadow_catcher, film/read.h).
  Color ratio() const {
    Color r(1.0f);
    for (int c = 0; c < 3; ++c) {
      if (without[c] != 0.0f) r[c] = with[c] / without[c];
    }
    return r;
  }
  // The light left as Combined keeps it without the Shadow Catcher pass (Cycles'
  // "approximate" catcher): the ratio's mean over colour, clamped to [0, 1].
  float left() const {
    const Color r = ratio();
    float sum = 0.0f;
    for (int c = 0; c < 3; ++c) sum += r[c];
    return std::clamp(sum / 3.0f, 0.0f, 1.0f);
  }
};

// What one camera sample (or, summed and scaled, one pixel) adds to each pass. The light
// terms belong to the camera hit (depth 0; through cut-outs, every layer the camera ray
// meets, by its coverage, times what the media in front let through) and are weighted by
// that share of the sample: Direct and Indirect hold colour times light, as Blender's
// recombination Color * (Direct + Indirect) wants; the film divides them by their Color.
// The camera ray's segments inside media are depth 0 too, as Cycles' volume passes: their
// emission goes to Emission, their scattering to Volume Direct; deeper segments, like
// deeper surfaces, to the indirect pass their path feeds.
struct SampleRecord {
  Color emission{0.0f};               // emission of the surfaces and media the camera ray meets
  Color environment{0.0f};            // the world where the camera ray escapes
  Color diffuse_direct{0.0f};         // kd/pi * light, through shadow feelers
  Color diffuse_indirect{0.0f};       // the ambient term Ia * ka * kd
  Color diffuse_color{0.0f};          // kd
  Color glossy_direct{0.0f};          // the Phong highlights of the lights
  Color glossy_indirect{0.0f};        // sigma_r * what the mirror ray brings back
  Color glossy_color{0.0f};           // ks + sigma_r
  Color transmission_indirect{0.0f};  // sigma_t * what the refracted ray brings back
  Color transmission_color{0.0f};     // sigma_t (Transmission Direct is always 0)
  // The light the media along the camera ray scatter once towards it, from the lamps,
  // the emitters and the world (Volume Indirect is always 0: no light scatters twice).
  Color volume_direct{0.0f};
  // Everything the ray tree's nodes at depth d add to the sample (emission and local
  // term of a surface, the world where a ray escapes), for d < contribution_depth;
  // the last bin used holds depth contribution_depth and beyond.
  std::array<Color, kMaxContributionDepth + 1> contributions{};
  // The summed weight on the sample (mean over RGB) of the rays not traced because of
  // the maximum depth or the cutoff.
  float cut_weight = 0.0f;
  // Data of the first surface the camera ray meets whose alpha reaches the threshold
  // (Settings::pass_alpha_threshold), as Cycles: normal and UV are averaged over the
  // samples; depth, position and the indices are the pixel's first sample's.
  float mist = 0.0f;       // sum over camera-ray surfaces of (1 - mist) * coverage
  Vec3 normal{0.0f};       // shading normal, world space, facing the camera
  Vec3 uv{0.0f};           // UV map 0, (u, v, 0)
  float depth = kNoDepth;  // distance along the camera's view axis
  Vec3 position{0.0f};     // world space
  float object_index = 0.0f;
  float material_index = 0.0f;
  bool data_found = false;  // whether the data surface was met (set by the kernel)
  // The denoising guides, as Cycles writes them (film/denoising_passes.h), summed over
  // the ray tree: along each path from the camera, at the first surface whose rough
  // lobes (diffuse, Phong, glossy rougher than kSharpGuideAlpha) carry over a quarter of
  // its weight, that surface's rough colours plus its emission, clamped to [0, 1], times
  // the path's PassPath::guide_tint, and its shading normal (world space, facing the
  // ray) times the path's guide_share; where a path escapes, the world, clamped, times
  // its tint (the normal adds nothing there).
  Color denoising_albedo{0.0f};
  Vec3 denoising_normal{0.0f};
  // The Shadow Catcher pass's sums: the light on the catchers the camera ray meets, times
  // its share of the sample (through cut-outs and media), and the share of the sample
  // they cover (what Combined's alpha would have with them in it).
  CaughtLight caught;
  float caught_coverage = 0.0f;

  // Sums the per-sample terms of `s` into these (those the kept `passes`, bits of
  // FilmPass, read; the others stay as they are).
  void add(const SampleRecord& s, uint32_t passes);
  // Takes the first-sample data (depth, position, indices) of `s`.
  void take_first(const SampleRecord& s);
  // Scales the summed terms (of the kept `passes`) by w (1 / samples), leaving the
  // first-sample data.
  void scale(float w, uint32_t passes);
};

// What a shadow feeler a wave queued (wave.h) adds to its sample's record once its
// answer is known, as PassRecorder would have added it had the feeler been traced where
// it was sent: `light` (its contribution times what arrives, as Combined has it) to its
// Contributions bin and to the indirect pass it feeds, and, from the camera hit, its
// diffuse and specular shares to the Direct passes.
struct FeelerPasses {
  Color diffuse{0.0f};  // throughput * the diffuse terms * irradiance, unshadowed
  Color specular{0.0f};
  int bin = -1;  // its Contributions bin, -1 where the pass is not kept
  IndirectPass indirect = IndirectPass::kNone;

  void arrived(const Color& transmittance, const Color& light, SampleRecord* record) const;
};

// The kernel's recorder when passes are requested: it is told, node by node, where each
// share of a sample's radiance comes from, and fills the fields of that sample's
// SampleRecord that the kept passes (Settings::passes) read; the others stay 0. Its
// position in the recursion is the throughput of the node being shaded (its weight on
// the sample: the sigma_r and sigma_t along the way times the coverage of cut-outs) and
// what the node carries on the passes (PassPath). A node's terms go, by its
// depth, to the camera hit's Direct, Emission and Environment passes, or to the
// indirect pass its path feeds: recursively or in waves, the same terms in the same
// passes.
class PassRecorder : public NoRecorder {
 public:
  // The position set while the kernel shades a surface or traces a child ray.
  class Scope {
   public:
    Scope(PassRecorder* recorder, const Color& throughput, const PassPath& path)
        : recorder_(recorder), throughput_(recorder->throughput_), path_(recorder->path_) {
      recorder->throughput_ = throughput;
      recorder->path_ = path;
    }
    ~Scope() {
      recorder_->throughput_ = throughput_;
      recorder_->path_ = path_;
    }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    PassRecorder* recorder_;
    Color throughput_;
    PassPath path_;
  };
  using Queued = FeelerPasses;
  // The Environment pass keeps the world where a transparent film leaves it out.
  static constexpr bool kHiddenWorld = true;

  PassRecorder(const WhittedIntegrator& integrator, SampleRecord* record);

  void escaped(Node node, int depth, float behind, const Color& through, const Color& world,
               bool shown) const;
  // A lamp the camera ray sees goes to Emission, as Cycles writes it; one a deeper ray
  // sees to the indirect pass its path feeds.
  void lamps(int depth, float behind, const Color& through, const Color& radiance) const;
  Scope cover(Node /*node*/, float behind, float a, const Color& through) {
    const float share = behind * a;
    return {this,
            throughput_ * share * through,
            {path_.indirect, path_.guide_tint * share, path_.guide_share * share}};
  }
  Scope segment(Node /*node*/, const Ray& /*segment*/, float /*length*/, float behind,
                const Color& through) {
    return {this, throughput_ * behind * through, path_};
  }
  // The segment's emission and scattering, into Combined's passes as its depth says.
  void segment_light(int depth, const SegmentLight& light) const;
  // The data passes come from the first surface the camera ray meets (depth 0) whose
  // alpha reaches the threshold; Mist from all of them, by their coverage.
  void surface(int depth, const Ray& ray, const Interaction& it, const SurfaceParams& surface) {
    if (depth > 0 || !data_) return;
    Vec3 ng;
    Vec3 ns;
    facing_normals(ray, it, surface, &ng, &ns);
    camera_surface(it, surface, ns, max_component(throughput_));
  }
  void arrived(const ShadingPoint& p, const LightTerms& t, const Color& light_in) {
    Color diffuse;
    Color specular;
    shares(p, t, light_in, &diffuse, &specular);
    diffuse_ += diffuse;
    specular_ += specular;
  }
  // Where the path still seeks its denoising guides: writes them at a rough surface (and
  // ends the search on its rays), or follows its branches.
  void split(const ShadingPoint& p, const Split& split, bool glossy);
  FeelerPasses queued(const ShadingPoint& p, const LightTerms& t, const Color& irradiance,
                      int depth) const;
  // The node's own terms (`total`: emission + local term as the kernel summed it, into
  // Combined), with those its lights added; the sums start again for the next node.
  void local(const ShadingPoint& p, int depth, const Color& emission, const Color& ambient,
             const Color& total);
  // A camera ray's hit on a shadow catcher, in the shading scope of its surface.
  void caught(const CaughtLight& light, float coverage) const {
    if (!caught_) return;
    record_->caught.with += throughput_ * light.with;
    record_->caught.without += throughput_ * light.without;
    record_->caught_coverage += coverage;
  }
  // From the camera hit: sigma_r into Glossy Color, and what its rays bring into Glossy
  // Indirect (sigma_t, Transmission, likewise).
  Scope reflected(int depth, const Color& sigma_r);
  Scope refracted(int depth, const Color& sigma_t);
  Scope branch(const Color& weight, float share, TreeRayKind /*kind*/) {
    return {this, throughput_ * weight * share, path(weight, share)};
  }
  void cut(const Ray& ray, int depth, TreeRayKind kind, const Color& weight, float share,
           TreeCut why) const;
  PassPath path(const Color& weight, float share) const {
    const Color w = weight * share;
    return {path_.indirect, path_.guide_tint * w, path_.guide_share * mean_component(w)};
  }
  void resume(SampleRecord* record, const Color& factor, const PassPath& path) {
    record_ = record;
    throughput_ = factor;
    path_ = path;
  }

 private:
  // The diffuse and specular shares of what arrives of a light sample. The kernel's sum,
  // these and the inspector's (TreeRecorder::unshadowed) multiply the same terms in their
  // own orders, which rounding tells apart: each keeps the order its images always had.
  static void shares(const ShadingPoint& p, const LightTerms& t, const Color& light_in,
                     Color* diffuse, Color* specular) {
    const SurfaceParams& surface = p.surface;
    *diffuse =
        ((t.lit * kInvPi * t.fade) * surface.diffuse + t.lit * t.loss * p.multiscatter) * light_in;
    *specular = (t.lit * surface.specular * (p.phong_norm * t.lobe) + Color(t.coat)) * light_in;
    if (p.alpha > 0.0f) *specular += surface.reflectivity * p.energy * t.glossy * light_in;
    if (t.sheen > 0.0f) *specular += sheen_share(p, t) * light_in;  // Cycles' velvet is glossy
    if (t.layer > 0.0f) *specular += p.layer_tint * t.layer * light_in;
  }
  // The record's field of the indirect pass the node being shaded feeds, if any is kept.
  Color* indirect_field() const;
  // A surface the camera ray meets, covering `share` of the sample; `normal` is its
  // shading normal turned to face the ray.
  void camera_surface(const Interaction& it, const SurfaceParams& surface, const Vec3& normal,
                      float share) const;

  const CompiledScene& scene_;
  const Settings& settings_;
  const Camera& camera_;
  SampleRecord* record_;
  bool light_;          // a pass of kLightPasses is kept
  bool data_;           // a pass of kDataPasses is kept
  bool contributions_;  // Contributions is kept
  bool cut_weight_;     // Cut Weight is kept
  bool guides_;         // a pass of kGuidePasses is kept
  bool caught_;         // Shadow Catcher is kept
  Color throughput_{1.0f};
  PassPath path_;
  // What the lights of the node being shaded add, summed as they arrive: kd/pi * E *
  // (n.l) * feeler transmittance, and the same for the Phong lobe and the coat's highlight.
  Color diffuse_{0.0f};
  Color specular_{0.0f};
};

}  // namespace whitted
