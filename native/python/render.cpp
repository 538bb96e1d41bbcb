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
  rays["volume"] = s.rays.volume();
  rays["ambient_occlusion"] = s.rays.ambient_occlusion;
  rays["bevel"] = s.rays.bevel;
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
  out["world_feelers"] = s.rays.world_feelers;
  out["volume_feelers"] = s.rays.volume_feelers;
  out["volume_queries"] = s.rays.volume_queries;
  out["volume_bounds"] = s.rays.volume_bounds;
  out["volume_steps"] = s.rays.volume_steps;
  out["compile_seconds"] = s.compile_seconds;
  out["world_light_seconds"] = s.world_light_seconds;
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
  out["waves"] = s.waves;
  out["wave_bytes"] = s.wave_bytes;
  out["active_pixels"] = s.active_pixels;
  out["rounds"] = s.rounds;
  out["time_limited"] = s.time_limited;
  out["samples_per_pixel"] = py::make_tuple(s.samples_min, s.samples_mean, s.samples_max);
  if (s.noise) {
    py::dict noise;
    noise["mean"] = s.noise->mean;
    noise["max"] = s.noise->max;
    out["noise"] = noise;
  }
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
      .def("start", &RenderJob::start,
           "Starts the worker threads and returns at once; a second call does nothing.")
      .def("wait", &RenderJob::wait, py::arg("timeout_seconds"),
           py::call_guard<py::gil_scoped_release>(),
           "True once the render has finished or stopped after cancel().")
      .def("cancel", &RenderJob::cancel,
           "Workers stop within a row of pixels; wait() then returns promptly.")
      .def_property_readonly("progress", &RenderJob::progress,
                             "The fraction of tiles of all passes done, 0 to 1.")
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
      .def(
          "take_finished_tiles",
          [](RenderJob& job) {
            std::vector<py::tuple> out;
            for (const Tile& t : job.take_finished_tiles()) {
              out.push_back(py::make_tuple(t.x, t.y, t.width, t.height));
            }
            return out;
          },
          "(x, y, width, height) of each tile whose last pass finished since the last call.")
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
      .def(
          "cost_image",
          [](const RenderJob& job) {
            const Settings& s = job.settings();
            return copy_cost(job, 0, 0, s.width, s.height).reshape({s.height, s.width});
          },
          "Rays traced per pixel (all kinds) so far, a new float32[height, width].")
      .def(
          "image",
          [](const RenderJob& job) {
            const Settings& s = job.settings();
            return copy_rect(job, 0, 0, s.width, s.height).reshape({s.height, s.width, 4});
          },
          "The RGBA image so far, a new float32[height, width, 4] (rows bottom to top).")
      .def(
          "stats", [](const RenderJob& job) { return stats_dict(job.stats()); },
          "A dict of the render so far: rays by type, rays skipped by reason, effects as "
          "{name, on, why}, times (world_light_seconds: of compile_seconds, the world light's map "
          "built by this job's compile, 0 when kept), counts, top_level_built, cancelled and "
          "error. Noise-driven "
          "sampling: active_pixels after the last check, rounds traced, time_limited (whether "
          "Settings.time_limit ended the render early), samples_per_pixel (min, mean, max) "
          "over the border once the render has stopped, and then noise: {mean, max} of the "
          "pixels' final noise estimate, Cycles' metric before its x5 scale (a pixel stops "
          "once it is below 5 x noise_threshold; divide by 5 to compare with the threshold), "
          "over the border's pixels with one (2 or more samples, not NaN). The key is absent "
          "without adaptive_sampling, before the render stops, and if no pixel has an "
          "estimate.")
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
