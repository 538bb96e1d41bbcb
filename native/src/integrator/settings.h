// Render settings: everything besides the scene that decides the image.
#pragma once

#include <cstdint>

namespace whitted {

enum class Fresnel { kOff, kSchlick, kExact };

struct Settings {
  int width = 640;
  int height = 480;
  int max_depth = 5;   // secondary bounces allowed after the camera ray
  int aa_samples = 1;  // per axis: aa_samples x aa_samples samples on a regular grid
  int threads = 0;     // 0: all hardware threads
  int tile_size = 32;
  Fresnel fresnel = Fresnel::kExact;
  // Adaptive depth control (Hall & Greenberg 1983; POV-Ray's adc_bailout): a secondary
  // ray whose weight on the pixel falls below this is not traced. 0 traces every ray.
  float cutoff = 1.0f / 255.0f;
  // Pixels traced: [xmin, xmax) x [ymin, ymax), rows from the bottom; all zero means the
  // whole image. The rest of the image stays 0.
  int border[4] = {0, 0, 0, 0};
  bool transparent_background = false;  // camera rays that miss give alpha 0

  // The border as a rectangle, the whole image when unset.
  void border_rect(int* xmin, int* ymin, int* xmax, int* ymax) const;

  // Throws std::invalid_argument naming the first bad value.
  void validate() const;
};

}  // namespace whitted
