#include "denoise/oidn.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <initializer_list>
#include <system_error>
#include <utility>

namespace whitted::oidn {

namespace {

// The OIDN C API as far as we use it (include/OpenImageDenoise/oidn.h, the same in 1.4 and
// 2.x): handles are opaque pointers, enums are ints.
using Device = void*;
using Filter = void*;
constexpr int kDeviceTypeCpu = 1;
constexpr int kFormatFloat3 = 3;
constexpr int kErrorNone = 0;
// OIDNQuality (2.x): OIDN_QUALITY_FAST 4, BALANCED 5, HIGH 6.
int quality_value(Quality q) {
  switch (q) {
    case Quality::kFast:
      return 4;
    case Quality::kBalanced:
      return 5;
    case Quality::kHigh:
      break;
  }
  return 6;
}

// RTLD_DEEPBIND makes OIDN's modules bind to their own dependencies (the TBB copy that
// scripts/stage_oidn.sh renames for the CPU device) before the host's: in Debian's
// Blender 3.4 (jemalloc, the system TBB loaded) the first oidnCommitDevice aborts in
// free() without it, even with the renamed TBB (seen, session 24). AddressSanitizer
// refuses DEEPBIND, so sanitizer builds load without it (and would abort in Blender 3.4).
#if defined(__SANITIZE_ADDRESS__)
constexpr int kDlopenFlags = RTLD_NOW | RTLD_LOCAL;
#else
constexpr int kDlopenFlags = RTLD_NOW | RTLD_LOCAL | RTLD_DEEPBIND;
#endif

std::string dl_error() {
  const char* e = dlerror();
  return e ? e : "unknown dlopen error";
}

// The directory of the binary holding this code (the Python module or a test program).
std::filesystem::path own_directory() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<const void*>(&own_directory), &info) == 0 || !info.dli_fname)
    return {};
  std::error_code ec;
  const auto file = std::filesystem::canonical(info.dli_fname, ec);
  return ec ? std::filesystem::path{} : file.parent_path();
}

// OIDN 2.x loads its CPU device from libOpenImageDenoise_device_cpu.so.<version> in the
// core's directory; our copies sit together, so this finds it next to the wrapper.
std::filesystem::path device_module(const std::filesystem::path& wrapper) {
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(wrapper.parent_path(), ec)) {
    if (entry.path().filename().string().starts_with("libOpenImageDenoise_device_cpu.so."))
      return entry.path();
  }
  return {};
}

}  // namespace

struct Library::Api {
  Device (*new_device)(int type);
  void (*commit_device)(Device);
  void (*release_device)(Device);
  int (*get_device_error)(Device, const char** message);
  void (*set_device_bool)(Device, const char* name, bool value);
  void (*set_device_int)(Device, const char* name, int value);
  int (*get_device_int)(Device, const char* name);
  Filter (*new_filter)(Device, const char* type);
  void (*set_shared_filter_image)(Filter, const char* name, void* ptr, int format, size_t width,
                                  size_t height, size_t byte_offset, size_t pixel_stride,
                                  size_t row_stride);
  void (*set_filter_bool)(Filter, const char* name, bool value);
  void (*set_filter_int)(Filter, const char* name, int value);
  void (*commit_filter)(Filter);
  void (*execute_filter)(Filter);
  void (*release_filter)(Filter);
  void (*set_progress_monitor)(Filter, bool (*monitor)(void* user, double done), void* user);

  // The device's pending error, or an empty string.
  std::string error(Device device) const {
    const char* message = nullptr;
    if (get_device_error(device, &message) == kErrorNone) return {};
    return message && *message ? message : "unknown OIDN error";
  }
};

namespace {

// Resolves `names` in order (2.x name first, then 1.x) into `fn`; on failure adds the
// names to `missing`.
template <typename Fn>
void resolve(void* handle, Fn& fn, std::initializer_list<const char*> names, std::string& missing) {
  for (const char* name : names) {
    if (void* sym = dlsym(handle, name)) {
      fn = reinterpret_cast<Fn>(sym);
      return;
    }
  }
  fn = nullptr;
  missing += missing.empty() ? "" : ", ";
  missing += *names.begin();
}

// Releases an OIDN handle when it leaves scope.
template <typename Handle>
class Owned {
 public:
  Owned(Handle h, void (*release)(Handle)) : h_(h), release_(release) {}
  Owned(const Owned&) = delete;
  Owned& operator=(const Owned&) = delete;
  ~Owned() {
    if (h_) release_(h_);
  }
  Handle get() const { return h_; }

