// The film's pixel filter (Render > Film > Pixel Filter), as Cycles': how much a camera
// sample at an offset from a pixel's centre counts towards that pixel.
#pragma once

#include <vector>

#include "integrator/settings.h"

namespace whitted {

// Filter importance sampling (Ernst, Stamminger and Greiner 2006): instead of weighting
// samples by the filter, the samples are placed by it. A sample's offset from the pixel's
// centre along each axis is drawn from the 1D filter (the 2D filter is their product, as
// Cycles'), and every sample weighs 1, so a pixel stays the mean of its own samples (no
// splatting into neighbours; tiles and threads change nothing). The filters and their
// widths are Cycles' (scene/film.cpp and its Blender sync): Box, the pixel's square
// whatever the width; Gaussian exp(-2 (6 v / 3w)^2) over |v| <= 1.5 w (a standard
// deviation of w / 4); Blackman-Harris over |v| <= w, its four-term window stretched over
// that support. The default, Blackman-Harris 1.5 pixels, softens edges over a pixel and a
// half each side. A sample drawn this way may land in a neighbouring pixel's square: it
// still belongs to the pixel that drew it.
class PixelFilter {
 public:
  PixelFilter(PixelFilterType type, float width);
  // The image's filter: the settings', except that Whitted's adaptive anti-aliasing
  // (its corners, and its grid when sampled one sample at a time) samples the pixel's
  // square, a Box of 1, in every render of the scene alike.
  explicit PixelFilter(const Settings& settings)
      : PixelFilter(settings.aa_mode == AntiAliasing::kAdaptive ? PixelFilterType::kBox
                                                                : settings.pixel_filter,
                    settings.aa_mode == AntiAliasing::kAdaptive ? 1.0f : settings.filter_width) {}

  // Where a sample whose uniform coordinate along one axis is u in [0, 1) lands, in
  // pixels from the pixel's lower (left or bottom) edge: the centre 0.5 for u = 0.5,
  // monotone in u, so stratified u give stratified offsets. The Box gives u itself (the
  // pixel's square, bit for bit).
  float position(float u) const;
  // The filter's value at offset v from the centre (its peak 1); 0 outside the support.
  float weight(float v) const;
  // Half the support: no sample lands further from the centre.
  float radius() const { return radius_; }

 private:
  PixelFilterType type_;
  float width_;
  float radius_;
  // The offset in [0, radius] at which the filter's mass from the centre outwards reaches
  // k / kTable of its half (k = 0 .. kTable); positions between are interpolated.
  std::vector<float> half_inverse_;
};

}  // namespace whitted
