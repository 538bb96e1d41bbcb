#include "integrator/settings.h"

#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>

#include "integrator/passes.h"

namespace whitted {
namespace {

void check_range(std::string_view name, int64_t value, int64_t low, int64_t high) {
  if (value < low || value > high) {
    throw std::invalid_argument(std::string(name) + " is " + std::to_string(value) +
                                "; it must be between " + std::to_string(low) + " and " +
                                std::to_string(high));
  }
}

// A setting against its kSettingRanges entry (a float NaN is out of every range), a
// float field against its bounds rounded to float (0.01 is 0.0099999998 there).
template <typename T>
void check_setting(const SettingRange& range, T value) {
  if constexpr (std::is_floating_point_v<T>) {
    if (!(value >= static_cast<T>(range.min) && value <= static_cast<T>(range.max))) {
      std::ostringstream message;
      message << range.name << " must be between " << range.min << " and " << range.max;
      throw std::invalid_argument(message.str());
    }
  } else {
    check_range(range.name, static_cast<int64_t>(value), static_cast<int64_t>(range.min),
                static_cast<int64_t>(range.max));
  }
}

}  // namespace

void Settings::validate() const {
  check_setting(setting_range("width"), width);
  check_setting(setting_range("height"), height);
  check_range("width * height", int64_t{width} * height, 1, int64_t{1} << 28);
  check_setting(setting_range("max_depth"), max_depth);
  check_setting(setting_range("glossy_samples"), glossy_samples);
  check_setting(setting_range("emitter_samples"), emitter_samples);
  check_setting(setting_range("aa_samples"), aa_samples);
  check_setting(setting_range("aa_depth"), aa_depth);
  check_setting(setting_range("aa_threshold"), aa_threshold);
  check_setting(setting_range("filter_width"), filter_width);
  check_setting(setting_range("seed"), seed);
  check_range("pixel_filter", static_cast<int64_t>(pixel_filter), 0, 2);
  check_setting(setting_range("threads"), threads);
  check_setting(setting_range("tile_size"), tile_size);
  check_setting(setting_range("probe_stride"), probe_stride);
  check_setting(setting_range("cryptomatte_kinds"), cryptomatte_kinds);
  check_setting(setting_range("cryptomatte_depth"), cryptomatte_depth);
  check_setting(setting_range("cutoff"), cutoff);
  check_setting(setting_range("start_pixel_size"), start_pixel_size);
  if ((start_pixel_size & (start_pixel_size - 1)) != 0) {
    throw std::invalid_argument("start_pixel_size is " + std::to_string(start_pixel_size) +
                                "; it must be a power of two");
  }
  check_setting(setting_range("noise_threshold"), noise_threshold);
  check_setting(setting_range("adaptive_min_samples"), adaptive_min_samples);
  check_setting(setting_range("time_limit"), time_limit);
  check_setting(setting_range("fault_tile"), fault_tile);
  check_setting(setting_range("contribution_depth"), contribution_depth);
  if (passes >= pass_bit(FilmPass::kCount)) {
    throw std::invalid_argument("passes has bits beyond the last film pass");
  }
  check_setting(setting_range("pass_alpha_threshold"), pass_alpha_threshold);
  if (!(mist_start >= 0.0f && mist_depth >= 0.0f && std::isfinite(mist_start) &&
        std::isfinite(mist_depth) && mist_falloff > 0.0f && mist_falloff <= 16.0f)) {
    throw std::invalid_argument(
        "mist: start and depth must be finite and >= 0, falloff in (0, 16]");
  }
  check_setting(setting_range("worker_nice"), worker_nice);
  check_setting(setting_range("volume_step_rate"), volume_step_rate);
  check_setting(setting_range("volume_max_steps"), volume_max_steps);
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
