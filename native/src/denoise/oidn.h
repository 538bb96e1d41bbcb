// Intel Open Image Denoise, loaded at run time (dlopen): no OIDN header or library is
// needed to build. The few C functions used are declared in oidn.cpp; the 2.x names are
// tried first, then the 1.x ones (2.x removed oidnSetFilter1b & co. from the library).
//
// Where the library is found (default_candidates): $WHITTED_OIDN_LIBRARY, then
// libs/libOpenImageDenoise.so.2 next to the module that holds this code, then the build
// tree's copy that scripts/stage_oidn.sh stages (build/oidn/lib). The first existing file
// is loaded; when none exists, status().report names every path looked at.
//
// No mutable global state: a Library is immutable once open() returns. shared() is the
// process's one Library, a function-local static const built once (thread-safe by the
// language) from default_candidates(); the dlopen handles are never closed, as OIDN's
// own modules stay mapped. Every denoise() call makes and releases its own device.
#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <vector>

namespace whitted::oidn {

// The aux images' prefilter, as Cycles' denoising_prefilter: kNone, the albedo and normal
// are noise-free already; kFast, the beauty filter cleans them itself; kAccurate, each is
// denoised by its own filter first.
enum class Prefilter { kNone, kFast, kAccurate };
// The RT filter's quality (OIDN 2.x; 1.x has only high).
enum class Quality { kHigh, kBalanced, kFast };

struct Options {
  int threads = 0;  // 0: OIDN picks (all cores)
  Prefilter prefilter = Prefilter::kAccurate;
  Quality quality = Quality::kHigh;
  // When set, OIDN polls it while filtering and stops once it is true; denoise() then
  // returns OIDN's "cancelled" error and `out` holds no finished image.
  const std::atomic<bool>* cancel = nullptr;
};

struct Status {
  bool ok = false;
  int version = 0;     // the device's, e.g. 20501 for 2.5.1; 0 unless ok
  std::string path;    // the library loaded (or tried); empty when none was found
  std::string report;  // why it is unavailable, or what was loaded
};

class Library {
 public:
  // Loads the first of `candidates` (paths of the OIDN wrapper library) that exists, and
  // checks that a CPU device commits. Never throws; failures are in status().
  static Library open(const std::vector<std::string>& candidates);
  static const Library& shared();
  static std::vector<std::string> default_candidates();

  const Status& status() const { return status_; }

  // Denoises `color` into `out` (packed float RGB, width x height; out may be color).
  // albedo and normal may be null; with a normal and no albedo a constant 0.5 albedo is
  // passed (OIDN needs an albedo whenever it has a normal). Never throws: returns an
  // empty string on success, else the reason (the library's report or OIDN's error).
  std::string denoise(const float* color, const float* albedo, const float* normal, float* out,
                      int width, int height, const Options& options) const;

  struct Api;  // the resolved C functions (oidn.cpp)

 private:
  Status status_;
  std::shared_ptr<const Api> api_;  // null unless status_.ok
};

}  // namespace whitted::oidn
