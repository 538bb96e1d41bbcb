#include "scene/motion.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>

namespace whitted {
namespace {

// A transform as translation, rotation and an upper-triangular scale-shear: M = T R S
// (the QR decomposition of its linear part by Gram-Schmidt over the columns).
struct Decomposed {
  glm::vec3 translation;
  glm::quat rotation;
  glm::mat3 scale_shear;
};

Decomposed decompose(const glm::mat4& m) {
  const glm::mat3 linear(m);
  glm::mat3 q(1.0f);
  glm::mat3 s(0.0f);  // s[column][row], upper triangular: row <= column
  for (int c = 0; c < 3; ++c) {
    glm::vec3 v = linear[c];
    for (int k = 0; k < c; ++k) {
      s[c][k] = glm::dot(q[k], linear[c]);
      v -= s[c][k] * q[k];
    }
    const float length = glm::length(v);
    s[c][c] = length;
    if (length > 0.0f) {
      q[c] = v / length;
    } else {  // a flattened axis: any unit vector completing the frame
      q[c] = c == 2 ? glm::cross(q[0], q[1]) : glm::vec3(c == 0 ? 1.0f : 0.0f, c == 1, 0.0f);
    }
  }
  if (glm::determinant(q) < 0.0f) {  // a mirror: keep the rotation proper, flip the scale
    q[2] = -q[2];
    s[2][2] = -s[2][2];
  }
  return {glm::vec3(m[3]), glm::quat_cast(q), s};
}

glm::mat4 compose(const Decomposed& d) {
  glm::mat4 m(glm::mat3_cast(d.rotation) * d.scale_shear);
  m[3] = glm::vec4(d.translation, 1.0f);
  return m;
}

Decomposed blend(const Decomposed& a, const Decomposed& b, float f) {
  glm::quat to = b.rotation;
  if (glm::dot(a.rotation, to) < 0.0f) to = -to;  // the shorter arc
  return {glm::mix(a.translation, b.translation, f), glm::slerp(a.rotation, to, f),
          (1.0f - f) * a.scale_shear + f * b.scale_shear};
}

float turn(const glm::quat& a, const glm::quat& b) {
  const float c = std::min(std::fabs(glm::dot(a, b)), 1.0f);
  return 2.0f * std::acos(c);
}

}  // namespace

TransformMotion::TransformMotion(const std::vector<glm::mat4>& samples) {
  if (samples.empty()) {
    steps_.push_back(glm::mat4(1.0f));
    return;
  }
  for (const glm::mat4& m : samples) moves_ = moves_ || m != samples.front();
  if (!moves_ || samples.size() == 1) {
    steps_.push_back(samples.front());
    return;
  }
  std::vector<Decomposed> parts;
  parts.reserve(samples.size());
  for (const glm::mat4& m : samples) parts.push_back(decompose(m));
  float widest = 0.0f;
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    widest = std::max(widest, turn(parts[i].rotation, parts[i + 1].rotation));
  }
  // Each sample interval split into `split` steps, evenly, so the steps stay evenly
  // spaced in time.
  const size_t intervals = parts.size() - 1;
  size_t split = std::max<size_t>(1, static_cast<size_t>(std::ceil(widest / kMaxStepAngle)));
  split = std::min(split, std::max<size_t>(1, (kMaxSteps - 1) / intervals));
  if (split == 1) {
    steps_ = samples;
    return;
  }
  steps_.reserve(intervals * split + 1);
  for (size_t i = 0; i < intervals; ++i) {
    steps_.push_back(samples[i]);
    for (size_t k = 1; k < split; ++k) {
      const float f = static_cast<float>(k) / static_cast<float>(split);
      steps_.push_back(compose(blend(parts[i], parts[i + 1], f)));
    }
  }
  steps_.push_back(samples.back());
}

glm::mat4 TransformMotion::at(float time) const {
  if (steps_.size() == 1) return steps_.front();
  const auto [i, f] = time_segment(time, steps_.size());
  return (1.0f - f) * steps_[i] + f * steps_[i + 1];
}

Shutter::Shutter(const std::vector<float>& openness, float rolling_duration)
    : rolling_(rolling_duration >= 0.0f), duration_(std::clamp(rolling_duration, 0.0f, 1.0f)) {
  if (openness.size() < 2) return;
  const auto open = [&](size_t i) {
    return std::isfinite(openness[i]) ? std::max(0.0f, openness[i]) : 0.0f;
  };
  bool even = true;
  for (size_t i = 1; i < openness.size(); ++i) even = even && open(i) == open(0);
  if (even) return;
  // The opening between neighbouring times, summed (trapezoids of the linear curve).
  std::vector<double> sums(openness.size(), 0.0);
  for (size_t i = 1; i < openness.size(); ++i) {
    sums[i] = sums[i - 1] + 0.5 * (double{open(i - 1)} + double{open(i)});
  }
  const double total = sums.back();
  if (!(total > 0.0)) return;  // never open: every time weighs the same
  cdf_.reserve(sums.size());
  for (double sum : sums) cdf_.push_back(static_cast<float>(sum / total));
  cdf_.back() = 1.0f;
}

float Shutter::time(float u, int row, int height) const {
  float t = u;
  if (!cdf_.empty()) {
    // The step whose share of the opening holds u (a shut step holds none), and the
    // time within it in proportion.
    const auto above = std::upper_bound(cdf_.begin() + 1, cdf_.end() - 1, u);
    const auto i = static_cast<size_t>(above - cdf_.begin()) - 1;
    const float width = cdf_[i + 1] - cdf_[i];
    const float within = width > 0.0f ? std::clamp((u - cdf_[i]) / width, 0.0f, 1.0f) : 0.0f;
    t = (static_cast<float>(i) + within) / static_cast<float>(cdf_.size() - 1);
  }
  if (!rolling_) return t;
  // Read from the top: the top row at the opening, the bottom row at the close.
  const float read = 1.0f - static_cast<float>(row) / static_cast<float>(std::max(1, height));
  return (t - 0.5f) * duration_ + (read - 0.5f) * (1.0f - duration_) + 0.5f;
}

}  // namespace whitted
