// Render settings: everything besides the scene that decides the image.
#pragma once

#include <array>
#include <cstdint>
#include <cstdlib>
#include <string_view>

namespace whitted {

enum class Fresnel { kOff, kSchlick, kExact };

// What a shadow feeler does at a refractive (glass) surface. Opaque: it stops, so glass
// casts a full shadow, as in Whitted (1980) and Cycles, whose shadow rays pass only
// cut-outs (alpha, Transparent BSDF); light focused through glass would be a caustic,
// which neither traces. Tinted: it passes, weighted by the glass's transmissivity (Hall
// and Greenberg's coloured shadows), a lighter shadow than the glass would cast.
enum class GlassShadows { kOpaque, kTinted };

// Where camera rays go inside a pixel. Regular: the centres of an n x n grid. Jittered:
// one point in each cell of that grid, placed by a hash of the pixel (deterministic).
// Adaptive (Whitted 1980; POV-Ray's method 2): the pixel's corners, and a square is
// split in four while its corners differ by more than the threshold, to a depth.
enum class AntiAliasing { kRegular, kJittered, kAdaptive };

// Render > Film > Pixel Filter, as Cycles' (integrator/pixel_filter.h): where a pixel's
// regular and jittered grid samples land around its centre. Box of width 1 is the seed's
// pixel square; Whitted's adaptive corners always sample the square.
enum class PixelFilterType { kBox, kGaussian, kBlackmanHarris };

// The deepest separate bin of the Contributions pass (Settings::contribution_depth).
inline constexpr int kMaxContributionDepth = 8;

struct Settings {
  int width = 640;
  int height = 480;
  int max_depth = 5;  // secondary bounces allowed after the camera ray
  // Distributed ray tracing's glossy rays (Cook et al. 1984): a glossy surface (a lobe
  // rougher than a mirror, Material::glossy) met by a ray that has not yet been
  // reflected glossily sends n x n rays drawn from its lobe, stratified; later glossy
  // bounces of the same branch send one each (the ray tree would otherwise grow by n^2
  // at every glossy bounce).
  int glossy_samples = 2;
  // Feelers to the emissive meshes (scene/mesh_light.h) and to the world where it lights
  // the scene (scene/world_light.h) from each shading point: n x n,
  // stratified over the power table and the triangles, at a branch's first glossy
  // bounce and before it; one after, as glossy rays.
  int emitter_samples = 2;
  // Render > Motion Blur's shutter, in frames, for the report; 0 when motion blur is off
  // (or the render is the viewport's, as in Cycles). What moves comes with the scene
  // (Instance::motion, Camera::motion).
  float shutter = 0.0f;
  AntiAliasing aa_mode = AntiAliasing::kRegular;
  int aa_samples = 1;  // per axis, regular and jittered: n x n samples
  PixelFilterType pixel_filter = PixelFilterType::kBox;
  float filter_width = 1.0f;  // in pixels (Cycles' Width: see PixelFilter)
  // Heterogeneous media (integrator/heterogeneous.h), as Cycles' Volumes panel: the
  // marching step is each medium's object's step (a tenth of the mean side of its box)
  // times its material's Step Rate times this (Cycles' Step Rate for renders: below 1
  // finer and slower); a segment takes at most volume_max_steps steps (longer ones where
  // it would take more).
  float volume_step_rate = 1.0f;
  int volume_max_steps = 1024;
  // Cycles' Seed (Sampling > Advanced): which of the equally good sets of random draws a
  // render takes (pixel_key, sampler.h); 0 is the draws of before the setting. The add-on
  // gives each frame its own with Use Animated Seed.
  uint32_t seed = 0;
  float aa_threshold = 0.3f;  // adaptive: split when corners differ by more (sum over RGB)
  int aa_depth = 3;           // adaptive: how many times a square may be split
  int threads = 0;            // 0: all hardware threads
  int tile_size = 32;
  // An estimate probe (addon/estimate.py): trace one tile in every probe_stride^2, spread
  // evenly over the border. Each traced pixel is the full render's (a pixel never depends
  // on its neighbours), so the probe's rays and values per pixel are the full render's.
  // 1 traces every tile.
  int probe_stride = 1;
  // Cryptomatte (integrator/cryptomatte.h): bit k keeps CryptomatteKind k (1 object,
  // 2 material, 4 asset), each with cryptomatte_depth ranks per pixel; 0: none.
  uint32_t cryptomatte_kinds = 0;
  int cryptomatte_depth = 0;
  Fresnel fresnel = Fresnel::kExact;
  GlassShadows glass_shadows = GlassShadows::kOpaque;
  // Adaptive depth control (Hall & Greenberg 1983; POV-Ray's adc_bailout): a secondary
  // ray whose weight on the pixel falls below this is not traced. 0 traces every ray.
  float cutoff = 1.0f / 255.0f;
  // Scene analysis: trace only the effects the scene calls for (shadows, reflection,
  // refraction, translucency; integrator/analysis.h). Off: every effect on, as a tracer
  // without the analysis (a benchmark baseline). Either way a ray whose coefficient is
  // zero is never traced.
  bool analysis = true;
  // Skip shadow feelers that cannot show: the light behind the surface (by the shading
  // normal), no irradiance (outside a spot's cone), or the whole light's contribution
  // below the cutoff. Off sends a feeler to every light sample (a benchmark baseline).
  bool feeler_pruning = true;
  // Trace the camera rays of blocks of pixels as Embree packets where the scene suits
  // packets (choose_packets and CameraSampler::first_hits, sampler.h; faster there).
  // Embree's packet and single-ray queries may pick differently where two faces tie:
  // coplanar faces, or a ray through the edge two faces share (docs/PERFORMANCE.md counts
  // the pixels on the suite's scenes). Off: one query per ray everywhere (a benchmark
  // baseline).
  bool packets = true;
  // Trace in waves (integrator/wave.h): the camera samples of a row of a tile together,
  // a generation of rays at a time, the feelers towards each lamp as packets. The pixels
  // are the recursion's up to float rounding (the order of the sums differs), and so
  // are the passes. The viewport's coarse previews and the inspector are traced
  // recursively either way. On by default (docs/notes/waves.md measures it); off (the
  // add-on's Trace in Waves unticked): the recursive kernel everywhere, the reference.
  bool waves = true;
  // Pixels traced: [xmin, xmax) x [ymin, ymax), rows from the bottom; all zero means the
  // whole image. The rest of the image stays 0.
  int border[4] = {0, 0, 0, 0};
  bool transparent_background = false;  // camera rays that miss give alpha 0
  // Progressive refinement, for the viewport: first coarse previews, one camera ray per
  // block of start_pixel_size, then half that, ..., down to 2 pixels, each shown over its
  // block; then one pass per sample of the aa_samples x aa_samples grid, each adding that
  // sample to every pixel (adaptive anti-aliasing is sampled as jittered). Off: one pass
  // that renders each pixel whole.
  bool progressive = false;
  int start_pixel_size = 8;  // a power of two, 1 to 64
  // Noise-driven (adaptive) sampling, as Cycles' (docs/notes/adaptive_sampling.md): the
  // pixels take their aa_samples x aa_samples samples in rounds, in the order of their
  // index (the Monte Carlo samples' Sobol points: each power-of-two prefix stratified over
  // the pixel; a regular grid's cells in a permutation per pixel: regular_cell, sampler.h),
  // and after each round a pixel whose noise
  // estimate (Film::converge) is below noise_threshold, and whose 3 x 3 neighbours' are
  // too, takes no more. noise_threshold 0: every pixel takes the whole grid.
  // adaptive_min_samples: samples before the first check; 0: Cycles' automatic
  // max(4, ceil(16 / threshold^0.3)); at most the grid. The maximum is the grid.
  bool adaptive_sampling = false;
  float noise_threshold = 0.01f;
  int adaptive_min_samples = 0;
  // Cycles' Time Limit, in seconds from the start of the trace (steady clock); 0: none.
  // With adaptive_sampling, a round (Pass::Kind::kRound) after the first that would start
  // past the limit is not traced: the render ends with the samples it has, each pixel the
  // mean of those it took. Without adaptive_sampling the limit is ignored (a fixed-count
  // render's samples come in one pass, or in the viewport's grid order, which a cut would
  // leave stratified over part of the pixel only).
  double time_limit = 0.0;
  // The workers' niceness (Linux: 0 is normal, 19 the lowest priority). The viewport
  // renders at a lower priority than Blender's own thread, so that on a machine whose
  // cores the workers fill the interface still draws each new pass at once.
  int worker_nice = 0;
  // Render passes beyond Combined and the ray cost: bits of FilmPass (passes.h, 1 << pass).
  // None: the kernels that record nothing, as fast as without passes.
  uint32_t passes = 0;
  // The Contributions pass: depths 0 .. contribution_depth - 1 apart, then one bin for
  // contribution_depth and beyond (1 to kMaxContributionDepth).
  int contribution_depth = 3;
  // The data passes come from the first surface a camera ray meets whose alpha is at
  // least this (Blender's view_layer.pass_alpha_threshold; 0: the first surface).
  float pass_alpha_threshold = 0.5f;
  // The Mist pass (the world's mist settings): 0 up to mist_start from the camera, 1 from
  // mist_start + mist_depth, between them ((distance - start) / depth)^mist_falloff
  // (Blender's falloffs: quadratic 2, linear 1, inverse quadratic 0.5).
  float mist_start = 5.0f;
  float mist_depth = 25.0f;
  float mist_falloff = 2.0f;
  // A test hook: the worker that takes this tile (an index into the tiles, bottom row
  // first) throws std::bad_alloc before tracing it, to show a failing worker stops the
  // job cleanly. -1: off.
  int fault_tile = -1;

