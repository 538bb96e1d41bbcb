#include "scene/world_light.h"

#include <algorithm>
#include <cmath>
#include <thread>

#include "core/math.h"
#include "scene/microfacet.h"
#include "scene/scene.h"

namespace whitted {

namespace {

constexpr float kTwoPi = 2.0f * kPi;
constexpr double kTwoPiD = 2.0 * 3.14159265358979323846;
constexpr double kPiD = 3.14159265358979323846;

// The floor under every texel's weight, relative to the mean texel's radiance: small
// enough to cost no visible noise, large enough that no lit direction is never drawn.
constexpr double kFloor = 1e-3;

float channel_mean(const Color& c) {
  return (c.r + c.g + c.b) / 3.0f;
}

// A direction of polar angle acos(cos_theta) from +Z and azimuth phi from +X.
Vec3 direction(double cos_theta, double phi) {
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  return {static_cast<float>(sin_theta * std::cos(phi)),
          static_cast<float>(sin_theta * std::sin(phi)), static_cast<float>(cos_theta)};
}

// The cosines of the polar angles bounding row j of a map h rows high.
double row_cos(int j, int h) {
  return std::cos(kPiD * j / h);
}

// The solid angle of each texel of row j of a w x h map.
double texel_solid_angle(int j, int w, int h) {
  return (kTwoPiD / w) * (row_cos(j, h) - row_cos(j + 1, h));
}

// The index of the first entry of the ascending cdf[0..n) above u (the last if none).
int find(const float* cdf, int n, float u) {
  const float* found = std::upper_bound(cdf, cdf + n, u);
  return std::min(static_cast<int>(found - cdf), n - 1);
}

// Draws (u, v) by the cosine about n: density cos(theta)/pi.
Vec3 cosine_direction(const glm::vec2& u, const Vec3& n) {
  float r = 0.0f;
  float phi = 0.0f;
  concentric_disc(2.0f * u.x - 1.0f, 2.0f * u.y - 1.0f, &r, &phi);
  const float x = r * std::cos(phi);
  const float y = r * std::sin(phi);
  const float z = std::sqrt(std::max(0.0f, 1.0f - x * x - y * y));
  return Frame(n).to_world(Vec3(x, y, z));
}

}  // namespace

std::shared_ptr<const WorldLight> WorldLight::build(const CompiledScene& scene,
                                                    const WorldLightParams& params) {
  if (!params.on) return nullptr;
  if (!scene.world && max_component(scene.background) <= 0.0f) return nullptr;
  std::shared_ptr<WorldLight> light(new WorldLight());
  light->params_ = params;
  if (!scene.world || params.width <= 0 || params.height <= 0) return light;
  const int w = params.width;
  const int h = params.height;
  // Each texel's mean radiance over 2 x 2 points spread evenly in azimuth and in cos(theta)
  // (equal solid angles), rows in parallel: each texel is its own, so the map does not
  // depend on how rows fall to threads.
  // A sun disc sampled apart is left out of the map: the map would blur it over its
  // texels, and its draws, landing on the disc or beside it, would add the variance the
  // disc's own draws avoid. The texels about the disc take the most of 8 x 8 points
  // outside it instead: the sky just beside a low sun (its aureole) is thousands of times
  // brighter than elsewhere, and a texel the disc mostly covers must still be drawn as
  // often as the bright sliver beside it asks (else a feeler finding the sliver brings
  // it over a tiny density: a firefly).
  const bool sun = params.sun_angle > 0.0f;
  const double sun_cos = sun ? std::cos(0.5 * params.sun_angle) : 2.0;
  // Within the disc's radius and two texels' diagonal of it: the texels about the disc.
  const double near_cos =
      std::cos(std::min(kPiD, 0.5 * params.sun_angle + 2.0 * kTwoPiD / std::min(w, 2 * h)));
  const Vec3 sun_direction = params.sun_direction;
  std::vector<double> weight(static_cast<size_t>(w) * h);
  // A texel's n x n points: at cos(theta) cos0 + (cos1 - cos0) b and azimuth 2 pi (i + a) / w,
  // a and b ((k + 0.5) / n for k < n). The 2 x 2 points' azimuths are shared by every row and
  // their polar angles by every column: their cosines and sines are taken once, the same
  // numbers direction() would give each point.
  const auto offset = [](int k, int n) { return (k + 0.5) / n; };
  std::vector<glm::dvec2> azimuths(2 * static_cast<size_t>(w));  // (cos phi, sin phi)
  for (int i = 0; i < w; ++i) {
    for (int k = 0; k < 2; ++k) {
      const double phi = kTwoPiD * (i + offset(k, 2)) / w;
      azimuths[2 * static_cast<size_t>(i) + k] = {std::cos(phi), std::sin(phi)};
    }
  }
  // A point's radiance, 0 on the disc and where the program gives no light.
  const auto seen = [&](const Vec3& d) {
    if (glm::dot(d, sun_direction) >= sun_cos) return 0.0;
    const float value = channel_mean(scene.world_light_radiance(d, 1));
    return std::isfinite(value) && value > 0.0f ? static_cast<double>(value) : 0.0;
  };
  // The most of a texel's 8 x 8 points, for the texels about the disc.
  const auto near_sun = [&](int i, double cos0, double cos1) {
    double most = 0.0;
    for (int s = 0; s < 64; ++s) {
      most = std::max(most, seen(direction(cos0 + (cos1 - cos0) * offset(s / 8, 8),
                                           kTwoPiD * (i + offset(s % 8, 8)) / w)));
    }
    return most;
  };
  const auto rows = [&](int first, int step) {
    for (int j = first; j < h; j += step) {
      const double cos0 = row_cos(j, h);
      const double cos1 = row_cos(j + 1, h);
      const double solid_angle = texel_solid_angle(j, w, h);
      double z[2];
      double sin_theta[2];
      for (int k = 0; k < 2; ++k) {
        z[k] = cos0 + (cos1 - cos0) * offset(k, 2);
        sin_theta[k] = std::sqrt(std::max(0.0, 1.0 - z[k] * z[k]));
      }
      for (int i = 0; i < w; ++i) {
        double value = 0.0;
        if (sun && glm::dot(direction(0.5 * (cos0 + cos1), kTwoPiD * (i + 0.5) / w),
                            sun_direction) >= near_cos) {
          value = near_sun(i, cos0, cos1);
        } else {
          double sum = 0.0;
          for (int s = 0; s < 4; ++s) {
            const glm::dvec2& azimuth = azimuths[2 * static_cast<size_t>(i) + s % 2];
            const double st = sin_theta[s / 2];
            sum += seen(Vec3(static_cast<float>(st * azimuth.x), static_cast<float>(st * azimuth.y),
                             static_cast<float>(z[s / 2])));
          }
          value = sum / 4;
        }
        weight[static_cast<size_t>(j) * w + i] = value * solid_angle;
      }
    }
  };
  const int threads = static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 16u));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(rows, t, threads);
  rows(0, threads);
  for (std::thread& t : pool) t.join();

  double total = 0.0;
  for (const double x : weight) total += x;
  if (!(total > 0.0)) return nullptr;  // a black world lights nothing
  // The floor: kFloor of the mean radiance, over each texel's solid angle.
  const double floor = kFloor * total / (4.0 * kPiD);
  light->width_ = w;
  light->height_ = h;
  light->rows_.resize(static_cast<size_t>(h));
  light->columns_.resize(static_cast<size_t>(w) * h);
  light->density_.resize(static_cast<size_t>(w) * h);
  std::vector<double> row_sum(static_cast<size_t>(h));
  double all = 0.0;
  for (int j = 0; j < h; ++j) {
    const double solid_angle = texel_solid_angle(j, w, h);
    double sum = 0.0;
    for (int i = 0; i < w; ++i) {
      double& x = weight[static_cast<size_t>(j) * w + i];
      x += floor * solid_angle;
      sum += x;
    }
    double running = 0.0;
    for (int i = 0; i < w; ++i) {
      running += weight[static_cast<size_t>(j) * w + i];
      light->columns_[static_cast<size_t>(j) * w + i] = static_cast<float>(running / sum);
    }
    light->columns_[static_cast<size_t>(j) * w + w - 1] = 1.0f;
    row_sum[static_cast<size_t>(j)] = sum;
    all += sum;
  }
  double running = 0.0;
  for (int j = 0; j < h; ++j) {
    running += row_sum[static_cast<size_t>(j)];
    light->rows_[static_cast<size_t>(j)] = static_cast<float>(running / all);
    const double solid_angle = texel_solid_angle(j, w, h);
    for (int i = 0; i < w; ++i) {
      light->density_[static_cast<size_t>(j) * w + i] =
          static_cast<float>(weight[static_cast<size_t>(j) * w + i] / (all * solid_angle));
    }
  }
  light->rows_.back() = 1.0f;
  if (sun) light->sun_cos_ = static_cast<float>(sun_cos);
  return light;
}

