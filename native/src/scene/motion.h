// Motion within the shutter: a transform (an object's, the camera's) sampled at evenly
// spaced times from the shutter's opening (time 0) to its closing (time 1), as Blender
// evaluates the scene at sub-frames.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include <glm/mat4x4.hpp>

namespace whitted {

// Where `time` in [0, 1] falls among `steps` (at least 2) evenly spaced time steps, as
// Embree finds it for a blend: the step before it, and the fraction of the way to the
// next. TransformMotion::at and Mesh::vertex_at blend with it.
struct TimeSegment {
  size_t step;
  float fraction;
};
inline TimeSegment time_segment(float time, size_t steps) {
  const auto segments = static_cast<float>(steps - 1);
  const float x = std::clamp(time, 0.0f, 1.0f) * segments;
  const auto step = static_cast<size_t>(std::clamp(std::floor(x), 0.0f, segments - 1.0f));
  return {step, x - static_cast<float>(step)};
}

class TransformMotion {
 public:
  // `samples`: at least one transform, sample i at time i / (n - 1). Between samples the
  // motion is decomposed (translation and scale-shear blended linearly, the rotation
  // along its great arc, as Cycles blends them) and the samples subdivided until no step
  // turns by more than kMaxStepAngle: Embree then blends neighbouring steps' matrices
  // linearly, which shrinks a turning object by 1 - cos(angle / 2) at most mid-step.
  explicit TransformMotion(const std::vector<glm::mat4>& samples);
  static constexpr float kMaxStepAngle = 0.07f;  // radians (4 degrees): shrinks 0.06%
  static constexpr size_t kMaxSteps = 129;       // Embree 3's limit on time steps

  // Evenly spaced over the shutter, for Embree (rtcSetGeometryTimeStepCount).
  const std::vector<glm::mat4>& steps() const { return steps_; }
  // The transform at `time` in [0, 1], blended as Embree blends the steps (its time
  // segment and fraction, then (1 - f) a + f b element by element).
  glm::mat4 at(float time) const;
  // Whether any step differs from the first.
  bool moves() const { return moves_; }

 private:
  std::vector<glm::mat4> steps_;
  bool moves_ = false;
};

// When within the shutter a camera sample is taken (Cycles' camera_sample): the time its
// sampler draws uniformly, mapped through the inverse of the Shutter Curve's cumulative
// opening (Render > Motion Blur: how open the shutter is over its time, so that every
// sample weighs the same and an opening shutter's early times are drawn less often),
// then, with Cycles' rolling shutter, moved towards the time its image row is read: the
// top row at the opening, the bottom at the close, the Duration keeping that share of
// the blur.
class Shutter {
 public:
  Shutter() = default;  // a box shutter whose rows are all read at once
  // `openness` at evenly spaced times from the opening to the close (negative values
  // count as shut; all equal, or none open: a box); `rolling_duration` in [0, 1], or
  // negative for a global shutter.
  Shutter(const std::vector<float>& openness, float rolling_duration);
  // The time in [0, 1] of a sample drawn at `u` in [0, 1) in the image row `row` from the
  // bottom of `height` rows.
  float time(float u, int row, int height) const;
  bool box() const { return cdf_.empty(); }
  bool rolling() const { return rolling_; }

 private:
  std::vector<float> cdf_;  // the opening summed up to each of the curve's times, to 1
  bool rolling_ = false;
  float duration_ = 0.0f;
};

}  // namespace whitted
