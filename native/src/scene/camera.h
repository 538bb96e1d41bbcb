// The camera: turns a point on the image into a primary ray.
#pragma once

#include <glm/mat4x4.hpp>

#include "core/ray.h"

namespace whitted {

enum class Projection { kPerspective, kOrthographic };

struct Camera {
  // Camera to world. The camera looks down its local -Z with +Y up (Blender's convention).
  glm::mat4 to_world{1.0f};
  Projection projection = Projection::kPerspective;
  // Image rectangle (xmin, xmax, ymin, ymax): on the plane at distance 1 for perspective,
  // in camera units for orthographic. Lens shift is already included.
  float window[4] = {-0.5f, 0.5f, -0.5f, 0.5f};
  float clip_start = 0.1f;
  float clip_end = 1000.0f;

  // (sx, sy) in [0,1]^2 with (0,0) the bottom-left corner of the image.
  Ray generate_ray(float sx, float sy) const;
};

}  // namespace whitted