  // The border as a rectangle, the whole image when unset.
  void border_rect(int* xmin, int* ymin, int* xmax, int* ymax) const;

  // Throws std::invalid_argument naming the first bad value.
  void validate() const;
};

// Whether the camera samples are Monte Carlo ones: jittered grid samples (Jittered, and
// Adaptive when it samples the grid: progressive or with a noise threshold), as against
// the regular grid's and Whitted's adaptive corners. Every 2D draw along such a sample's
// chain (sized lamps' feelers, glossy lobes, emitter feelers) is then a point of the
// pixel's Owen-scrambled Sobol sequence of that draw (core/sobol.h, NodeState::pixel and
// index), as its film point, lens point and time are (CameraSampler::grid_ray, which
// takes them so for every mode but the regular grid).
inline bool jittered_samples(const Settings& s) {
  return s.aa_mode == AntiAliasing::kJittered ||
         (s.aa_mode == AntiAliasing::kAdaptive && (s.progressive || s.adaptive_sampling));
}

// The bounds validate() holds each bounded setting to, inclusive, by its field's name: the
// one definition of them (whitted_native.LIMITS; the add-on's controls take their ranges
// from it). Whole numbers for the int fields.
struct SettingRange {
  std::string_view name;
  double min;
  double max;
};
inline constexpr std::array kSettingRanges = {
    SettingRange{"width", 1, 65536},
    SettingRange{"height", 1, 65536},
    SettingRange{"max_depth", 0, 256},
    SettingRange{"glossy_samples", 1, 16},
    SettingRange{"emitter_samples", 1, 16},
    SettingRange{"aa_samples", 1, 64},
    SettingRange{"filter_width", 0.01, 10},
    SettingRange{"seed", 0, INT32_MAX},
    SettingRange{"aa_threshold", 0, 3},
    SettingRange{"aa_depth", 0, 6},
    SettingRange{"threads", 0, 1024},
    SettingRange{"tile_size", 1, 4096},
    SettingRange{"probe_stride", 1, 256},
    SettingRange{"cryptomatte_kinds", 0, 7},
    SettingRange{"cryptomatte_depth", 0, 16},
    SettingRange{"cutoff", 0, 1},
    SettingRange{"start_pixel_size", 1, 64},
    SettingRange{"noise_threshold", 0, 1},
    SettingRange{"adaptive_min_samples", 0, 4096},
    SettingRange{"time_limit", 0, 1e6},
    SettingRange{"worker_nice", 0, 19},
    SettingRange{"fault_tile", -1, INT32_MAX},
    SettingRange{"contribution_depth", 1, kMaxContributionDepth},
    SettingRange{"pass_alpha_threshold", 0, 1},
    SettingRange{"volume_step_rate", 0.01, 100},  // as Cycles'
    SettingRange{"volume_max_steps", 2, 65536},   // as Cycles'
};

// The range of setting `name`; a name not in kSettingRanges does not compile.
consteval SettingRange setting_range(std::string_view name) {
  for (const SettingRange& range : kSettingRanges) {
    if (range.name == name) return range;
  }
  std::abort();  // not a constant expression: the compiler reports the call
}

}  // namespace whitted
