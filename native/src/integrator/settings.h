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

  // Throws std::invalid_argument naming the first bad value.
  void validate() const;
};

}  // namespace whitted
