#include "integrator/settings.h"

#include <stdexcept>
#include <string>

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
  check_range("aa_samples", aa_samples, 1, 64);
  check_range("threads", threads, 0, 1024);
  check_range("tile_size", tile_size, 1, 4096);
}

}  // namespace whitted
