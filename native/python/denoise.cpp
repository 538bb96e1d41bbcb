// Open Image Denoise (native/src/denoise/oidn.h): whether it loaded, and denoising of a
// float RGB image, for the tests and the add-on.
#include "denoise/oidn.h"

#include "bindings.h"

namespace whitted::python {
namespace {

oidn::Prefilter prefilter_from(const std::string& name) {
  if (name == "none") return oidn::Prefilter::kNone;
  if (name == "fast") return oidn::Prefilter::kFast;
  if (name == "accurate") return oidn::Prefilter::kAccurate;
  throw py::value_error("prefilter must be 'none', 'fast' or 'accurate', not '" + name + "'");
}

oidn::Quality quality_from(const std::string& name) {
  if (name == "high") return oidn::Quality::kHigh;
  if (name == "balanced") return oidn::Quality::kBalanced;
  if (name == "fast") return oidn::Quality::kFast;
  throw py::value_error("quality must be 'high', 'balanced' or 'fast', not '" + name + "'");
}

// A flag another thread sets to stop a denoise in progress (Options::cancel): the add-on's
// viewport denoises on a Python thread and stops it when the viewport closes.
struct DenoiseCancel {
  std::atomic<bool> flag{false};
};

}  // namespace

void bind_denoise(py::module_& m) {
  py::class_<DenoiseCancel>(m, "DenoiseCancel",
                            "Stops an oidn_denoise call given it, from any thread: cancel().")
      .def(py::init<>())
      .def(
          "cancel", [](DenoiseCancel& c) { c.flag.store(true); },
          "Ask the denoise to stop; it then raises RuntimeError (OIDN's 'cancelled').")
      .def_property_readonly(
          "cancelled", [](const DenoiseCancel& c) { return c.flag.load(); },
          "Whether cancel() was called.");
  m.def(
      "oidn_status",
      [] {
        const oidn::Status& s = oidn::Library::shared().status();
        py::dict out;
        out["ok"] = s.ok;
        out["version"] = s.version;
        out["path"] = s.path;
        out["report"] = s.report;
        return out;
      },
      "Open Image Denoise as this process loaded it (once, at the first call): {'ok', "
      "'version' (e.g. 20501), 'path' (the library, '' when none was found), 'report' (why "
      "it is unavailable, or what was loaded)}.");
  m.def(
      "oidn_denoise",
      [](const FloatArray& color, const std::optional<FloatArray>& albedo,
         const std::optional<FloatArray>& normal, int threads, const std::string& prefilter,
         const std::string& quality, DenoiseCancel* cancel) {
        require_shape(color, "color", {-1, -1, 3});
        const py::ssize_t h = color.shape(0), w = color.shape(1);
        if (albedo) require_shape(*albedo, "albedo", {h, w, 3});
        if (normal) require_shape(*normal, "normal", {h, w, 3});
        oidn::Options options;
        options.threads = threads;
        options.prefilter = prefilter_from(prefilter);
        options.quality = quality_from(quality);
        if (cancel != nullptr) options.cancel = &cancel->flag;
        FloatArray out({h, w, py::ssize_t{3}});
        std::string error;
        {
          py::gil_scoped_release release;
          error = oidn::Library::shared().denoise(
              color.data(), albedo ? albedo->data() : nullptr, normal ? normal->data() : nullptr,
              out.mutable_data(), static_cast<int>(w), static_cast<int>(h), options);
        }
        if (!error.empty()) throw std::runtime_error(error);
        return out;
      },
      py::arg("color"), py::arg("albedo") = py::none(), py::arg("normal") = py::none(),
      py::kw_only(), py::arg("threads") = 0, py::arg("prefilter") = "accurate",
      py::arg("quality") = "high", py::arg("cancel") = nullptr,
      "Denoises a float RGB image (height, width, 3) with Open Image Denoise's RT filter "
      "(hdr), given optional albedo and normal images of the same shape; returns a new "
      "array. prefilter: 'none' (the aux images are noise-free), 'fast' or 'accurate' (each "
      "aux image is denoised first); quality: 'high', 'balanced' or 'fast'; threads 0: all; "
      "cancel: a DenoiseCancel another thread may set (the GIL is released while denoising). "
      "RuntimeError with oidn_status()['report'] when the library is unavailable.");
}

}  // namespace whitted::python
