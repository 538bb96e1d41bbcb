// Emissive meshes as lights (scene/mesh_light.h): the irradiance their feelers gather is
// the analytic one, each Emission Sampling side lights only its side, a glossy surface
// reflecting an emitter counts its light once (MIS), and the hard cases (a degenerate or
// dark emitter, a camera inside one) stay finite and reported. Threads and tiles change
// no pixel: glossy_test.cpp's ThePixelsDependOnNeitherThreadsNorTiles has a panel.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "integrator/analysis.h"
#include "integrator/whitted.h"
#include "scene/mesh_light.h"
#include "scene_builders.h"

namespace whitted {
namespace {

using testing::add_object;
using testing::emitter;
using testing::quad;

Material white_floor() {
  Material m;
  m.diffuse = Color(0.8f);
  m.ambient = 0.0f;
  return m;
}

// The radiance a Lambertian floor of albedo 0.8 sends back at the origin, traced from the
// side (under the panel), as the mean of `n` camera samples' seeds.
float floor_radiance(const Scene& scene, const Settings& settings, int n = 1,
                     const Vec3& origin = Vec3(0.0f, -3.0f, 0.3f), float time = 0.0f) {
  const auto compiled = scene.compile();
  const WhittedIntegrator integrator(*compiled, settings);
  RayCounts counts;
  const Ray ray{origin, glm::normalize(-origin), 0.0f, kInfinity, kCameraRay, time};
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    NodeState state;
    state.seed = hash3(static_cast<uint32_t>(i), 7u, 0u);
    const Color c = integrator.trace(ray, state, &counts);
    EXPECT_TRUE(is_finite(c));
    sum += c.x;
  }
  return static_cast<float>(sum / n);
}

// A square panel of half side s at height h over the floor's origin, its normal up.
Scene panel_scene(EmissionSampling sampling, float s = 0.5f, float h = 1.0f) {
  Scene scene;
  add_object(&scene, "floor", quad(-20, 20, -20, 20, 0), white_floor());
  add_object(&scene, "panel", quad(-s, s, -s, s, h), emitter(Color(2.0f), sampling));
  scene.set_background(Color(0.0f));
  return scene;
}

// The irradiance under the centre of a parallel square of radiance L, half side s, at
// height h: four corner rectangles' configuration factors, E = 4 pi L F with
// F = (1/2pi) [x/sqrt(1+x^2) atan(y/sqrt(1+x^2)) + y/sqrt(1+y^2) atan(x/sqrt(1+y^2))].
double square_irradiance(double L, double s, double h) {
  const double x = s / h;
  const double r = std::sqrt(1.0 + x * x);
  const double f = (1.0 / (2.0 * M_PI)) * 2.0 * (x / r) * std::atan(x / r);
  return 4.0 * M_PI * L * f;
}

TEST(MeshLight, APanelLightsTheFloorBelowItAsTheConfigurationFactorSays) {
  Settings settings;
  settings.emitter_samples = 16;
  const float expected = static_cast<float>(0.8 / M_PI * square_irradiance(2.0, 0.5, 1.0));
  const float got = floor_radiance(panel_scene(EmissionSampling::kBoth), settings);
  EXPECT_NEAR(got, expected, 0.01f * expected);
  // Its front faces up: only Back (and Both) light the floor beneath.
  EXPECT_NEAR(floor_radiance(panel_scene(EmissionSampling::kBack), settings), got, 1e-6f);
  EXPECT_EQ(floor_radiance(panel_scene(EmissionSampling::kFront), settings), 0.0f);
  EXPECT_EQ(floor_radiance(panel_scene(EmissionSampling::kNone), settings), 0.0f);
  // Few feelers are noisier, not biased: the mean over camera samples' strata agrees.
  settings.emitter_samples = 1;
  EXPECT_NEAR(floor_radiance(panel_scene(EmissionSampling::kBoth), settings, 256), expected,
              0.03f * expected);
}

// A panel moving within the shutter (motion blur) lights the floor from where the
// shading point's time puts it: its feelers aim at it there, as the rays that meet it do.
TEST(MeshLight, AMovingPanelLightsFromWhereTheTimePutsIt) {
  Settings settings;
  settings.emitter_samples = 8;
  const glm::mat4 away = glm::translate(glm::mat4(1.0f), Vec3(1.5f, 0.0f, 0.0f));
  const Vec3 eye(0.0f, -3.0f, 0.3f);
  // The panel placed at `to_world`, moving over the shutter by `motion` if given.
  const auto placed = [&](const glm::mat4& to_world, const std::vector<glm::mat4>& motion) {
    Scene scene = panel_scene(EmissionSampling::kBoth);
    Instance panel{"panel", to_world, {"panel"}};
    panel.motion = motion;
    scene.set_instance("panel", panel);
    return scene;
  };
  const Scene moving = placed(glm::mat4(1.0f), {glm::mat4(1.0f), away});
  for (const float time : {0.0f, 0.5f, 1.0f}) {
    const glm::mat4 there = glm::translate(glm::mat4(1.0f), Vec3(1.5f * time, 0.0f, 0.0f));
    const float still = floor_radiance(placed(there, {}), settings, 1, eye);
    EXPECT_NEAR(floor_radiance(moving, settings, 1, eye, time), still, 1e-4f * still) << time;
  }
  // A deforming panel likewise, its vertices moved instead of its transform.
  Scene deforming = panel_scene(EmissionSampling::kBoth);
  Mesh panel = quad(-0.5f, 0.5f, -0.5f, 0.5f, 1.0f);
  std::vector<float> shifted = panel.positions;
  for (size_t v = 0; v < panel.vertex_count(); ++v) shifted[3 * v] += 1.5f;
  panel.motion_positions = {panel.positions, shifted};
  deforming.set_mesh("panel", panel);
  const float far = floor_radiance(placed(away, {}), settings, 1, eye);
  EXPECT_NEAR(floor_radiance(deforming, settings, 1, eye, 1.0f), far, 1e-4f * far);
  EXPECT_LT(far, 0.5f * floor_radiance(placed(glm::mat4(1.0f), {}), settings, 1, eye));
}

TEST(MeshLight, AnOccluderCastsItsShadow) {
  Scene scene = panel_scene(EmissionSampling::kBoth);
  Material grey = white_floor();
  add_object(&scene, "blocker", quad(-2, 2, -2, 2, 0.5f), grey);
  Settings settings;
  settings.emitter_samples = 4;
  EXPECT_EQ(floor_radiance(scene, settings), 0.0f);
}

// Many small emitters sum to one large one of the same radiance: the power table picks
// among them in proportion, the strata cover them.
TEST(MeshLight, ManySmallEmittersSumToTheirUnion) {
  Scene tiles;
  add_object(&tiles, "floor", quad(-20, 20, -20, 20, 0), white_floor());
  const int n = 10;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const float x0 = -0.5f + static_cast<float>(i) / n;
      const float y0 = -0.5f + static_cast<float>(j) / n;
      const std::string name = "tile" + std::to_string(i * n + j);
      add_object(&tiles, name, quad(x0, x0 + 1.0f / n, y0, y0 + 1.0f / n, 1.0f),
                 emitter(Color(2.0f), EmissionSampling::kBoth));
    }
  }
  tiles.set_background(Color(0.0f));
  const auto compiled = tiles.compile();
  EXPECT_EQ(compiled->mesh_lights->objects(), static_cast<size_t>(n * n));
  EXPECT_EQ(compiled->mesh_lights->triangles().size(), static_cast<size_t>(2 * n * n));
  Settings settings;
  settings.emitter_samples = 8;
  const float expected = static_cast<float>(0.8 / M_PI * square_irradiance(2.0, 0.5, 1.0));
  EXPECT_NEAR(floor_radiance(tiles, settings, 16), expected, 0.01f * expected);
  bool named = false;
  for (const EffectDecision& d : analyse(*compiled, settings).decisions) {
    if (d.name != "emissive meshes as lights") continue;
    named = true;
    EXPECT_TRUE(d.on);
    EXPECT_EQ(d.why, "100 objects, 200 triangles");
  }
  EXPECT_TRUE(named);
}

