// Panoramic cameras: the projections Blender's Panoramic camera type offers, each a map
// from a point of the image to a direction (Cycles' kernel/camera/projection.h defines
// them; these are written from its formulas).
#pragma once

#include <glm/vec2.hpp>

#include "core/math.h"

namespace whitted {

enum class PanoramaType {
  kEquirectangular,         // longitude across, latitude up, within their ranges
  kEquiangularCubemapFace,  // one face of a cube, its angles spread evenly
  kMirrorBall,              // the world as a chrome ball reflects it
  kFisheyeEquidistant,      // angle from the axis proportional to the image radius
  kFisheyeEquisolid,        // a real fisheye lens: r = 2 f sin(theta / 2), on the sensor
  kFisheyeLensPolynomial,   // theta a polynomial of the sensor radius (mm)
  kCentralCylindrical,      // longitude across, height on a unit cylinder up
};

struct Panorama {
  PanoramaType type = PanoramaType::kEquirectangular;
  // Equirectangular ranges, radians: longitude about the view axis (left is minimum),
  // latitude above the horizon.
  float longitude_min = -kPi;
  float longitude_max = kPi;
  float latitude_min = -0.5f * kPi;
  float latitude_max = 0.5f * kPi;
  float fisheye_fov = kPi;       // radians: the fisheyes' widest angle
  float fisheye_lens = 10.5f;    // mm (equisolid)
  float sensor_width = 36.0f;    // mm, fitted to the image's aspect (the fisheyes')
  float sensor_height = 24.0f;   // mm
  float polynomial[5] = {0.0f};  // k0..k4: theta = -(k0 + k1 r + ... + k4 r^4), r in mm
  // Central cylindrical: longitude range (radians) and the height range over the radius.
  float cylinder_u_min = -kPi;
  float cylinder_u_max = kPi;
  float cylinder_v_min = -1.0f;
  float cylinder_v_max = 1.0f;

  // The unit direction, in the camera's frame (looking down -Z, +Y up), of image point
  // (u, v): [0, 1]^2 spans the image from its bottom-left corner (lens shift added). False
  // where the projection covers no direction (outside a fisheye's or the ball's circle).
  bool direction(float u, float v, Vec3* local) const;
  // The image point (u, v) that looks along unit camera-frame direction `local`: the
  // inverse of direction() (what Cycles' Window texture coordinate reads for panoramas);
  // for the polynomial fisheye found by Newton's method, as Cycles finds it.
  glm::vec2 image_point(const Vec3& local) const;
  // The projection's own frame (Cycles' panorama space: +X its centre, +Z up) to the
  // camera's; the mirror ball looks down its -Y. Its determinant (+1 or -1) orients the
  // aperture: a thin lens on a panorama spans the plane across each ray.
  Vec3 to_camera(const Vec3& d) const;
  float handedness() const { return type == PanoramaType::kMirrorBall ? -1.0f : 1.0f; }
};

}  // namespace whitted
