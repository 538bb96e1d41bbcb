#include "integrator/settings.h"

#include <iomanip>
#include <sstream>
#include <string>
#include <string_view>

#include "bindings.h"
#include "integrator/passes.h"
#include "scene/light.h"

namespace whitted::python {

// A film pass by its name (whitted_native.FILM_PASSES).
FilmPass film_pass(const std::string& name) {
  for (size_t p = 0; p < kFilmPassCount; ++p) {
    if (kFilmPassNames[p] == name) return static_cast<FilmPass>(p);
  }
  throw std::invalid_argument("no film pass '" + name + "'");
}

uint32_t pass_bits(const std::vector<std::string>& names) {
  uint32_t bits = 0;
  for (const std::string& name : names) bits |= pass_bit(film_pass(name));
  return bits;
}

namespace {

// A bounded setting's docstring: what it is, then its range from kSettingRanges (the one
// definition of the bounds validate() holds it to).
std::string ranged(const SettingRange& range, std::string_view doc) {
  std::ostringstream out;
  out << std::setprecision(10) << doc << " In [" << range.min << ", " << range.max << "].";
  return out.str();
}

}  // namespace

std::vector<std::string> pass_names(uint32_t bits) {
  std::vector<std::string> names;
  for (size_t p = 0; p < kFilmPassCount; ++p) {
    if ((bits & pass_bit(static_cast<FilmPass>(p))) != 0) names.emplace_back(kFilmPassNames[p]);
  }
  return names;
}

void bind_settings(py::module_& m) {
  // The native tables the add-on builds its own from (addon/native.py): {film pass:
  // floats per pixel} in FilmPass order, and {bounded setting: (min, max)} (kSettingRanges,
  // and Light.samples as "light_samples").
  py::dict film_passes;
  for (const FilmPassInfo& pass : kFilmPasses) film_passes[py::str(pass.name)] = pass.channels;
  m.attr("FILM_PASSES") = film_passes;
  py::dict limits;
  for (const SettingRange& range : kSettingRanges) {
    limits[py::str(range.name)] = py::make_tuple(range.min, range.max);
  }
  limits["light_samples"] = py::make_tuple(1.0, static_cast<double>(kMaxLightSamples));
  m.attr("LIMITS") = limits;

  const Settings d;  // the defaults of the constructor's keywords

  py::enum_<AntiAliasing>(m, "AntiAliasing")
      .value("REGULAR", AntiAliasing::kRegular)
      .value("JITTERED", AntiAliasing::kJittered)
      .value("ADAPTIVE", AntiAliasing::kAdaptive);

  py::enum_<Fresnel>(m, "Fresnel")
      .value("OFF", Fresnel::kOff)
      .value("SCHLICK", Fresnel::kSchlick)
      .value("EXACT", Fresnel::kExact);

  py::enum_<GlassShadows>(m, "GlassShadows",
                          "What a shadow feeler does at glass: OPAQUE stops (a full shadow, as "
                          "Cycles and Whitted 1980); TINTED passes, times its transmissivity.")
      .value("OPAQUE", GlassShadows::kOpaque)
      .value("TINTED", GlassShadows::kTinted);

  py::enum_<PixelFilterType>(m, "PixelFilterType",
                             "Render > Film > Pixel Filter, as Cycles': where a pixel's grid "
                             "samples land about its centre (Whitted's adaptive anti-aliasing "
                             "samples the pixel's square).")
      .value("BOX", PixelFilterType::kBox)
      .value("GAUSSIAN", PixelFilterType::kGaussian)
      .value("BLACKMAN_HARRIS", PixelFilterType::kBlackmanHarris);

  py::class_<Settings>(m, "Settings",
                      "What a RenderJob renders with: image size, depth, sampling, passes.")
      .def(py::init([](int width, int height, int max_depth, int aa_samples, int threads,
                       int tile_size, Fresnel fresnel, std::array<int, 4> border,
                       bool transparent_background, float cutoff, AntiAliasing aa_mode,
                       float aa_threshold, int aa_depth, bool analysis, bool feeler_pruning,
                       bool progressive, int start_pixel_size, GlassShadows glass_shadows,
                       const std::vector<std::string>& passes, int contribution_depth,
                       float pass_alpha_threshold, std::array<float, 3> mist, int glossy_samples,
                       int emitter_samples, float shutter, bool adaptive_sampling,
                       float noise_threshold, int adaptive_min_samples, double time_limit,
                       PixelFilterType pixel_filter, float filter_width, uint32_t seed) {
             Settings s;
             s.width = width;
             s.height = height;
             s.max_depth = max_depth;
             s.aa_samples = aa_samples;
             s.threads = threads;
             s.tile_size = tile_size;
             s.fresnel = fresnel;
             std::copy(border.begin(), border.end(), s.border);
             s.transparent_background = transparent_background;
             s.cutoff = cutoff;
             s.aa_mode = aa_mode;
             s.aa_threshold = aa_threshold;
             s.aa_depth = aa_depth;
             s.analysis = analysis;
             s.feeler_pruning = feeler_pruning;
             s.progressive = progressive;
             s.start_pixel_size = start_pixel_size;
             s.glass_shadows = glass_shadows;
             s.passes = pass_bits(passes);
             s.contribution_depth = contribution_depth;
             s.pass_alpha_threshold = pass_alpha_threshold;
             s.mist_start = mist[0];
             s.mist_depth = mist[1];
             s.mist_falloff = mist[2];
             s.glossy_samples = glossy_samples;
             s.emitter_samples = emitter_samples;
             s.shutter = shutter;
             s.adaptive_sampling = adaptive_sampling;
             s.noise_threshold = noise_threshold;
             s.adaptive_min_samples = adaptive_min_samples;
             s.time_limit = time_limit;
             s.pixel_filter = pixel_filter;
             s.filter_width = filter_width;
             s.seed = seed;
             s.validate();
             return s;
           }),
           py::arg("width") = d.width, py::arg("height") = d.height,
           py::arg("max_depth") = d.max_depth, py::arg("aa_samples") = d.aa_samples,
           py::arg("threads") = d.threads, py::arg("tile_size") = d.tile_size,
           py::arg("fresnel") = d.fresnel,
           py::arg("border") =
               std::array<int, 4>{d.border[0], d.border[1], d.border[2], d.border[3]},
           py::arg("transparent_background") = d.transparent_background,
           py::arg("cutoff") = d.cutoff, py::arg("aa_mode") = d.aa_mode,
           py::arg("aa_threshold") = d.aa_threshold, py::arg("aa_depth") = d.aa_depth,
           py::arg("analysis") = d.analysis, py::arg("feeler_pruning") = d.feeler_pruning,
           py::arg("progressive") = d.progressive, py::arg("start_pixel_size") = d.start_pixel_size,
           py::arg("glass_shadows") = d.glass_shadows, py::arg("passes") = pass_names(d.passes),
           py::arg("contribution_depth") = d.contribution_depth,
           py::arg("pass_alpha_threshold") = d.pass_alpha_threshold,
           py::arg("mist") = std::array<float, 3>{d.mist_start, d.mist_depth, d.mist_falloff},
           py::arg("glossy_samples") = d.glossy_samples,
           py::arg("emitter_samples") = d.emitter_samples, py::arg("shutter") = d.shutter,
           py::arg("adaptive_sampling") = d.adaptive_sampling,
           py::arg("noise_threshold") = d.noise_threshold,
           py::arg("adaptive_min_samples") = d.adaptive_min_samples,
           py::arg("time_limit") = d.time_limit, py::arg("pixel_filter") = d.pixel_filter,
           py::arg("filter_width") = d.filter_width, py::arg("seed") = d.seed,
           "border: (xmin, ymin, xmax, ymax) pixels traced, end exclusive, rows from the "
           "bottom; all zero for the whole image. progressive: coarse previews from blocks "
           "of start_pixel_size (a power of two, 1 to 64) down to 2 pixels, then one pass "
           "per anti-aliasing sample (for the viewport). passes: names from FILM_PASSES "
           "kept besides the image and the ray cost (docs/PASSES.md); contribution_depth: "
           "the Contributions pass holds depths 0 .. contribution_depth - 1 apart and the "
           "rest in one bin (1 to 8); pass_alpha_threshold: the data passes come from the "
           "first surface at least this opaque; mist: (start, depth, falloff exponent); "
           "glossy_samples: n, for n x n rays drawn from a glossy lobe at a branch's first "
           "glossy bounce (one at later ones); emitter_samples: n, for n x n feelers to the "
           "emissive meshes and to the world (where it lights the scene) from a shading point "
           "(one after a glossy bounce); shutter: Render > "
           "Motion Blur's, in frames, for the report (0: motion blur off); pixel_filter, "
           "filter_width: Film > Pixel Filter's type (a PixelFilterType) and width in pixels; "
           "seed: which set of random draws the render takes (0: those of before the "
           "setting).")
      .def("validate", &Settings::validate,
           "Raise ValueError naming the first value out of its range (LIMITS), as a render "
           "does.")
      .def_readwrite("width", &Settings::width,
                     ranged(setting_range("width"),
                            "Image width in pixels.")
                         .c_str())
      .def_readwrite("height", &Settings::height,
                     ranged(setting_range("height"),
                            "Image height in pixels.")
                         .c_str())
      .def_readwrite("max_depth", &Settings::max_depth,
                     ranged(setting_range("max_depth"),
                            "Secondary bounces (reflection, refraction) allowed after the camera "
                            "ray.")
                         .c_str())
      .def_readwrite("glossy_samples", &Settings::glossy_samples,
                     ranged(setting_range("glossy_samples"),
                            "n: a branch's first glossy bounce sends n x n rays drawn from the "
                            "lobe (later ones one).")
                         .c_str())
      .def_readwrite("emitter_samples", &Settings::emitter_samples,
                     ranged(setting_range("emitter_samples"),
                            "n: n x n feelers to the emissive meshes per shading point (one after "
                            "a glossy bounce).")
                         .c_str())
      .def_readwrite("shutter", &Settings::shutter,
                     "Render > Motion Blur's shutter in frames, for the report; 0: motion blur "
                     "off.")
      .def_readwrite("aa_samples", &Settings::aa_samples,
                     ranged(setting_range("aa_samples"),
                            "Anti-aliasing samples per pixel axis (n x n) for REGULAR and "
                            "JITTERED.")
                         .c_str())
      .def_readwrite("threads", &Settings::threads,
                     ranged(setting_range("threads"),
                            "Worker threads; 0: all hardware threads.")
                         .c_str())
      .def_readwrite("tile_size", &Settings::tile_size,
                     ranged(setting_range("tile_size"),
                            "Edge of the square tiles the workers take, in pixels.")
                         .c_str())
      .def_readwrite("cryptomatte_kinds", &Settings::cryptomatte_kinds,
                     "Cryptomatte kinds kept: bits 1 object, 2 material, 4 asset; 0: none.")
      .def_readwrite("cryptomatte_depth", &Settings::cryptomatte_depth,
                     ranged(setting_range("cryptomatte_depth"),
                            "Cryptomatte ranks kept per pixel and kind.")
                         .c_str())
      .def_readwrite("probe_stride", &Settings::probe_stride,
                     "An estimate probe: trace one tile in every probe_stride^2, spread over "
                     "the border, each pixel as the full render traces it; 1: every tile.")
      .def_readwrite("fresnel", &Settings::fresnel,
                     "How reflectivity and transmissivity split by angle: OFF (as given), "
                     "SCHLICK's approximation or EXACT dielectric Fresnel.")
      .def_readwrite("pixel_filter", &Settings::pixel_filter,
                     "Film > Pixel Filter's type (a PixelFilterType).")
      .def_readwrite("filter_width", &Settings::filter_width,
                     ranged(setting_range("filter_width"),
                            "Film > Pixel Filter's width in pixels (Cycles': Gaussian 4 standard "
                            "deviations, Blackman-Harris the support's half; the Box is the "
                            "pixel's square whatever it is).")
                         .c_str())
      .def_readwrite("seed", &Settings::seed,
                     ranged(setting_range("seed"),
                            "Cycles' Seed: which of the equally good sets of random draws the "
                            "render takes; 0: those of before the setting.")
                         .c_str())
      .def_readwrite("glass_shadows", &Settings::glass_shadows,
                     "What a shadow feeler does at glass (a GlassShadows).")
      .def_property_readonly("border",
                             [](const Settings& s) {
                               return std::array<int, 4>{s.border[0], s.border[1], s.border[2],
                                                         s.border[3]};
                             },
                             "(xmin, ymin, xmax, ymax): the pixels traced, end exclusive, rows "
                             "from the bottom; all zero: the whole image.")
      .def_readwrite("transparent_background", &Settings::transparent_background,
                     "Camera rays that hit nothing give alpha 0 (else 1).")
      .def_readwrite("cutoff", &Settings::cutoff,
                     ranged(setting_range("cutoff"),
                            "Adaptive depth control: a secondary ray weighing less than this on "
                            "its pixel is not traced; 0: all are.")
                         .c_str())
      .def_readwrite("aa_mode", &Settings::aa_mode,
                     "Anti-aliasing: REGULAR grid, JITTERED grid or ADAPTIVE corner splitting (an "
                     "AntiAliasing).")
      .def_readwrite("aa_threshold", &Settings::aa_threshold,
                     ranged(setting_range("aa_threshold"),
                            "ADAPTIVE: a square is split when its corners differ by more than "
                            "this (summed over RGB).")
                         .c_str())
      .def_readwrite("aa_depth", &Settings::aa_depth,
                     ranged(setting_range("aa_depth"),
                            "ADAPTIVE: how many times a square may be split.")
                         .c_str())
      .def_readwrite("packets", &Settings::packets,
                     "Trace each pixel's camera rays as one Embree packet; off: one query "
                     "per ray (a benchmark baseline).")
      .def_readwrite("waves", &Settings::waves,
                     "Trace a row of a tile's camera samples together, a generation of rays "
                     "at a time (integrator/wave.h; the default); off: the recursive kernel, the "
                     "reference.")
      .def_readwrite("analysis", &Settings::analysis,
                     "Trace only the effects the scene calls for (shadows, reflection, "
                     "refraction, translucency); off: every effect on (a benchmark baseline).")
      .def_readwrite("feeler_pruning", &Settings::feeler_pruning,
                     "Skip shadow feelers that cannot show (light behind the surface, no "
                     "irradiance, below the cutoff); off: a feeler to every light sample "
                     "(a benchmark baseline).")
      .def_readwrite("progressive", &Settings::progressive,
                     "For the viewport: coarse previews from start_pixel_size blocks down to 2 "
                     "pixels, then one pass per anti-aliasing sample.")
      .def_readwrite("adaptive_sampling", &Settings::adaptive_sampling,
                     "Noise-driven sampling: each pixel takes its aa_samples x aa_samples "
                     "samples in rounds, in its own permuted order, and stops once its noise "
                     "estimate and its 8 neighbours' are below noise_threshold.")
      .def_readwrite("noise_threshold", &Settings::noise_threshold,
                     ranged(setting_range("noise_threshold"),
                            "adaptive_sampling: the noise a pixel stops below (as Cycles' "
                            "Noise Threshold); 0: every pixel takes the whole grid.")
                         .c_str())
      .def_readwrite("adaptive_min_samples", &Settings::adaptive_min_samples,
                     ranged(setting_range("adaptive_min_samples"),
                            "adaptive_sampling: samples before the first noise check (at "
                            "least 4, at most the grid); 0: automatic, as Cycles' "
                            "max(4, ceil(16 / threshold^0.3)).")
                         .c_str())
      .def_readwrite("time_limit", &Settings::time_limit,
                     ranged(setting_range("time_limit"),
                            "Seconds (Cycles' Time Limit; 0: none). adaptive_sampling: a round "
                            "after the first that would start this long after the trace began "
                            "is not traced, and the render ends with the samples it has "
                            "(stats()['time_limited']). Ignored without adaptive_sampling.")
                         .c_str())
      .def_readwrite("start_pixel_size", &Settings::start_pixel_size,
                     ranged(setting_range("start_pixel_size"),
                            "progressive: the block edge of the first, coarsest preview (a power "
                            "of two).")
                         .c_str())
      .def_property(
          "passes", [](const Settings& s) { return pass_names(s.passes); },
          [](Settings& s, const std::vector<std::string>& names) { s.passes = pass_bits(names); },
          "Names of the film passes kept besides the image and the ray cost (FILM_PASSES).")
      .def_readwrite("contribution_depth", &Settings::contribution_depth,
                     ranged(setting_range("contribution_depth"),
                            "The Contributions pass keeps bounce depths 0 .. n - 1 apart and the "
                            "rest in one bin.")
                         .c_str())
      .def_readwrite("volume_step_rate", &Settings::volume_step_rate,
                     ranged(setting_range("volume_step_rate"),
                            "Heterogeneous media: the marching step is each medium's object's "
                            "(a tenth of its box's mean side) times its material's step rate "
                            "times this (Cycles' Volumes > Step Rate).")
                         .c_str())
      .def_readwrite("volume_max_steps", &Settings::volume_max_steps,
                     ranged(setting_range("volume_max_steps"),
                            "The most steps a heterogeneous medium's segment is marched in "
                            "(Cycles' Volumes > Max Steps); longer steps beyond.")
                         .c_str())
      .def_readwrite("pass_alpha_threshold", &Settings::pass_alpha_threshold,
                     ranged(setting_range("pass_alpha_threshold"),
                            "The data passes come from the first surface at least this opaque (0: "
                            "the first surface).")
                         .c_str())
      .def_property(
          "mist",
          [](const Settings& s) {
            return std::array<float, 3>{s.mist_start, s.mist_depth, s.mist_falloff};
          },
          [](Settings& s, std::array<float, 3> mist) {
            s.mist_start = mist[0];
            s.mist_depth = mist[1];
            s.mist_falloff = mist[2];
          },
          "The Mist pass: (start, depth, falloff), 0 before start and 1 beyond start + depth, "
          "((distance - start) / depth)^falloff between.")
      .def_readwrite("worker_nice", &Settings::worker_nice,
                     "The workers' niceness, 0 (normal) to 19 (lowest priority): the "
                     "viewport renders below the interface's priority.")
      .def_readwrite("fault_tile", &Settings::fault_tile,
                     "A test hook: the worker that takes this tile index throws "
                     "std::bad_alloc (MemoryError from wait()) before tracing it; -1: off.");
}

}  // namespace whitted::python