// A glossy floor reflecting a panel: the feelers and the glossy rays both reach the
// panel, and MIS counts its light once. The same floor lit by the rays alone (the panel's
// Emission Sampling off) converges to the same value.
TEST(MeshLight, AGlossyReflectionOfAnEmitterCountsItOnce) {
  for (const float roughness : {0.15f, 0.4f}) {
    const auto scene_with = [&](EmissionSampling sampling) {
      Scene scene;
      Material metal;
      metal.diffuse = Color(0.0f);
      metal.ambient = 0.0f;
      metal.reflectivity = Color(0.9f);
      metal.roughness = roughness;
      add_object(&scene, "floor", quad(-20, 20, -20, 20, 0), metal);
      add_object(&scene, "panel", quad(-0.6f, 0.6f, 0.1f, 1.3f, 1.0f),
                 emitter(Color(2.0f), sampling));
      scene.set_background(Color(0.0f));
      return scene;
    };
    Settings settings;
    settings.cutoff = 0.0f;
    settings.glossy_samples = 4;
    settings.emitter_samples = 4;
    // Seen at 45 degrees from beside the panel: the view's mirror meets it.
    const Vec3 origin(0.0f, -0.8f, 0.8f);
    const float both = floor_radiance(scene_with(EmissionSampling::kBoth), settings, 64, origin);
    settings.glossy_samples = 16;
    const float rays = floor_radiance(scene_with(EmissionSampling::kNone), settings, 64, origin);
    EXPECT_GT(rays, 0.05f) << roughness;
    EXPECT_NEAR(both, rays, 0.03f * rays) << "roughness " << roughness;
  }
}

