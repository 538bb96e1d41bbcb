#include "scene/panorama.h"

#include <algorithm>
#include <cmath>

namespace whitted {
namespace {

// A fisheye's direction in the projection's frame (+X the axis) for angle `theta` from
// the axis at image offset (x, y) from the centre, `r` its length: y up the image is +Z,
// x right is -Y.
Vec3 fisheye(float theta, float x, float y, float r) {
  const float s = std::sin(theta);
  const float c = r > 0.0f ? x / r : 0.0f;  // at the centre, up (as Cycles)
  const float t = r > 0.0f ? y / r : 1.0f;
  return {std::cos(theta), -c * s, t * s};
}

}  // namespace

Vec3 Panorama::to_camera(const Vec3& d) const {
  // Cycles' blender_camera_matrix: the projections look down their +X with +Z up, the
  // ball down its -Y; Blender's camera looks down -Z with +Y up.
  if (type == PanoramaType::kMirrorBall) return {d.x, d.z, d.y};
  return {-d.y, d.z, -d.x};
}

glm::vec2 Panorama::image_point(const Vec3& local) const {
  // Camera frame back to the projection's (to_camera's inverse).
  const Vec3 d = type == PanoramaType::kMirrorBall ? Vec3(local.x, local.z, local.y)
                                                   : Vec3(-local.z, -local.x, local.y);
  const float across = std::sqrt(d.y * d.y + d.z * d.z);  // off the projection's axis
  // The unit direction of (d.y, d.z) in the image plane (image x is -d.y, y is d.z).
  const glm::vec2 side = across > 0.0f ? glm::vec2(-d.y, d.z) / across : glm::vec2(0.0f);
  switch (type) {
    case PanoramaType::kEquirectangular: {
      const float longitude = -std::atan2(d.y, d.x);
      const float latitude = 0.5f * kPi - std::acos(std::clamp(d.z, -1.0f, 1.0f));
      return {(longitude - longitude_min) / (longitude_max - longitude_min),
              (latitude - latitude_min) / (latitude_max - latitude_min)};
    }
    case PanoramaType::kEquiangularCubemapFace:
      return {0.5f - std::atan2(d.y, d.x) * 2.0f / kPi, std::atan2(d.z, d.x) * 2.0f / kPi + 0.5f};
    case PanoramaType::kMirrorBall: {
      // The ball's normal halfway between the view direction (0, -1, 0) reversed and d.
      Vec3 n = d - Vec3(0.0f, 1.0f, 0.0f);
      const float length = glm::length(n);
      if (length > 0.0f) n /= length;
      return {0.5f * (n.x + 1.0f), 0.5f * (n.z + 1.0f)};
    }
    case PanoramaType::kFisheyeEquidistant: {
      const float r = std::atan2(across, d.x) / fisheye_fov;  // of the image's half width
      return glm::vec2(0.5f) + r * side;
    }
    case PanoramaType::kFisheyeEquisolid: {
      const float theta = std::acos(std::clamp(d.x, -1.0f, 1.0f));
      const float r = 2.0f * fisheye_lens * std::sin(0.5f * theta);  // mm on the sensor
      return {0.5f + r * side.x / sensor_width, 0.5f + r * side.y / sensor_height};
    }
    case PanoramaType::kFisheyeLensPolynomial: {
      // theta = -(k0 + k1 r + ... + k4 r^4) solved for r from the linear guess.
      const float theta = -std::acos(std::clamp(d.x, -1.0f, 1.0f));
      const float* k = polynomial;
      float r = k[1] != 0.0f ? (theta - k[0]) / k[1] : 0.0f;
      for (int i = 0; i < 20; ++i) {
        const float f = theta - (k[0] + r * (k[1] + r * (k[2] + r * (k[3] + r * k[4]))));
        const float df = k[1] + r * (2.0f * k[2] + r * (3.0f * k[3] + r * 4.0f * k[4]));
        if (df == 0.0f) break;
        const float step = f / df;
        r += step;
        if (std::fabs(step) < 1e-6f) break;
      }
      return {0.5f + r * side.x / sensor_width, 0.5f + r * side.y / sensor_height};
    }
    case PanoramaType::kCentralCylindrical: {
      const float longitude = -std::atan2(d.y, d.x);
      const float height = d.z / std::sqrt(d.x * d.x + d.y * d.y);
      return {(longitude - cylinder_u_min) / (cylinder_u_max - cylinder_u_min),
              (height - cylinder_v_min) / (cylinder_v_max - cylinder_v_min)};
    }
  }
  return glm::vec2(0.5f);
}

bool Panorama::direction(float u, float v, Vec3* local) const {
  Vec3 d(0.0f);
  switch (type) {
    case PanoramaType::kEquirectangular: {
      // u from the minimum longitude (left) to the maximum; v from the minimum latitude
      // (bottom) up. The projection's azimuth phi (towards its +Y, the camera's left) is
      // minus the longitude.
      const float phi = -(longitude_min + u * (longitude_max - longitude_min));
      const float latitude = latitude_min + v * (latitude_max - latitude_min);
      const float theta = 0.5f * kPi - latitude;  // from the +Z pole
      const float s = std::sin(theta);
      d = {s * std::cos(phi), s * std::sin(phi), std::cos(theta)};
      break;
    }
    case PanoramaType::kEquiangularCubemapFace:
      d = glm::normalize(
          Vec3(1.0f, std::tan((0.5f - u) * 0.5f * kPi), std::tan((v - 0.5f) * 0.5f * kPi)));
      break;
    case PanoramaType::kMirrorBall: {
      // The ball's normal n under image point (u, v) (the ball seen from its -Y side)
      // mirrors the view direction (0, -1, 0): the direction the ball shows there.
      const float x = 2.0f * u - 1.0f;
      const float z = 2.0f * v - 1.0f;
      if (x * x + z * z > 1.0f) return false;
      const Vec3 n(x, -std::sqrt(std::max(1.0f - x * x - z * z, 0.0f)), z);
      const Vec3 incoming(0.0f, -1.0f, 0.0f);
      d = 2.0f * glm::dot(n, incoming) * n - incoming;
      break;
    }
    case PanoramaType::kFisheyeEquidistant: {
      const float x = 2.0f * u - 1.0f;
      const float y = 2.0f * v - 1.0f;
      const float r = std::sqrt(x * x + y * y);
      if (r > 1.0f) return false;
      d = fisheye(0.5f * r * fisheye_fov, x, y, r);
      break;
    }
    case PanoramaType::kFisheyeEquisolid: {
      const float x = (u - 0.5f) * sensor_width;
      const float y = (v - 0.5f) * sensor_height;
      const float r = std::sqrt(x * x + y * y);
      if (r > 2.0f * fisheye_lens * std::sin(0.25f * fisheye_fov)) return false;
      d = fisheye(2.0f * std::asin(std::min(r / (2.0f * fisheye_lens), 1.0f)), x, y, r);
      break;
    }
    case PanoramaType::kFisheyeLensPolynomial: {
      const float x = (u - 0.5f) * sensor_width;
      const float y = (v - 0.5f) * sensor_height;
      const float r = std::sqrt(x * x + y * y);
      const float theta =
          -(polynomial[0] +
            r * (polynomial[1] + r * (polynomial[2] + r * (polynomial[3] + r * polynomial[4]))));
      if (std::abs(theta) > 0.5f * fisheye_fov) return false;
      d = fisheye(theta, x, y, r);
      break;
    }
    case PanoramaType::kCentralCylindrical: {
      // Longitude grows to the right, as in the equirectangular map.
      const float phi = -(cylinder_u_min + u * (cylinder_u_max - cylinder_u_min));
      const float height = cylinder_v_min + v * (cylinder_v_max - cylinder_v_min);
      d = glm::normalize(Vec3(std::cos(phi), std::sin(phi), height));
      break;
    }
  }
  if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z)) return false;
  *local = to_camera(d);
  return true;
}

}  // namespace whitted
