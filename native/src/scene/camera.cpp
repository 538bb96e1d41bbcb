#include "scene/camera.h"

#include <algorithm>
#include <cmath>

#include <glm/mat3x3.hpp>

namespace whitted {

Ray Camera::generate_ray(float sx, float sy, glm::vec2 lens_sample, float time) const {
  return CameraFrame(*this).generate_ray(sx, sy, lens_sample, time);
}

glm::vec2 Lens::aperture_point(glm::vec2 u) const {
  glm::vec2 point(0.0f);
  if (blades < 3) {
    float r = 0.0f;
    float phi = 0.0f;
    concentric_disc(2.0f * u.x - 1.0f, 2.0f * u.y - 1.0f, &r, &phi);
    point = glm::vec2(r * std::cos(phi), r * std::sin(phi));
  } else {
    // u.x picks one of the polygon's triangles about its centre and, rescaled, the
    // distance from the centre (sqrt: uniform over area); u.y the place along its edge.
    // Its corners sit half a step either side of `rotation` (+ k steps), as Cycles'
    // regular_polygon_sample places them: at rotation 0 a square's edges are upright.
    const float sides = static_cast<float>(blades);
    const float scaled = u.x * sides;
    const float side = std::min(std::floor(scaled), sides - 1.0f);
    const float along = std::sqrt(scaled - side);
    const float step = 2.0f * kPi / sides;
    const float a0 = rotation + (side - 0.5f) * step;
    const glm::vec2 c0(std::cos(a0), std::sin(a0));
    const glm::vec2 c1(std::cos(a0 + step), std::sin(a0 + step));
    point = along * ((1.0f - u.y) * c0 + u.y * c1);
  }
  point.x /= ratio;  // anamorphic: narrower (ratio > 1) or wider
  return radius * point;
}

CameraFrame::CameraFrame(const Camera& c) : CameraFrame(c, c.to_world) {}

CameraFrame::CameraFrame(const Camera& c, const glm::mat4& to_world)
    : camera(c),
      right(glm::normalize(Vec3(to_world[0]))),
      up(glm::normalize(Vec3(to_world[1]))),
      back(glm::normalize(Vec3(to_world[2]))),
      position(to_world[3]) {}

Ray CameraFrame::generate_ray(float sx, float sy, glm::vec2 lens_sample, float time) const {
  // A moving camera is where the sample's time puts it (its motion blended as Embree
  // blends an instance's), its axes normalised again.
  Ray ray = camera.motion
                ? CameraFrame(camera, camera.motion->at(time)).ray_here(sx, sy, lens_sample)
                : ray_here(sx, sy, lens_sample);
  ray.time = time;
  return ray;
}

Ray CameraFrame::ray_here(float sx, float sy, glm::vec2 lens_sample) const {
  const float* window = camera.window;
  const float x = window[0] + sx * (window[1] - window[0]);
  const float y = window[2] + sy * (window[3] - window[2]);
  if (camera.projection == Projection::kPanoramic) return panoramic_ray(x, y, lens_sample);
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
  if (!camera.lens.blurs()) return ray;
  // The thin lens: from a point of the aperture through where the pinhole ray meets the
  // plane in focus (focus_distance along the view axis); clip distances stay depths.
  const float depth = glm::dot(ray.direction, -back);  // per unit of the ray's length
  const Vec3 focus = ray.origin + ray.direction * (camera.lens.focus_distance / depth);
  const glm::vec2 offset = camera.lens.aperture_point(lens_sample);
  const Vec3 origin = ray.origin + offset.x * right + offset.y * up;
  const Vec3 d = focus - origin;
  const float length = glm::length(d);
  ray.origin = origin;
  ray.direction = d / length;
  // Both projections' rays now leave the camera's plane (depth 0).
  const float per_depth = 1.0f / glm::dot(ray.direction, -back);
  ray.t_min = camera.clip_start * per_depth;
  ray.t_max = camera.clip_end * per_depth;
  return ray;
}

Ray CameraFrame::panoramic_ray(float u, float v, glm::vec2 lens_sample) const {
  Ray ray;
  Vec3 d;
  if (!camera.panorama.direction(u, v, &d)) {
    ray.kind = kNoRay;
    ray.origin = position;
    ray.t_max = 0.0f;
    return ray;
  }
  ray.kind = kCameraRay;
  Vec3 origin(0.0f);
  if (camera.lens.blurs()) {
    // A thin lens across each ray, as Cycles: the aperture spans the plane at right angles
    // to the ray, oriented by the projection's own +X axis; the ray passes through its
    // point at focus_distance along itself.
    const Vec3 axis = camera.panorama.to_camera(Vec3(1.0f, 0.0f, 0.0f));
    Vec3 across = axis - glm::dot(axis, d) * d;
    const float length = glm::length(across);
    // Along the axis itself (never the camera's Y) any perpendicular will do.
    across =
        length > 1e-6f ? across / length : glm::normalize(glm::cross(d, Vec3(0.0f, 1.0f, 0.0f)));
    const Vec3 other = camera.panorama.handedness() * glm::cross(d, across);
    const glm::vec2 offset = camera.lens.aperture_point(lens_sample);
    origin = offset.x * across + offset.y * other;
    d = glm::normalize(camera.lens.focus_distance * d - origin);
  }
  // Camera frame to world; clip distances are measured along the ray (Cycles' panoramas).
  ray.origin = position + origin.x * right + origin.y * up + origin.z * back;
  ray.direction = glm::normalize(d.x * right + d.y * up + d.z * back);
  ray.t_min = camera.clip_start;
  ray.t_max = camera.clip_end;
  return ray;
}

}  // namespace whitted
