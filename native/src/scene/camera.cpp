#include "scene/camera.h"

#include <glm/mat3x3.hpp>

namespace whitted {

Ray Camera::generate_ray(float sx, float sy) const {
  const float x = window[0] + sx * (window[1] - window[0]);
  const float y = window[2] + sy * (window[3] - window[2]);
  // Blender ignores the camera's scale; keep only its rotation.
  const Vec3 right = glm::normalize(Vec3(to_world[0]));
  const Vec3 up = glm::normalize(Vec3(to_world[1]));
  const Vec3 back = glm::normalize(Vec3(to_world[2]));
  const Vec3 position = Vec3(to_world[3]);
  Ray ray;
  ray.kind = kCameraRay;
  if (projection == Projection::kPerspective) {
    const Vec3 d = x * right + y * up - back;  // point on the plane at distance 1
    const float length = glm::length(d);
    ray.origin = position;
    ray.direction = d / length;
    // Clip distances are depths along the view axis; a ray of unit depth has this length.
    ray.t_min = clip_start * length;
    ray.t_max = clip_end * length;
  } else {
    ray.origin = position + x * right + y * up;
    ray.direction = -back;
    ray.t_min = clip_start;
    ray.t_max = clip_end;
  }
  return ray;
}

}  // namespace whitted
