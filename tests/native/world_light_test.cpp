// The world as a light (scene/world_light.h): its importance map's density against its
// samples, and what it gives a Lambertian floor against the integral it stands for.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "core/math.h"
#include "integrator/whitted.h"
#include "scene/world_light.h"
#include "scene_builders.h"
#include "shader/program.h"

namespace whitted {
namespace {

using testing::add_object;
using testing::quad;

constexpr uint32_t kU = Program::kUnused;

// A world of radiance max(d.z, 0) + `floor` by direction d: a sky brightest overhead,
// as its program would come from a graph (Texture Coordinate > Vector Math > Math).
std::shared_ptr<const Program> sky_of_z(float floor) {
  // r0 the direction, r1 +Z, r2 d.z, r3 0, r4 max(d.z, 0), r5 `floor`, r6 the sum.
  const uint32_t code[] = {static_cast<uint32_t>(Op::kInput),
                           kInputPosition,
                           0,
                           kU,
                           kU,
                           kU,
                           kU,
                           kU,
                           static_cast<uint32_t>(Op::kVectorMath),
                           static_cast<uint32_t>(VectorMathOp::kDotProduct),
                           2,
                           0,
                           1,
                           kU,
                           kU,
                           kU,
                           static_cast<uint32_t>(Op::kMath),
                           static_cast<uint32_t>(MathOp::kMaximum),
                           4,
                           2,
                           3,
                           kU,
                           kU,
                           kU,
                           static_cast<uint32_t>(Op::kMath),
                           static_cast<uint32_t>(MathOp::kAdd),
                           6,
                           4,
                           5,
                           kU,
                           kU,
                           kU};
  const float registers[] = {0, 0, 0, 0, 0, 0, 1,     0,     0,     0,     0, 0, 0, 0,
                             0, 0, 0, 0, 0, 0, floor, floor, floor, floor, 0, 0, 0, 0};
  return std::make_shared<const Program>(code, 4, registers, 7, std::vector<float>{},
                                         std::vector<std::string>{});
}

WorldLightParams lit(int width = 0, int height = 0) {
  WorldLightParams params;
  params.on = true;
  params.why = "test";
  params.width = width;
  params.height = height;
  return params;
}

// A white Lambertian floor under the world, nothing else.
Scene floor_under(const WorldLightParams& params, std::shared_ptr<const Program> world,
                  Color background = Color(0.0f)) {
  Scene scene;
  Material white;
  white.diffuse = Color(1.0f);
  white.ambient = 0.0f;
  add_object(&scene, "floor", quad(-1e4f, 1e4f, -1e4f, 1e4f, 0.0f), white);
  scene.set_background(background);
  if (world) scene.set_world(std::move(world), 6, 0.0f);
  scene.set_world_light(params);
  return scene;
}

// What the floor sends back towards a camera looking down at it, over `n` seeds.
double floor_radiance(const Scene& scene, int n, Settings settings = {}) {
  const auto compiled = scene.compile();
  const WhittedIntegrator integrator(*compiled, settings);
  RayCounts counts;
  const Ray ray{Vec3(0.3f, -2.0f, 3.0f),
                glm::normalize(Vec3(-0.3f, 2.0f, -3.0f)),
                0.0f,
                kInfinity,
                kCameraRay,
                0.0f};
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    NodeState state;
    state.seed = hash3(static_cast<uint32_t>(i), 11u, 0u);
    const Color c = integrator.trace(ray, state, &counts);
    EXPECT_TRUE(is_finite(c));
    sum += c.x;
  }
  return sum / n;
}

TEST(WorldLight, AWhiteWorldOverAWhiteFloorGivesBackTheWorld) {
  // The white furnace: a floor of albedo 1 under a uniform sky of radiance 0.7 sends
  // back 0.7, whatever the samples (a world of one colour is drawn by the cosine).
  const Scene scene = floor_under(lit(), nullptr, Color(0.7f));
  EXPECT_NEAR(floor_radiance(scene, 4), 0.7, 1e-5);
  EXPECT_FALSE(scene.compile()->world_light->has_map());
}

TEST(WorldLight, ABlackWorldOrAWorldSetNotToLightCostsNothing) {
  EXPECT_EQ(floor_under(lit(), nullptr, Color(0.0f)).compile()->world_light, nullptr);
  WorldLightParams off = lit(64, 32);
  off.on = false;
  EXPECT_EQ(floor_under(off, sky_of_z(0.0f)).compile()->world_light, nullptr);
  EXPECT_EQ(floor_radiance(floor_under(off, sky_of_z(0.0f)), 1), 0.0);
}

TEST(WorldLight, TheMapsDensityIntegratesToOneAndIsWhatItsSamplesFollow) {
  const auto compiled = floor_under(lit(64, 32), sky_of_z(0.05f)).compile();
  const WorldLight& light = *compiled->world_light;
  ASSERT_TRUE(light.has_map());
  const Vec3 n(0.0f, 0.0f, 1.0f);
  // The density over the sphere by a fine midpoint quadrature in (cos theta, phi).
  double total = 0.0;
  const int cells = 512;
  for (int j = 0; j < cells; ++j) {
    const double z = -1.0 + 2.0 * (j + 0.5) / cells;
    for (int i = 0; i < 2 * cells; ++i) {
      const double phi = M_PI * (i + 0.5) / cells;
      const double r = std::sqrt(1.0 - z * z);
      const Vec3 d(static_cast<float>(r * std::cos(phi)), static_cast<float>(r * std::sin(phi)),
                   static_cast<float>(z));
      total += light.pdf(d, n);
    }
  }
  total *= (2.0 / cells) * (M_PI / cells);
  EXPECT_NEAR(total, 1.0, 2e-3);
  // Samples' share above z = 0.5 against the density's integral there, and every
  // sample's density is the one pdf() gives.
  const int samples = 64 * 64;
  int above = 0;
  for (int k = 0; k < samples; ++k) {
    const glm::vec2 u((static_cast<float>(k % 64) + 0.5f) / 64.0f,
                      (static_cast<float>(k / 64) + 0.5f) / 64.0f);
    const WorldLight::Sample s = light.sample(u, n);
    EXPECT_NEAR(glm::length(s.wi), 1.0f, 1e-5f);
    EXPECT_FLOAT_EQ(s.pdf, light.pdf(s.wi, n));
    above += s.wi.z > 0.5f ? 1 : 0;
  }
  // Radiance z + 0.05 above the horizon, 0.05 below: the share of power above z = 0.5 is
  // (int_0.5^1 (z + 0.05) dz) / (int_0^1 (z + 0.05) dz + 0.05) = 0.4 / 0.6.
  EXPECT_NEAR(static_cast<double>(above) / samples, 0.4 / 0.6, 0.01);
}

TEST(WorldLight, ASkyBrightestOverheadLightsAnOpenFloorAsItsIntegralSays) {
  // Radiance max(z, 0) lights an upward floor with E = int z cos dw = 2 pi / 3, and a
  // white Lambertian floor sends back E / pi = 2/3: drawn from the map, within noise.
  Settings settings;
  settings.emitter_samples = 4;
  const Scene scene = floor_under(lit(128, 64), sky_of_z(0.0f));
  EXPECT_NEAR(floor_radiance(scene, 64, settings), 2.0 / 3.0, 0.01);
  // Drawn by the cosine (World > Settings > Sampling None), the same integral.
  const Scene cosine = floor_under(lit(), sky_of_z(0.0f));
  EXPECT_NEAR(floor_radiance(cosine, 64, settings), 2.0 / 3.0, 0.01);
}

TEST(WorldLight, AnEditElsewhereKeepsTheMapAndAWorldEditRebuildsIt) {
  Scene scene = floor_under(lit(64, 32), sky_of_z(0.0f));
  const auto first = scene.compile()->world_light;
  Material grey;
  grey.diffuse = Color(0.5f);
  scene.set_material("floor", grey);
  EXPECT_EQ(scene.compile()->world_light, first);
  scene.set_world(sky_of_z(0.1f), 6, 0.0f);
  EXPECT_NE(scene.compile()->world_light, first);
}

TEST(WorldLight, BadSettingsAreRefused) {
  Scene scene;
  WorldLightParams huge = lit(kMaxWorldMap * 2, 16);
  EXPECT_THROW(scene.set_world_light(huge), std::invalid_argument);
  WorldLightParams sun = lit();
  sun.sun_angle = 0.1f;
  sun.sun_direction = Vec3(0.0f);
  EXPECT_THROW(scene.set_world_light(sun), std::invalid_argument);
}

}  // namespace
}  // namespace whitted
