#include "integrator/settings.h"

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "integrator/passes.h"

namespace whitted {
namespace {

void check_range(const char* name, int64_t value, int64_t low, int64_t high) {
  if (value < low || value > high) {
    throw std::invalid_argument(std::string(name) + " is " + std::to_string(value) +
                                "; it must be between " + std::to_string(low) + " and " +
                                std::to_string(high));
  }
}

}  // namespace

void Settings::validate() const {
  check_range("width", width, 1, 65536);
  check_range("height", height, 1, 65536);
  // 16 bytes a pixel: 2^28 pixels is a 4 GiB image, past what a render should allocate.
  check_range("width * height", int64_t{width} * height, 1, int64_t{1} << 28);
  check_range("max_depth", max_depth, 0, 256);
  check_range("glossy_samples", glossy_samples, 1, 16);
  check_range("emitter_samples", emitter_samples, 1, 16);
  check_range("aa_samples", aa_samples, 1, 64);
  check_range("aa_depth", aa_depth, 0, 6);
  if (!(aa_threshold >= 0.0f && aa_threshold <= 3.0f)) {
    throw std::invalid_argument("aa_threshold must be between 0 and 3");
  }
  check_range("threads", threads, 0, 1024);
  check_range("tile_size", tile_size, 1, 4096);
  check_range("probe_stride", probe_stride, 1, 256);
  check_range("cryptomatte_kinds", cryptomatte_kinds, 0, 7);
  check_range("cryptomatte_depth", cryptomatte_depth, 0, 16);
  if (!(cutoff >= 0.0f && cutoff <= 1.0f)) {
    throw std::invalid_argument("cutoff must be between 0 and 1");
  }
  check_range("start_pixel_size", start_pixel_size, 1, 64);
  if ((start_pixel_size & (start_pixel_size - 1)) != 0) {
    throw std::invalid_argument("start_pixel_size is " + std::to_string(start_pixel_size) +
                                "; it must be a power of two");
  }
  check_range("fault_tile", fault_tile, -1, INT32_MAX);
  check_range("contribution_depth", contribution_depth, 1, kMaxContributionDepth);
  if (passes >= pass_bit(FilmPass::kCount)) {
    throw std::invalid_argument("passes has bits beyond the last film pass");
  }
  if (!(pass_alpha_threshold >= 0.0f && pass_alpha_threshold <= 1.0f)) {
    throw std::invalid_argument("pass_alpha_threshold must be between 0 and 1");
  }
  if (!(mist_start >= 0.0f && mist_depth >= 0.0f && std::isfinite(mist_start) &&
        std::isfinite(mist_depth) && mist_falloff > 0.0f && mist_falloff <= 16.0f)) {
    throw std::invalid_argument(
        "mist: start and depth must be finite and >= 0, falloff in (0, 16]");
  }
  check_range("worker_nice", worker_nice, 0, 19);
  check_range("glass_shadows", static_cast<int64_t>(glass_shadows), 0, 1);
  int xmin = 0, ymin = 0, xmax = 0, ymax = 0;
  border_rect(&xmin, &ymin, &xmax, &ymax);
  check_range("border xmin", xmin, 0, width - 1);
  check_range("border ymin", ymin, 0, height - 1);
  check_range("border xmax", xmax, xmin + 1, width);
  check_range("border ymax", ymax, ymin + 1, height);
}

void Settings::border_rect(int* xmin, int* ymin, int* xmax, int* ymax) const {
  const bool whole = border[0] == 0 && border[1] == 0 && border[2] == 0 && border[3] == 0;
  *xmin = whole ? 0 : border[0];
  *ymin = whole ? 0 : border[1];
  *xmax = whole ? width : border[2];
  *ymax = whole ? height : border[3];
}

}  // namespace whitted
