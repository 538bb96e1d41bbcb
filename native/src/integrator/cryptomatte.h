// Cryptomatte (Psyop's specification 1.1.0): for every pixel, the ids of what the camera
// sees there (object, material, asset), each with its coverage, the share of the pixel's
// coverage samples that meet it, ranked by coverage. The ids come from Python
// (addon/cryptomatte.py hashes the names); the EXR layers and their metadata are written
// by addon/result.py.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "integrator/pixel_filter.h"
#include "integrator/settings.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace whitted {

// The kinds of id, in this order; bit k of Settings::cryptomatte_kinds keeps kind k.
enum class CryptomatteKind : int { kObject, kMaterial, kAsset };
inline constexpr int kCryptomatteKinds = 3;
inline constexpr std::array<std::string_view, kCryptomatteKinds> kCryptomatteKindNames = {
    "object", "material", "asset"};
inline constexpr int kMaxCryptomatteDepth = 16;  // ranks per kind (Blender's limit)

// The ranked ids of every pixel, for the kinds the settings keep. Each pixel is written by
// one worker, once; a finished tile's pixels may be read.
class CryptomatteFilm {
 public:
  explicit CryptomatteFilm(const Settings& settings);

  bool enabled() const { return depth_ > 0 && kinds_ != 0; }
  bool has(CryptomatteKind kind) const { return (kinds_ >> static_cast<int>(kind) & 1u) != 0; }
  int depth() const { return depth_; }
  // Floats per pixel of a kept kind: (id, coverage) for each rank, the largest coverage
  // first, zero past the last id met.
  int channels() const { return 2 * depth_; }
  // A kept kind's ranks, channels() floats per pixel, rows bottom to top.
  const std::vector<float>& ranks(CryptomatteKind kind) const {
    return ranks_[static_cast<size_t>(kind)];
  }

  // Traces the coverage samples of pixel (x, y) and ranks what they meet: an n x n grid
  // of camera rays at its cells' centres placed by the pixel filter (n: aa_samples for regular and
  // jittered anti-aliasing, 2^aa_depth for adaptive: its finest squares). A ray passes through
  // cut-outs, each surface covering its alpha of what is left (as the image); a holdout
  // or the world covers nothing.
  void trace_pixel(const CompiledScene& scene, const Camera& camera, int x, int y);

 private:
  int width_;
  int height_;
  int samples_per_axis_;
  uint32_t seed_;  // Settings::seed: its samples' lens and time are the image's
  PixelFilter filter_;
  uint32_t kinds_;
  int depth_;
  std::array<std::vector<float>, kCryptomatteKinds> ranks_;
};

// Keeps the `depth` largest of `weights` (id, weight) pairs after summing the weights of
// equal ids, largest first (ties: the smaller id first), each weight times `scale`, into
// `out` (2 * depth floats, zero-filled past the last id). Ids 0 (nothing) are left out.
void rank_ids(std::vector<std::array<float, 2>>* weights, int depth, float scale, float* out);

}  // namespace whitted
