// The world as a light at infinite distance (Cook 1984's area light at infinity; image
// based lighting, Debevec 1998): where it lights a surface, each shading point sends
// feelers towards it, drawn by its radiance from an importance map, a piecewise-constant
// 2D distribution over directions (pbrt's ImageInfiniteLight; Cycles' background light).
//
// The map's texel (i, j) is the solid angle of azimuth phi in [2 pi i/W, 2 pi (i+1)/W)
// about +Z from +X and polar angle theta (from +Z, Blender's up) in [pi j/H, pi (j+1)/H);
// its weight is its mean radiance (the channels' mean, so that a blue sky is sampled as
// much as its blue asks) times its solid angle. A feeler picks a texel by weight, then a
// direction uniformly over the texel's solid angle: its density is the texel's
// probability over its solid angle, with no sin(theta) to divide by at the poles.
// A world of one colour needs no map: its feelers are drawn by the cosine about the
// normal, as a diffuse surface weighs them.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "core/math.h"
#include "core/ray.h"

namespace whitted {

struct CompiledScene;

// How the exporter asks for the world light (addon/export/world.py), the Cycles settings
// it reads in the comments.
struct WorldLightParams {
  bool on = false;  // the world lights surfaces (else `why` says why not, for the report)
  std::string why = "the world lights no surface (Scene.set_world_light)";
  // Importance map size, texels (World > Settings > Sampling: Auto or Manual's Map
  // Resolution); 0 x 0: no map (a world of one colour; Sampling None).
  int width = 0;
  int height = 0;
  // Ray Visibility: whether it lights diffuse lobes and shows in glossy ones.
  bool diffuse = true;
  bool glossy = true;
  int max_bounces = 1024;  // World > Settings > Light Paths > Max Bounces
  // A sky's sun disc (Sky Texture, sun disc on): its direction (unit, towards the sun)
  // and angular diameter (radians); 0: none. Sampled as its own part of the world, so a
  // tiny bright disc gives no fireflies (with a map only: Sampling None samples none).
  Vec3 sun_direction{0.0f, 0.0f, 1.0f};
  float sun_angle = 0.0f;
};

class WorldLight {
 public:
  // The world light of a compiled scene's world (its program, or its background colour),
  // as `params` ask; null when it is off or the world is black. The map is evaluated in
  // parallel rows, each texel at 2 x 2 points as a diffuse ray one bounce deep sees it,
  // a floor under every texel (a thousandth of the mean) so that no direction the
  // program lights has density 0.
  static std::shared_ptr<const WorldLight> build(const CompiledScene& scene,
                                                 const WorldLightParams& params);

  // How many directions each draw gives: one from the map (or the cosine), and with a
  // sun disc one more, uniformly over the disc's cone. Both are kept, each weighed by
  // the balance heuristic (Veach's multi-sample estimator, f / (p_map + p_sun)): no
  // draw chooses between them, so neither the shadowed ground (lit by the sky alone) nor
  // the sunlit one (by the disc) pays for the other's choice.
  int techniques() const { return params_.sun_angle > 0.0f && has_map() ? 2 : 1; }

  struct Sample {
    Vec3 wi;           // unit, towards the world
    float pdf = 0.0f;  // pdf(wi, n): the techniques' densities summed
  };
  // Technique `technique`'s direction of the two numbers u in [0, 1)^2 for a shading
  // point of normal n (a world of one colour is drawn by the cosine about n; a map's
  // density does not depend on it).
  Sample sample(const glm::vec2& u, const Vec3& n, int technique = 0) const;
  // The sum over the techniques of the density with which each draws direction wi at
  // normal n, per unit solid angle: what a draw's radiance is divided by.
  float pdf(const Vec3& wi, const Vec3& n) const;

  const WorldLightParams& params() const { return params_; }
  bool has_map() const { return width_ > 0; }
  size_t bytes() const;

 private:
  WorldLight() = default;
  int texel(const Vec3& wi) const;
  float map_pdf(const Vec3& wi) const;
  float sun_pdf(const Vec3& wi) const;
  // The sun technique's density inside the disc's cone: uniform over its solid angle.
  float sun_density() const { return 1.0f / (2.0f * kPi * (1.0f - sun_cos_)); }

  WorldLightParams params_;
  int width_ = 0;
  int height_ = 0;
  std::vector<float> rows_;     // H: the marginal CDF over rows, ending at 1
  std::vector<float> columns_;  // H x W: each row's conditional CDF, ending at 1
  std::vector<float> density_;  // H x W: each texel's probability over its solid angle
  float sun_cos_ = 1.0f;        // the cosine of the disc's angular radius
};

}  // namespace whitted