 private:
  Handle h_;
  void (*release_)(Handle);
};

}  // namespace

std::vector<std::string> Library::default_candidates() {
  std::vector<std::string> out;
  if (const char* env = std::getenv("WHITTED_OIDN_LIBRARY"); env && *env) out.emplace_back(env);
  if (const auto dir = own_directory(); !dir.empty())
    out.push_back((dir / "libs" / "libOpenImageDenoise.so.2").string());
  out.emplace_back(WHITTED_OIDN_STAGED_DIR "/libOpenImageDenoise.so.2");
  return out;
}

const Library& Library::shared() {
  static const Library library = open(default_candidates());
  return library;
}

Library Library::open(const std::vector<std::string>& candidates) {
  Library lib;
  Status& s = lib.status_;
  std::string looked;
  for (const std::string& c : candidates) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(c, ec)) {
      s.path = c;
      break;
    }
    looked += looked.empty() ? c : ", " + c;
  }
  if (s.path.empty()) {
    s.report = "OpenImageDenoise not found: looked in " + (looked.empty() ? "nothing" : looked);
    return lib;
  }
  void* handle = dlopen(s.path.c_str(), kDlopenFlags);
  if (!handle) {
    s.report = "OpenImageDenoise could not be loaded from " + s.path + ": " + dl_error();
    return lib;
  }
  // Mapped before the first device, with the same flags, so that the core's own dlopen
  // of this path reuses it and its TBB binds as the wrapper's does (see kDlopenFlags).
  // OIDN 1.x has no device modules.
  if (const auto device = device_module(s.path); !device.empty()) {
    if (!dlopen(device.c_str(), kDlopenFlags)) {
      s.report = "OpenImageDenoise's CPU device could not be loaded from " + device.string() +
                 ": " + dl_error();
      return lib;
    }
  }
  auto api = std::make_shared<Api>();
  std::string missing;
  resolve(handle, api->new_device, {"oidnNewDevice"}, missing);
  resolve(handle, api->commit_device, {"oidnCommitDevice"}, missing);
  resolve(handle, api->release_device, {"oidnReleaseDevice"}, missing);
  resolve(handle, api->get_device_error, {"oidnGetDeviceError"}, missing);
  resolve(handle, api->set_device_bool, {"oidnSetDeviceBool", "oidnSetDevice1b"}, missing);
  resolve(handle, api->set_device_int, {"oidnSetDeviceInt", "oidnSetDevice1i"}, missing);
  resolve(handle, api->get_device_int, {"oidnGetDeviceInt", "oidnGetDevice1i"}, missing);
  resolve(handle, api->new_filter, {"oidnNewFilter"}, missing);
  resolve(handle, api->set_shared_filter_image, {"oidnSetSharedFilterImage"}, missing);
  resolve(handle, api->set_filter_bool, {"oidnSetFilterBool", "oidnSetFilter1b"}, missing);
  resolve(handle, api->set_filter_int, {"oidnSetFilterInt", "oidnSetFilter1i"}, missing);
  resolve(handle, api->commit_filter, {"oidnCommitFilter"}, missing);
  resolve(handle, api->execute_filter, {"oidnExecuteFilter"}, missing);
  resolve(handle, api->release_filter, {"oidnReleaseFilter"}, missing);
  resolve(handle, api->set_progress_monitor, {"oidnSetFilterProgressMonitorFunction"}, missing);
  if (!missing.empty()) {
    s.report = "OpenImageDenoise at " + s.path + " lacks " + missing;
    return lib;
  }
  const Owned<Device> device(api->new_device(kDeviceTypeCpu), api->release_device);
  if (!device.get()) {
    s.report = "OpenImageDenoise at " + s.path + " has no CPU device: " + api->error(nullptr);
    return lib;
  }
  api->commit_device(device.get());
  if (std::string e = api->error(device.get()); !e.empty()) {
    s.report = "OpenImageDenoise at " + s.path + ": the CPU device failed: " + e;
    return lib;
  }
  s.version = api->get_device_int(device.get(), "version");
  const int v = s.version;
  s.ok = true;
  s.report = "OpenImageDenoise " + std::to_string(v / 10000) + "." + std::to_string(v / 100 % 100) +
             "." + std::to_string(v % 100) + " from " + s.path;
  lib.api_ = std::move(api);
  return lib;
}

