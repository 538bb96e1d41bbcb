#include "integrator/pixel_filter.h"

#include <algorithm>
#include <cmath>

#include "core/math.h"

namespace whitted {
namespace {

// Steps of the filter's half over [0, radius] in its cumulative table; the inverse is
// tabulated as finely. Interpolated linearly, the placed samples' density is the filter's
// within 0.1% of its peak (pixel_filter tests).
constexpr int kSteps = 4096;
constexpr int kTable = 1024;

}  // namespace

PixelFilter::PixelFilter(PixelFilterType type, float width)
    : type_(type),
      // Cycles' Box is the pixel's square whatever the width (its sync sets 1).
      width_(type == PixelFilterType::kBox ? 1.0f : width),
      radius_(0.5f) {
  if (type_ == PixelFilterType::kGaussian) radius_ = 1.5f * width_;
  if (type_ == PixelFilterType::kBlackmanHarris) radius_ = width_;
  if (type_ == PixelFilterType::kBox) return;  // position() is u itself
  // The half's cumulative mass at kSteps + 1 offsets (trapezoids), then inverted at
  // kTable + 1 evenly spaced masses.
  std::vector<double> mass(kSteps + 1, 0.0);
  const double step = static_cast<double>(radius_) / kSteps;
  for (int i = 1; i <= kSteps; ++i) {
    const auto a = static_cast<float>((i - 1) * step);
    const auto b = static_cast<float>(i * step);
    mass[i] = mass[i - 1] + 0.5 * step * (static_cast<double>(weight(a)) + weight(b));
  }
  half_inverse_.resize(kTable + 1);
  int i = 0;
  for (int k = 0; k <= kTable; ++k) {
    const double target = mass[kSteps] * k / kTable;
    while (i < kSteps && mass[i + 1] < target) ++i;
    const double span = mass[std::min(i + 1, kSteps)] - mass[i];
    const double t = span > 0.0 ? std::clamp((target - mass[i]) / span, 0.0, 1.0) : 0.0;
    half_inverse_[k] = static_cast<float>((i + t) * step);
  }
  half_inverse_[0] = 0.0f;
  half_inverse_[kTable] = radius_;
}

float PixelFilter::weight(float v) const {
  v = std::fabs(v);
  if (v > radius_) return 0.0f;
  switch (type_) {
    case PixelFilterType::kBox:
      return 1.0f;
    case PixelFilterType::kGaussian: {
      // exp(-2 (6 v / W)^2) with W = 3 w the support's full width: sigma = w / 4.
      const float s = 6.0f * v / (3.0f * width_);
      return std::exp(-2.0f * s * s);
    }
    case PixelFilterType::kBlackmanHarris: {
      // The four-term Blackman-Harris window over the support [-w, w], peak at 0.
      const float phase = 2.0f * kPi * (v / (2.0f * width_) + 0.5f);
      return 0.35875f - 0.48829f * std::cos(phase) + 0.14128f * std::cos(2.0f * phase) -
             0.01168f * std::cos(3.0f * phase);
    }
  }
  return 0.0f;
}

float PixelFilter::position(float u) const {
  if (type_ == PixelFilterType::kBox) return u;  // the pixel's square
  // Symmetric: the half's inverse at |2u - 1| of its mass, on u's side of the centre, so
  // u = 0.5 is the centre exactly.
  const float m = std::fabs(2.0f * u - 1.0f) * static_cast<float>(kTable);
  const int k = std::min(static_cast<int>(m), kTable - 1);
  const float t = m - static_cast<float>(k);
  const float offset = half_inverse_[k] + t * (half_inverse_[k + 1] - half_inverse_[k]);
  return 0.5f + (u < 0.5f ? -offset : offset);
}

}  // namespace whitted
