// The camera: turns a point on the image into a primary ray.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>

#include <memory>

#include "core/ray.h"
#include "scene/motion.h"
#include "scene/panorama.h"

namespace whitted {

enum class Projection { kPerspective, kOrthographic, kPanoramic };

// A thin lens: depth of field as Cycles' camera models it. Rays leave a point of the
// aperture and pass through the point of the plane in focus the pinhole ray meets.
struct Lens {
  float radius = 0.0f;          // of the aperture, world units; 0: a pinhole (no blur)
  float focus_distance = 1.0f;  // of the plane in focus, along the view axis
  int blades = 0;               // a regular polygon of this many sides; below 3 a disc
  float rotation = 0.0f;        // of the polygon, radians
  float ratio = 1.0f;           // anamorphic bokeh: the aperture's width over this

  bool blurs() const { return radius > 0.0f; }
  // The point of the aperture for (u, v) in [0, 1)^2, in units of the camera's right
  // and up axes: the disc (or polygon) of `radius`, area-preserving.
  glm::vec2 aperture_point(glm::vec2 u) const;
};

struct Camera {
  // Camera to world. The camera looks down its local -Z with +Y up (Blender's convention).
  glm::mat4 to_world{1.0f};
  Projection projection = Projection::kPerspective;
  // Image rectangle (xmin, xmax, ymin, ymax): on the plane at distance 1 for perspective,
  // in camera units for orthographic, of the panorama's [0, 1]^2 for panoramic (Cycles'
  // viewplane). Lens shift is already included.
  float window[4] = {-0.5f, 0.5f, -0.5f, 0.5f};
  float clip_start = 0.1f;
  float clip_end = 1000.0f;
  Lens lens;
  Panorama panorama;  // the projection of a kPanoramic camera
  // Its to_world over the shutter (motion blur; scale removed); null when it stays put.
  std::shared_ptr<const TransformMotion> motion;
  // When in the shutter each camera sample is taken (its curve, a rolling shutter).
  Shutter shutter;

  // (sx, sy) in [0,1]^2 with (0,0) the bottom-left corner of the image; `lens` the
  // aperture sample (Lens::aperture_point), ignored by a pinhole. Where a panorama covers
  // no direction the ray's kind is kNoRay: it sees nothing (opaque black, as Cycles).
  // `time` in [0, 1] places a moving camera in its shutter; the ray carries it.
  Ray generate_ray(float sx, float sy, glm::vec2 lens = glm::vec2(0.5f), float time = 0.0f) const;
};

// What a camera's rays are made from, taken from it once for the many rays of a render:
// Camera::generate_ray makes one per ray, a sampler one per render.
struct CameraFrame {
  explicit CameraFrame(const Camera& camera);
  // The camera placed at `to_world` (a moving camera at one moment of its shutter).
  CameraFrame(const Camera& camera, const glm::mat4& to_world);
  Ray generate_ray(float sx, float sy, glm::vec2 lens = glm::vec2(0.5f), float time = 0.0f) const;

  const Camera& camera;
  // Blender ignores the camera's scale: the unit axes of its rotation.
  Vec3 right;
  Vec3 up;
  Vec3 back;
  Vec3 position;

 private:
  // The ray through (sx, sy) from these axes, whatever the time.
  Ray ray_here(float sx, float sy, glm::vec2 lens) const;
  // The ray of a kPanoramic camera through window point (u, v).
  Ray panoramic_ray(float u, float v, glm::vec2 lens) const;
};

}  // namespace whitted
