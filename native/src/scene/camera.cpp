#include "scene/camera.h"

#include <glm/mat3x3.hpp>

namespace whitted {

Ray Camera::generate_ray(float sx, float sy) const {
  return CameraFrame(*this).generate_ray(sx, sy);
}

CameraFrame::CameraFrame(const Camera& c)
    : camera(c),
      right(glm::normalize(Vec3(c.to_world[0]))),
      up(glm::normalize(Vec3(c.to_world[1]))),
      back(glm::normalize(Vec3(c.to_world[2]))),
      position(c.to_world[3]) {}

Ray CameraFrame::generate_ray(float sx, float sy) const {
  const float* window = camera.window;
  const float x = window[0] + sx * (window[1] - window[0]);
  const float y = window[2] + sy * (window[3] - window[2]);
  Ray ray;
  ray.kind = kCameraRay;
  if (camera.projection == Projection::kPerspective) {
    const Vec3 d = x * right + y * up - back;  // point on the plane at distance 1
    const float length = glm::length(d);
    ray.origin = position;
    ray.direction = d / length;
    // Clip distances are depths along the view axis; a ray of unit depth has this length.
    ray.t_min = camera.clip_start * length;
    ray.t_max = camera.clip_end * length;
  } else {
    ray.origin = position + x * right + y * up;
    ray.direction = -back;
    ray.t_min = camera.clip_start;
    ray.t_max = camera.clip_end;
  }
  return ray;
}

}  // namespace whitted