std::string Library::denoise(const float* color, const float* albedo, const float* normal,
                             float* out, int width, int height, const Options& options) const {
  if (!status_.ok) return status_.report;
  if (width <= 0 || height <= 0 || !color || !out) return "denoise: empty image";
  const Api& api = *api_;
  const Owned<Device> device(api.new_device(kDeviceTypeCpu), api.release_device);
  if (!device.get()) return "OpenImageDenoise: no CPU device: " + api.error(nullptr);
  api.set_device_int(device.get(), "numThreads", options.threads);
  api.set_device_bool(device.get(), "setAffinity", false);
  api.commit_device(device.get());
  if (std::string e = api.error(device.get()); !e.empty()) return "OpenImageDenoise: " + e;

  const size_t w = static_cast<size_t>(width), h = static_cast<size_t>(height);
  const bool has_quality = status_.version >= 20000;
  // Runs the RT filter over `images` (name, pointer) with the given flags.
  auto run = [&](std::initializer_list<std::pair<const char*, const float*>> images, float* output,
                 bool hdr, bool clean_aux) -> std::string {
    const Owned<Filter> filter(api.new_filter(device.get(), "RT"), api.release_filter);
    if (!filter.get()) return "OpenImageDenoise: no RT filter: " + api.error(device.get());
    for (const auto& [name, data] : images) {
      // OIDN only reads its inputs; the C API takes them as void*.
      api.set_shared_filter_image(filter.get(), name, const_cast<float*>(data), kFormatFloat3, w, h,
                                  0, 0, 0);
    }
    api.set_shared_filter_image(filter.get(), "output", output, kFormatFloat3, w, h, 0, 0, 0);
    api.set_filter_bool(filter.get(), "hdr", hdr);
    api.set_filter_bool(filter.get(), "cleanAux", clean_aux);
    if (has_quality) api.set_filter_int(filter.get(), "quality", quality_value(options.quality));
    if (options.cancel) {
      // OIDN calls this from its own threads; returning false cancels the filter.
      auto keep_going = [](void* user, double) {
        return !static_cast<const std::atomic<bool>*>(user)->load(std::memory_order_relaxed);
      };
      api.set_progress_monitor(filter.get(), keep_going,
                               const_cast<std::atomic<bool>*>(options.cancel));
    }
    api.commit_filter(filter.get());
    api.execute_filter(filter.get());
    if (std::string e = api.error(device.get()); !e.empty()) return "OpenImageDenoise: " + e;
    return {};
  };

  std::vector<float> albedo_used, normal_used;
  if (normal && !albedo) albedo_used.assign(w * h * 3, 0.5f);
  if (options.prefilter == Prefilter::kAccurate) {
    if (albedo) {
      albedo_used.assign(albedo, albedo + w * h * 3);
      if (std::string e = run({{"albedo", albedo}}, albedo_used.data(), false, false); !e.empty())
        return e;
    }
    if (normal) {
      normal_used.assign(normal, normal + w * h * 3);
      if (std::string e = run({{"normal", normal}}, normal_used.data(), false, false); !e.empty())
        return e;
    }
  }
  const float* a = albedo_used.empty() ? albedo : albedo_used.data();
  const float* n = normal_used.empty() ? normal : normal_used.data();
  const bool clean_aux = options.prefilter != Prefilter::kFast;
  if (n) return run({{"color", color}, {"albedo", a}, {"normal", n}}, out, true, clean_aux);
  if (a) return run({{"color", color}, {"albedo", a}}, out, true, clean_aux);
  return run({{"color", color}}, out, true, false);
}

}  // namespace whitted::oidn
