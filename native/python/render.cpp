#include "integrator/render.h"

#include "bindings.h"

#include <algorithm>
#include <functional>

namespace whitted::python {
namespace {

py::dict stats_dict(const RenderStats& s) {
  py::dict rays;
  rays["camera"] = s.rays.camera;
  rays["shadow"] = s.rays.shadow;
  rays["reflection"] = s.rays.reflection;
  rays["refraction"] = s.rays.refraction;
  rays["glossy"] = s.rays.glossy;
  rays["transparent"] = s.rays.transparent;
  rays["total"] = s.rays.total();
  py::dict out;
  out["rays"] = rays;
  out["total_internal_reflections"] = s.rays.total_internal_reflections;
  out["depth_limited"] = s.rays.depth_limited;
  out["cutoff_skipped"] = s.rays.cutoff_skipped;
  py::dict skipped;
  skipped["backfacing"] = s.rays.shadow_rays_skipped.backfacing;
  skipped["unlit"] = s.rays.shadow_rays_skipped.unlit;
  skipped["cutoff"] = s.rays.shadow_rays_skipped.cutoff;
  out["shadow_rays_skipped"] = skipped;
  py::list effects;
  for (const EffectDecision& decision : s.effects) {
    py::dict effect;
    effect["name"] = decision.name;
    effect["on"] = decision.on;
    effect["why"] = decision.why;
    effects.append(effect);
  }
  out["effects"] = effects;
  out["nonfinite_samples"] = s.rays.nonfinite_samples;
  out["compile_seconds"] = s.compile_seconds;
  out["top_level_built"] = s.top_level_built;
  out["trace_seconds"] = s.trace_seconds;
  out["threads"] = s.threads;
  out["samples"] = s.samples;
  out["pixels"] = s.pixels;
  out["triangles"] = s.triangles;
  out["curve_segments"] = s.curve_segments;
  out["points"] = s.points;
  out["instances"] = s.instances;
  out["degenerate_instances"] = s.degenerate_instances;
  out["lights"] = s.lights;
  out["camera_packets"] = s.camera_packets;
  out["visible_instances"] = s.visible_instances;
  out["instances_per_pixel"] = s.instances_per_pixel;
  out["cancelled"] = s.cancelled;
  out["error"] = s.error;
  return out;
}

void check_rect(const RenderJob& job, int x, int y, int w, int h) {
  const Settings& s = job.settings();
  if (x < 0 || y < 0 || w < 0 || h < 0 || x + w > s.width || y + h > s.height) {
    throw std::invalid_argument("rectangle outside the image");
  }
}

// Copies a rectangle of the per-pixel ray counts into a float32[h*w, 1] array.
py::array_t<float> copy_cost(const RenderJob& job, int x, int y, int w, int h) {
  check_rect(job, x, y, w, h);
  const Settings& s = job.settings();
  py::array_t<float> out({static_cast<py::ssize_t>(w) * h, py::ssize_t{1}});
  float* dst = out.mutable_data();
  for (int row = 0; row < h; ++row) {
    const float* line = job.film().cost().data() + static_cast<size_t>(y + row) * s.width + x;
    std::copy(line, line + w, dst + static_cast<size_t>(row) * w);
  }
  return out;
}

// A rectangle of full rows of a job buffer (`channels` floats per pixel) as a read-only
// float32[h*w, channels] view, without a copy: the rows are contiguous. `owner` (the
// Python RenderJob) is kept alive by the view.
py::array_t<float> view_rows(const py::object& owner, const std::vector<float>& buffer, int width,
                             int y, int h, int channels) {
  py::array_t<float> out({static_cast<py::ssize_t>(width) * h, py::ssize_t{channels}},
                         buffer.data() + static_cast<size_t>(channels) * y * width, owner);
  py::detail::array_proxy(out.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return out;
}

// Copies a rectangle of the image into a C-contiguous float32[h*w, 4] array, the shape
// Blender's foreach_set takes for a render pass.
py::array_t<float> copy_rect(const RenderJob& job, int x, int y, int w, int h) {
  check_rect(job, x, y, w, h);
  const Settings& s = job.settings();
  py::array_t<float> out({static_cast<py::ssize_t>(w) * h, py::ssize_t{4}});
  float* dst = out.mutable_data();
  const float* src = job.film().pixels().data();
  for (int row = 0; row < h; ++row) {
    const float* line = src + 4 * (static_cast<size_t>(y + row) * s.width + x);
    std::copy(line, line + 4 * static_cast<size_t>(w), dst + 4 * static_cast<size_t>(row) * w);
  }
  return out;
}

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

std::vector<std::string> pass_names(uint32_t bits) {
  std::vector<std::string> names;
  for (size_t p = 0; p < kFilmPassCount; ++p) {
    if ((bits & pass_bit(static_cast<FilmPass>(p))) != 0) names.emplace_back(kFilmPassNames[p]);
  }
  return names;
}

// A kept pass of the job's film, by name.
FilmPass kept_pass(const RenderJob& job, const std::string& name) {
  const FilmPass pass = film_pass(name);
  if (!job.film().has_pass(pass)) {
    throw std::invalid_argument("the render keeps no '" + name + "' pass (Settings.passes)");
  }
  return pass;
}

// Copies a rectangle of a buffer of `channels` floats per pixel into float32[h*w, channels].
py::array_t<float> copy_channels(const RenderJob& job, const std::vector<float>& buffer,
                                 int channels, int x, int y, int w, int h) {
  check_rect(job, x, y, w, h);
  const Settings& s = job.settings();
  py::array_t<float> out({static_cast<py::ssize_t>(w) * h, py::ssize_t{channels}});
  float* dst = out.mutable_data();
  const auto n = static_cast<size_t>(channels);
  for (int row = 0; row < h; ++row) {
    const float* line = buffer.data() + n * (static_cast<size_t>(y + row) * s.width + x);
    std::copy(line, line + n * w, dst + n * static_cast<size_t>(row) * w);
  }
  return out;
}

}  // namespace

void bind_render(py::module_& m) {
  std::vector<std::string> film_passes(kFilmPassNames.begin(), kFilmPassNames.end());
  m.attr("FILM_PASSES") = film_passes;

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

  py::class_<Settings>(m, "Settings")
      .def(py::init([](int width, int height, int max_depth, int aa_samples, int threads,
                       int tile_size, Fresnel fresnel, std::array<int, 4> border,
                       bool transparent_background, float cutoff, AntiAliasing aa_mode,
                       float aa_threshold, int aa_depth, bool analysis, bool feeler_pruning,
                       bool progressive, int start_pixel_size, GlassShadows glass_shadows,
                       const std::vector<std::string>& passes, int contribution_depth,
                       float pass_alpha_threshold, std::array<float, 3> mist, int glossy_samples,
                       int emitter_samples, float shutter) {
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
             s.validate();
             return s;
           }),
           py::arg("width") = 640, py::arg("height") = 480, py::arg("max_depth") = 5,
           py::arg("aa_samples") = 1, py::arg("threads") = 0, py::arg("tile_size") = 32,
           py::arg("fresnel") = Fresnel::kExact, py::arg("border") = std::array<int, 4>{0, 0, 0, 0},
           py::arg("transparent_background") = false, py::arg("cutoff") = 1.0f / 255.0f,
           py::arg("aa_mode") = AntiAliasing::kRegular, py::arg("aa_threshold") = 0.3f,
           py::arg("aa_depth") = 3, py::arg("analysis") = true, py::arg("feeler_pruning") = true,
           py::arg("progressive") = false, py::arg("start_pixel_size") = 8,
           py::arg("glass_shadows") = GlassShadows::kOpaque,
           py::arg("passes") = std::vector<std::string>{}, py::arg("contribution_depth") = 3,
           py::arg("pass_alpha_threshold") = 0.5f,
           py::arg("mist") = std::array<float, 3>{5.0f, 25.0f, 2.0f}, py::arg("glossy_samples") = 2,
           py::arg("emitter_samples") = 2, py::arg("shutter") = 0.0f,
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
           "emissive meshes from a shading point (one after a glossy bounce); shutter: Render > "
           "Motion Blur's, in frames, for the report (0: motion blur off).")
      .def_readwrite("width", &Settings::width)
      .def_readwrite("height", &Settings::height)
      .def_readwrite("max_depth", &Settings::max_depth)
      .def_readwrite("glossy_samples", &Settings::glossy_samples)
      .def_readwrite("emitter_samples", &Settings::emitter_samples)
      .def_readwrite("shutter", &Settings::shutter)
      .def_readwrite("aa_samples", &Settings::aa_samples)
      .def_readwrite("threads", &Settings::threads)
      .def_readwrite("tile_size", &Settings::tile_size)
      .def_readwrite("cryptomatte_kinds", &Settings::cryptomatte_kinds,
                     "Cryptomatte kinds kept: bits 1 object, 2 material, 4 asset; 0: none.")
      .def_readwrite("cryptomatte_depth", &Settings::cryptomatte_depth,
                     "Cryptomatte ranks kept per pixel and kind (0 to 16).")
      .def_readwrite("probe_stride", &Settings::probe_stride,
                     "An estimate probe: trace one tile in every probe_stride^2, spread over "
                     "the border, each pixel as the full render traces it; 1: every tile.")
      .def_readwrite("fresnel", &Settings::fresnel)
      .def_readwrite("glass_shadows", &Settings::glass_shadows)
      .def_property_readonly(
          "border",
          [](const Settings& s) {
            return std::array<int, 4>{s.border[0], s.border[1], s.border[2], s.border[3]};
          })
      .def_readwrite("transparent_background", &Settings::transparent_background)
      .def_readwrite("cutoff", &Settings::cutoff)
      .def_readwrite("aa_mode", &Settings::aa_mode)
      .def_readwrite("aa_threshold", &Settings::aa_threshold)
      .def_readwrite("aa_depth", &Settings::aa_depth)
      .def_readwrite("packets", &Settings::packets,
                     "Trace each pixel's camera rays as one Embree packet; off: one query "
                     "per ray (a benchmark baseline).")
      .def_readwrite("analysis", &Settings::analysis,
                     "Trace only the effects the scene calls for (shadows, reflection, "
                     "refraction, translucency); off: every effect on (a benchmark baseline).")
      .def_readwrite("feeler_pruning", &Settings::feeler_pruning,
                     "Skip shadow feelers that cannot show (light behind the surface, no "
                     "irradiance, below the cutoff); off: a feeler to every light sample "
                     "(a benchmark baseline).")
      .def_readwrite("progressive", &Settings::progressive)
      .def_readwrite("start_pixel_size", &Settings::start_pixel_size)
      .def_property(
          "passes", [](const Settings& s) { return pass_names(s.passes); },
          [](Settings& s, const std::vector<std::string>& names) { s.passes = pass_bits(names); })
      .def_readwrite("contribution_depth", &Settings::contribution_depth)
      .def_readwrite("pass_alpha_threshold", &Settings::pass_alpha_threshold)
      .def_property(
          "mist",
          [](const Settings& s) {
            return std::array<float, 3>{s.mist_start, s.mist_depth, s.mist_falloff};
          },
          [](Settings& s, std::array<float, 3> mist) {
            s.mist_start = mist[0];
            s.mist_depth = mist[1];
            s.mist_falloff = mist[2];
          })
      .def_readwrite("worker_nice", &Settings::worker_nice,
                     "The workers' niceness, 0 (normal) to 19 (lowest priority): the "
                     "viewport renders below the interface's priority.")
      .def_readwrite("fault_tile", &Settings::fault_tile,
                     "A test hook: the worker that takes this tile index throws "
                     "std::bad_alloc (MemoryError from wait()) before tracing it; -1: off.");

  py::class_<RenderJob>(m, "RenderJob",
                        "A render on worker threads. Poll with wait(), collect finished "
                        "tiles, cancel() to stop. Rows run bottom to top.")
      .def(py::init([](const Scene& scene, const Settings& settings, uint32_t record_stride,
                       const std::optional<Camera>& camera, bool record_results) {
             // The camera is copied with the GIL held: Python may assign scene.camera.
             const Camera view = camera ? *camera : scene.camera;
             py::gil_scoped_release release;
             return std::make_unique<RenderJob>(scene, settings, view, record_stride,
                                                record_results);
           }),
           py::arg("scene"), py::arg("settings"), py::arg("record_stride") = 0,
           py::arg("camera") = py::none(), py::arg("record_results") = false,
           "Compiles the scene (or reuses its last snapshot) and prepares the render. "
           "camera: the view to render, None for scene.camera. record_stride n > 0 records "
           "the rays of every n-th pixel for trace_bare() (a benchmark baseline); "
           "record_results also what they found, for replay().")
      .def(
          "replay",
          [](const RenderJob& job) {
            py::gil_scoped_release release;
            return std::make_unique<RenderJob>(ReplayOf{job});
          },
          // The replay reads this job's recording: it keeps this job alive.
          py::keep_alive<0, 1>(),
          "After a finished render made with record_results: a new job (to start) that "
          "renders the recorded pixels again, each worker the tiles it took and every query "
          "answered from its recording instead of Embree: the shading alone. Its image is "
          "this one's, bit for bit, where pixels were recorded (the others stay empty).")
      .def(
          "inspect",
          [](const RenderJob& job, int x, int y, int sample) {
            RayTree tree;
            {
              py::gil_scoped_release release;
              tree = job.inspect(x, y, sample);
            }
            return ray_tree_dict(tree, job.scene());
          },
          py::arg("x"), py::arg("y"), py::arg("sample") = -1,
          "The ray tree of pixel (x, y), counted from the bottom-left, traced again apart "
          "from the render with its scene, settings and camera: {'pixel': [r, g, b], "
          "'alpha', 'rays': [...]}, one dict per ray (kind, depth, parent, origin, end, "
          "object, material, light, weight, contribution, cut, blocked, ...); the "
          "contributions sum to 'pixel'. sample k >= 0: that grid sample alone. Raises "
          "IndexError outside the image.")
      .def("start", &RenderJob::start)
      .def("wait", &RenderJob::wait, py::arg("timeout_seconds"),
           py::call_guard<py::gil_scoped_release>(),
           "True once the render has finished or stopped after cancel().")
      .def("cancel", &RenderJob::cancel,
           "Workers stop within a row of pixels; wait() then returns promptly.")
      .def_property_readonly("progress", &RenderJob::progress)
      .def_property_readonly("frame", &RenderJob::frame,
                             "Passes completed (0 before the first): display() shows "
                             "something new each time it grows.")
      .def(
          "pass_info",
          [](const RenderJob& job) {
            const PassInfo info = job.pass_info();
            py::dict out;
            out["pass"] = info.pass;
            out["passes"] = info.passes;
            out["pixel_size"] = info.pixel_size;
            out["samples"] = info.samples;
            return out;
          },
          "{pass: passes completed, passes: in the schedule, pixel_size and samples (per "
          "pixel, its own) of the last completed pass; 0 before the first}.")
      .def(
          "display",
          [](const RenderJob& job, const std::string& kind, int first) {
            const Film& film = job.film();
            std::function<void(float*)> fill;
            if (kind == "image") {
              fill = [&film](float* out) { film.display_image(out); };
            } else if (kind == "cost") {
              fill = [&film](float* out) { film.display_cost(out); };
            } else {
              const auto known = std::find(kFilmPassNames.begin(), kFilmPassNames.end(), kind);
              if (known == kFilmPassNames.end() ||
                  !film.has_pass(static_cast<FilmPass>(known - kFilmPassNames.begin()))) {
                throw std::invalid_argument(
                    "display kind must be 'image', 'cost' or a film pass the render keeps "
                    "(Settings.passes), not '" +
                    kind + "'");
              }
              const auto pass = static_cast<FilmPass>(known - kFilmPassNames.begin());
              const int channels = film.pass_channels(pass);
              if (first < 0 || first + (channels == 1 ? 1 : 3) > channels) {
                throw std::invalid_argument("first channel out of the pass's range");
              }
              fill = [&film, pass, first](float* out) { film.display_pass(pass, first, out); };
            }
            py::array_t<float> out(
                {py::ssize_t{film.height()}, py::ssize_t{film.width()}, py::ssize_t{4}});
            float* dst = out.mutable_data();
            {
              py::gil_scoped_release release;
              fill(dst);
            }
            return out;
          },
          py::arg("kind") = "image", py::arg("first") = 0,
          "A new float32[height, width, 4] copy of what the film shows now, for a half-float "
          "texture (rows bottom to top). 'image': RGBA scene-linear, premultiplied, each "
          "value clamped to [0, 65000], NaN as 0. 'cost': rays per pixel as a heat map "
          "(cividis, dark blue to yellow, scaled by the largest so far), alpha 1. A kept "
          "film pass's name: its channels first .. first+2 (one-float passes grey), clamped "
          "the same way, Depth divided by the farthest surface, alpha 1.")
      .def(
          "pass_tile",
          [](const py::object& self, const std::string& name, int x, int y, int w, int h) {
            const auto& job = self.cast<const RenderJob&>();
            const FilmPass pass = kept_pass(job, name);
            const std::vector<float>& buffer = job.film().pass(pass);
            const int channels = job.film().pass_channels(pass);
            check_rect(job, x, y, w, h);
            return x == 0 && w == job.settings().width
                       ? view_rows(self, buffer, w, y, h, channels)
                       : copy_channels(job, buffer, channels, x, y, w, h);
          },
          py::arg("name"), py::arg("x"), py::arg("y"), py::arg("width"), py::arg("height"),
          "A kept film pass of a finished rectangle, float32[h*w, channels]; whole rows come "
          "as a read-only view.")
      .def(
          "pass_image",
          [](const RenderJob& job, const std::string& name) {
            const FilmPass pass = kept_pass(job, name);
            const Settings& s = job.settings();
            const int channels = job.film().pass_channels(pass);
            return copy_channels(job, job.film().pass(pass), channels, 0, 0, s.width, s.height)
                .reshape({s.height, s.width, channels});
          },
          py::arg("name"), "A kept film pass, float32[height, width, channels].")
      .def("take_finished_tiles",
           [](RenderJob& job) {
             std::vector<py::tuple> out;
             for (const Tile& t : job.take_finished_tiles()) {
               out.push_back(py::make_tuple(t.x, t.y, t.width, t.height));
             }
             return out;
           })
      .def(
          "tile",
          [](const py::object& self, int x, int y, int w, int h) {
            const auto& job = self.cast<const RenderJob&>();
            check_rect(job, x, y, w, h);
            return x == 0 && w == job.settings().width
                       ? view_rows(self, job.film().pixels(), w, y, h, 4)
                       : copy_rect(job, x, y, w, h);
          },
          py::arg("x"), py::arg("y"), py::arg("width"), py::arg("height"),
          "RGBA of a finished rectangle, float32[h*w, 4]; whole rows come as a read-only "
          "view of the job's buffer (no copy).")
      .def(
          "cost_tile",
          [](const py::object& self, int x, int y, int w, int h) {
            const auto& job = self.cast<const RenderJob&>();
            check_rect(job, x, y, w, h);
            return x == 0 && w == job.settings().width
                       ? view_rows(self, job.film().cost(), w, y, h, 1)
                       : copy_cost(job, x, y, w, h);
          },
          py::arg("x"), py::arg("y"), py::arg("width"), py::arg("height"),
          "Rays traced per pixel (all kinds) of a finished rectangle, float32[h*w, 1]; whole "
          "rows come as a read-only view.")
      .def(
          "cryptomatte_tile",
          [](const RenderJob& job, const std::string& kind, int x, int y, int w, int h) {
            check_rect(job, x, y, w, h);
            const CryptomatteFilm& film = job.cryptomatte();
            const auto found =
                std::find(kCryptomatteKindNames.begin(), kCryptomatteKindNames.end(), kind);
            if (found == kCryptomatteKindNames.end()) {
              throw std::invalid_argument(
                  "cryptomatte kind must be 'object', 'material' or 'asset', not '" + kind + "'");
            }
            const auto k = static_cast<CryptomatteKind>(found - kCryptomatteKindNames.begin());
            if (!film.enabled() || !film.has(k)) {
              throw std::invalid_argument("the render keeps no cryptomatte '" + kind + "'");
            }
            const int c = film.channels();
            const int width = job.settings().width;
            py::array_t<float> out({static_cast<py::ssize_t>(w) * h, static_cast<py::ssize_t>(c)});
            float* dst = out.mutable_data();
            const float* src = film.ranks(k).data();
            for (int row = 0; row < h; ++row) {
              const float* line = src + (static_cast<size_t>(y + row) * width + x) * c;
              std::copy(line, line + static_cast<size_t>(w) * c,
                        dst + static_cast<size_t>(row) * w * c);
            }
            return out;
          },
          py::arg("kind"), py::arg("x"), py::arg("y"), py::arg("width"), py::arg("height"),
          "The ranked Cryptomatte ids of a finished rectangle, float32[h*w, 2 * depth]: (id, "
          "coverage) by rank, the largest coverage first; kind: 'object', 'material' or 'asset'.")
      .def("cost_image",
           [](const RenderJob& job) {
             const Settings& s = job.settings();
             return copy_cost(job, 0, 0, s.width, s.height).reshape({s.height, s.width});
           })
      .def("image",
           [](const RenderJob& job) {
             const Settings& s = job.settings();
             return copy_rect(job, 0, 0, s.width, s.height).reshape({s.height, s.width, 4});
           })
      .def("stats", [](const RenderJob& job) { return stats_dict(job.stats()); })
      .def(
          "trace_bare",
          [](const RenderJob& job) {
            BareTrace bare;
            {
              py::gil_scoped_release release;
              bare = job.trace_bare();
            }
            py::dict out;
            out["rays"] = bare.rays;
            out["seconds"] = bare.seconds;
            out["threads"] = bare.threads;
            return out;
          },
          "After a finished render made with record_stride: its recorded rays traced again "
          "by a bare loop of single-ray Embree queries on as many threads; "
          "{rays, seconds, threads}.");
}

}  // namespace whitted::python