int WorldLight::texel(const Vec3& wi) const {
  float phi = std::atan2(wi.y, wi.x);
  if (phi < 0.0f) phi += kTwoPi;
  const int i =
      std::clamp(static_cast<int>(phi / kTwoPi * static_cast<float>(width_)), 0, width_ - 1);
  const int j = std::clamp(static_cast<int>(std::acos(std::clamp(wi.z, -1.0f, 1.0f)) / kPi *
                                            static_cast<float>(height_)),
                           0, height_ - 1);
  return j * width_ + i;
}

float WorldLight::map_pdf(const Vec3& wi) const {
  return density_[static_cast<size_t>(texel(wi))];
}

float WorldLight::sun_pdf(const Vec3& wi) const {
  return glm::dot(wi, params_.sun_direction) < sun_cos_ ? 0.0f : sun_density();
}

WorldLight::Sample WorldLight::sample(const glm::vec2& u, const Vec3& n, int technique) const {
  Sample out;
  if (!has_map()) {
    out.wi = cosine_direction(u, n);
    out.pdf = pdf(out.wi, n);
    return out;
  }
  if (technique == 1) {
    // Uniformly over the sun disc's cone.
    const float c = 1.0f - (1.0f - sun_cos_) * u.x;
    out.wi = Frame(params_.sun_direction).to_world(direction(c, kTwoPiD * u.y));
    // Drawn in the cone: its own density whatever the rounding of wi says (a direction
    // on the cone's edge may test outside it, and over the map's density alone, which
    // leaves the disc out, bring the disc as a firefly).
    out.pdf = map_pdf(out.wi) + sun_density();
    return out;
  }
  const glm::vec2 v = u;
  // A row by the marginal CDF, a column by the row's conditional one, each number
  // rescaled within the chosen entry to place the direction inside the texel.
  const int j = find(rows_.data(), height_, v.y);
  const float row_low = j > 0 ? rows_[static_cast<size_t>(j) - 1] : 0.0f;
  const float row_t = std::clamp(
      (v.y - row_low) / std::max(rows_[static_cast<size_t>(j)] - row_low, 1e-30f), 0.0f, 1.0f);
  const float* row = columns_.data() + static_cast<size_t>(j) * width_;
  const int i = find(row, width_, v.x);
  const float column_low = i > 0 ? row[i - 1] : 0.0f;
  const float column_t =
      std::clamp((v.x - column_low) / std::max(row[i] - column_low, 1e-30f), 0.0f, 1.0f);
  const double cos0 = row_cos(j, height_);
  const double cos1 = row_cos(j + 1, height_);
  out.wi = direction(cos0 + (cos1 - cos0) * row_t, kTwoPiD * (i + column_t) / width_);
  // Rounding may carry a direction on a texel's edge into its neighbour: the density
  // is the one pdf() gives, so both techniques of MIS agree.
  out.pdf = pdf(out.wi, n);
  return out;
}

float WorldLight::pdf(const Vec3& wi, const Vec3& n) const {
  if (!has_map()) return std::max(0.0f, glm::dot(wi, n)) * kInvPi;
  const float map = map_pdf(wi);
  return techniques() == 2 ? map + sun_pdf(wi) : map;
}

size_t WorldLight::bytes() const {
  return sizeof(WorldLight) + sizeof(float) * (rows_.size() + columns_.size() + density_.size());
}

}  // namespace whitted