// The hard cases: an emitter of zero area or zero strength lights nothing and says so;
// a camera inside a closed emitter sees its radiance, and a white floor in it returns
// kd L (a whole hemisphere of radiance L).
TEST(MeshLight, DegenerateAndDarkEmittersLightNothing) {
  for (const bool zero_area : {true, false}) {
    Scene scene;
    add_object(&scene, "floor", quad(-20, 20, -20, 20, 0), white_floor());
    const Mesh mesh = zero_area ? quad(-0.5f, 0.5f, 0.0f, 0.0f, 1.0f) : quad(-1, 1, -1, 1, 1);
    add_object(&scene, "panel", mesh,
               emitter(Color(zero_area ? 2.0f : 0.0f), EmissionSampling::kBoth));
    scene.set_background(Color(0.0f));
    const auto compiled = scene.compile();
    EXPECT_TRUE(compiled->mesh_lights->empty());
    const Effects effects = analyse(*compiled, Settings{});
    EXPECT_FALSE(effects.has(kEmitterEffect));
    for (const EffectDecision& d : effects.decisions) {
      if (d.name == "emissive meshes as lights") {
        EXPECT_EQ(d.why, "no mesh emits with its Emission Sampling on");
      }
    }
    EXPECT_EQ(floor_radiance(scene, Settings{}), 0.0f);
  }
}

TEST(MeshLight, ACameraInsideAClosedEmitterSeesItAndLightsTheFloor) {
  Scene scene;
  add_object(&scene, "floor", quad(-1, 1, -1, 1, 0), white_floor());
  const float L = 1.5f;
  const Material glow = emitter(Color(L), EmissionSampling::kBoth);
  // The ceiling and four walls of a 2 x 2 x 2 box on the floor.
  add_object(&scene, "ceiling", quad(-1, 1, -1, 1, 2), glow);
  for (int k = 0; k < 4; ++k) {
    const glm::mat4 wall =
        glm::rotate(glm::mat4(1.0f), static_cast<float>(k) * 0.5f * kPi, Vec3(0, 0, 1)) *
        glm::translate(glm::mat4(1.0f), Vec3(1.0f, 0.0f, 1.0f)) *
        glm::rotate(glm::mat4(1.0f), 0.5f * kPi, Vec3(0, 1, 0));
    add_object(&scene, "wall" + std::to_string(k), quad(-1, 1, -1, 1, 0), glow, wall);
  }
  scene.set_background(Color(0.0f));
  Settings settings;
  settings.emitter_samples = 8;
  const auto compiled = scene.compile();
  const WhittedIntegrator integrator(*compiled, settings);
  RayCounts counts;
  const Vec3 eye(0.2f, -0.3f, 1.0f);
  const Color seen =
      integrator.trace(Ray{eye, Vec3(0, 0, 1), 0.0f, kInfinity, kCameraRay}, NodeState{}, &counts);
  EXPECT_FLOAT_EQ(seen.x, L);
  const float floor = floor_radiance(scene, settings, 16, eye);
  EXPECT_NEAR(floor, 0.8f * L, 0.02f * 0.8f * L);
}

}  // namespace
}  // namespace whitted
