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

// What a camera's rays are made from, taken from it once for the many rays of a render:
// Camera::generate_ray makes one per ray, a sampler one per render.
struct CameraFrame {
  explicit CameraFrame(const Camera& camera);
  Ray generate_ray(float sx, float sy) const;

  const Camera& camera;
  // Blender ignores the camera's scale: the unit axes of its rotation.
  Vec3 right;
  Vec3 up;
  Vec3 back;
  Vec3 position;
};

}  // namespace whitted
