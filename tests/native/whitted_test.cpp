// The integrator against analytic expectations: Lambertian shading under a point light,
// mirror reflection, refraction through a slab, shadows, depth limits.
#include "integrator/whitted.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "integrator/lobes.h"
#include "scene_builders.h"

namespace whitted {
namespace {

using testing::add_object;
using testing::clear;
using testing::emitter;
using testing::looking_down;
using testing::occluder_over_floor;
using testing::quad;

// Every pixel of a Lambertian plane under a point light is kd/pi * I cos(theta) / r^2.
// Any shadow acne would darken some pixel and fail this.
TEST(Whitted, LambertianPlaneUnderPointLightMatchesInverseSquareCosineLaw) {
  Scene scene;
  Material white;
  white.diffuse = Color(0.7f);
  white.ambient = 0.0f;
  add_object(&scene, "floor", quad(-20, 20, -20, 20, 0), white);
  Light light;
  light.type = LightType::kPoint;
  light.color = Color(80.0f);  // radiant intensity, W/sr
  light.position = Vec3(1.5f, -0.5f, 3.0f);
  scene.set_light("light", light);
  scene.camera = looking_down(Vec3(0.0f, 0.0f, 6.0f), 1.5f);
  scene.set_background(Color(0.0f));
  const auto compiled = scene.compile();
  Settings settings;
  const WhittedIntegrator integrator(*compiled, settings);
  RayCounts counts;
  const int n = 96;
  int checked = 0;
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const Ray ray = scene.camera.generate_ray((x + 0.5f) / n, (y + 0.5f) / n);
      const Color c = integrator.trace(ray, NodeState{}, &counts);
      // Where the camera ray meets z = 0, in double precision.
      const double t = -double(ray.origin.z) / ray.direction.z;
      const double px = ray.origin.x + t * ray.direction.x;
      const double py = ray.origin.y + t * ray.direction.y;
      const double dx = light.position.x - px, dy = light.position.y - py, dz = light.position.z;
      const double r2 = dx * dx + dy * dy + dz * dz;
      const double expected = 0.7 / M_PI * 80.0 * (dz / std::sqrt(r2)) / r2;
      ASSERT_NEAR(c.x, expected, 1e-3 * expected) << "pixel " << x << "," << y;
      ++checked;
    }
  }
  EXPECT_EQ(checked, n * n);
  EXPECT_EQ(counts.shadow, static_cast<uint64_t>(n * n));
  EXPECT_EQ(counts.reflection + counts.refraction, 0u);
}

// A lamp's ray visibility (Cycles' Diffuse and Glossy): with Diffuse off it lights no
// diffuse term, with Glossy off it leaves no highlight and the diffuse term as it was.
TEST(Whitted, ALampsRayVisibilityHidesItsDiffuseOrSpecularTerms) {
  const auto centre = [](bool diffuse, bool glossy, float specular) {
    Scene scene;
    Material shiny;
    shiny.diffuse = Color(0.5f);
    shiny.specular = Color(specular);
    shiny.ambient = 0.0f;
    add_object(&scene, "floor", quad(-20, 20, -20, 20, 0), shiny);
    Light light;
    light.color = Color(50.0f);
    light.position = Vec3(0.0f, 0.0f, 3.0f);
    light.diffuse = diffuse;
    light.glossy = glossy;
    scene.set_light("light", light);
    scene.camera = looking_down(Vec3(0.0f, 0.0f, 6.0f), 0.1f);
    const auto compiled = scene.compile();
    const WhittedIntegrator integrator(*compiled, Settings{});
    RayCounts counts;
    return integrator.trace(scene.camera.generate_ray(0.5f, 0.5f), NodeState{}, &counts).x;
  };
  const float diffuse_only = centre(true, true, 0.0f);
  EXPECT_NEAR(diffuse_only, 0.5f / kPi * 50.0f / 9.0f, 1e-4f);
  EXPECT_GT(centre(true, true, 0.5f), 1.5f * diffuse_only);  // the highlight under the lamp
  EXPECT_EQ(centre(true, false, 0.5f), diffuse_only);        // Glossy off: no highlight
  EXPECT_EQ(centre(false, true, 0.0f), 0.0f);                // Diffuse off: no diffuse light
  EXPECT_GT(centre(false, true, 0.5f), 0.0f);                // ... but the highlight stays
}

// A lamp's Max Bounces: at 0 it lights what camera rays meet, not what a mirror shows
// (the floor seen in it is one bounce away).
TEST(Whitted, ALampsMaxBouncesLimitsTheBouncesItLights) {
  const auto seen = [](int max_bounces, const Vec3& towards) {
    Scene scene;
    Material white;
    white.ambient = 0.0f;
    add_object(&scene, "floor", quad(-20, 20, -20, 20, 0), white);
    Material mirror;
    mirror.diffuse = Color(0.0f);
    mirror.ambient = 0.0f;
    mirror.reflectivity = Color(1.0f);
    // Upright in the plane x = 2, facing -x.
    const float corners[] = {2, -2, 0, 2, -2, 3, 2, 2, 3, 2, 2, 0};
    const uint32_t triangles[] = {0, 1, 2, 0, 2, 3};
    add_object(&scene, "mirror", make_mesh(corners, 4, triangles, 2, nullptr, nullptr), mirror);
    Light light;
    light.color = Color(20.0f);
    light.position = Vec3(0.0f, 0.0f, 3.0f);
    light.max_bounces = max_bounces;
    scene.set_light("light", light);
    const auto compiled = scene.compile();
    const WhittedIntegrator integrator(*compiled, Settings{});
    RayCounts counts;
    const Vec3 from(0.0f, 0.0f, 1.0f);
    const Ray ray{from, glm::normalize(towards - from), 0.0f, kInfinity, kCameraRay};
    return integrator.trace(ray, NodeState{}, &counts).x;
  };
  const Vec3 floor(0.0f, 0.0f, 0.0f);
  const Vec3 mirror(2.0f, 0.0f, 0.5f);  // reflects to the floor under the lamp
  const float lit = 0.8f / kPi * 20.0f / 9.0f;
  EXPECT_NEAR(seen(0, floor), lit, 1e-4f);
  EXPECT_EQ(seen(0, mirror), 0.0f);
  EXPECT_NEAR(seen(1, mirror), lit, 1e-3f);
  EXPECT_NEAR(seen(1024, mirror), lit, 1e-3f);
}

// A mirror floor under an area lamp facing it: the reflected ray meets the lamp's
// rectangle and brings its radiance, unless the lamp's visibility hides it from
// reflected rays. A glossy floor gets the same highlight from feelers and glossy rays
// combined (MIS) as from its feelers alone.
TEST(Whitted, AMirrorShowsAnAreaLampAndAGlossyFloorCountsItOnce) {
  const auto seen = [](float roughness, uint32_t visibility, const Vec3& at) {
    Scene scene;
    Material floor;
    floor.diffuse = Color(0.0f);
    floor.ambient = 0.0f;
    floor.reflectivity = Color(1.0f);
    floor.roughness = roughness;
    add_object(&scene, "floor", quad(-20, 20, -20, 20, 0), floor);
    Light lamp;
    lamp.type = LightType::kArea;
    lamp.color = Color(3.0f);
    lamp.position = Vec3(0.0f, 0.0f, 2.0f);
    lamp.direction = Vec3(0.0f, 0.0f, -1.0f);
    lamp.size[0] = 1.0f;
    lamp.size[1] = 0.5f;
    lamp.samples = 8;
    lamp.visibility = visibility;
    scene.set_light("lamp", Light(lamp));
    const auto compiled = scene.compile();
    Settings settings;
    settings.glossy_samples = 16;
    const WhittedIntegrator integrator(*compiled, settings);
    RayCounts counts;
    const Vec3 from(0.0f, -1.0f, 1.0f);
    const Ray ray{from, glm::normalize(at - from), 0.0f, kInfinity, kCameraRay};
    return integrator.trace(ray, NodeState{}, &counts).x;
  };
  const uint32_t all = kReflectionRay | kRefractionRay;
  // Seen from (0, -1, 1), the floor point (0, -2/3, 0) reflects the view to the lamp's
  // centre (0, 0, 2); the point (0, -1/2, 0) to (0, 1/2, 2), past its edge (y = 1/4).
  // Without the lamp in it, the mirror shows the background.
  const Vec3 centre(0.0f, -2.0f / 3.0f, 0.0f);
  const float background = seen(0.0f, kRefractionRay, centre);
  EXPECT_NEAR(seen(0.0f, all, centre), background + 3.0f, 1e-4f);
  EXPECT_EQ(seen(0.0f, all, Vec3(0.0f, -0.5f, 0.0f)), background);
  for (const float roughness : {0.2f, 0.4f}) {
    const float both = seen(roughness, all, centre);
    const float feelers = seen(roughness, 0u, centre);
    EXPECT_GT(feelers, 0.1f);
    EXPECT_NEAR(both, feelers, 0.05f * feelers) << "roughness " << roughness;
  }
}

TEST(Whitted, OccluderCastsAHardShadowOfTheRightSize) {
  const Scene scene = occluder_over_floor(1.0f);
  const auto compiled = scene.compile();
  const WhittedIntegrator integrator(*compiled, Settings{});
  RayCounts counts;
  // From height 2 a 1x1 blocker at height 1 shadows the square |x|,|y| < 1 on the floor.
  const auto floor_radiance = [&](float x, float y) {
    Ray ray{Vec3(x, y, 0.5f), Vec3(0.0f, 0.0f, -1.0f), 0.0f, kInfinity};
    return integrator.trace(ray, NodeState{}, &counts).x;
  };
  EXPECT_EQ(floor_radiance(0.0f, 0.0f), 0.0f);
  EXPECT_EQ(floor_radiance(0.95f, 0.0f), 0.0f);
  EXPECT_GT(floor_radiance(1.05f, 0.0f), 0.0f);
  EXPECT_GT(floor_radiance(0.0f, -1.05f), 0.0f);
}

// A camera ray bounced off a mirror sees what geometry says it should: the marker at the
// reflected position, the background just beside it.
TEST(Whitted, MirrorShowsTheReflectedObjectWhereGeometrySays) {
  Scene scene;
  Material mirror;
  mirror.diffuse = Color(0.0f);
  mirror.ambient = 0.0f;
  mirror.reflectivity = Color(0.9f);
  add_object(&scene, "mirror", quad(-10, 10, -10, 10, 0), mirror);
  // Marker 0.2 wide around x = 4 at height 1 (the ray from (0,0,1) towards (2,0,0)
  // reflects there).
  add_object(&scene, "marker", quad(3.9f, 4.1f, -0.1f, 0.1f, 1.0f), emitter(Color(2.0f)));
  scene.set_background(Color(0.25f));
  const auto compiled = scene.compile();
  const WhittedIntegrator integrator(*compiled, Settings{});
  RayCounts counts;
  const auto look = [&](float x_target) {
    const Vec3 origin(0.0f, 0.0f, 1.0f);
    Ray ray{origin, glm::normalize(Vec3(x_target, 0.0f, 0.0f) - origin), 0.0f, kInfinity};
    return integrator.trace(ray, NodeState{}, &counts).x;
  };
  EXPECT_NEAR(look(2.0f), 0.9f * 2.0f, 1e-5f);   // marker, times reflectivity
  EXPECT_NEAR(look(1.9f), 0.9f * 0.25f, 1e-5f);  // background beside it
  EXPECT_NEAR(look(2.1f), 0.9f * 0.25f, 1e-5f);
  EXPECT_EQ(counts.reflection, 3u);
}

// A ray through a glass slab of thickness d leaves parallel to itself, shifted sideways
// by d sin(theta_i - theta_t) / cos(theta_t) (the textbook lateral displacement).
TEST(Whitted, GlassSlabDisplacesARayByTheTextbookAmount) {
  Scene scene;
  const Material glass = clear(1.5f);
  // Slab between z = -1 and z = 0: top faces +z, bottom faces -z (outward normals).
  add_object(&scene, "slab_top", quad(-50, 50, -50, 50, 0.0f), glass);
  Mesh bottom = quad(-50, 50, -50, 50, -1.0f);
  std::swap(bottom.triangles[1], bottom.triangles[2]);
  std::swap(bottom.triangles[4], bottom.triangles[5]);
  scene.set_mesh("slab_bottom", std::move(bottom));
  scene.set_instance("slab_bottom", Instance{"slab_bottom", glm::mat4(1.0f), {"slab_top"}});
  // A floor at z = -2, bright for x > 0 and black for x < 0.
  add_object(&scene, "bright", quad(0.0f, 50, -50, 50, -2.0f), emitter(Color(1.0f)));
  scene.set_background(Color(0.0f));
  const auto compiled = scene.compile();
  Settings settings;
  settings.fresnel = Fresnel::kOff;
  const WhittedIntegrator integrator(*compiled, settings);
  RayCounts counts;
  for (float theta : {0.2f, 0.5f, 0.9f}) {
    const Vec3 dir(std::sin(theta), 0.0f, -std::cos(theta));
    // Find the origin x at which the ray's landing point crosses the floor's edge.
    float lo = -20.0f;
    float hi = 20.0f;
    for (int i = 0; i < 60; ++i) {
      const float mid = 0.5f * (lo + hi);
      Ray ray{Vec3(mid, 0.0f, 5.0f), dir, 0.0f, kInfinity};
      (integrator.trace(ray, NodeState{}, &counts).x > 0.5f ? hi : lo) = mid;
    }
    const double theta_t = std::asin(std::sin(theta) / 1.5);
    const double lateral = std::sin(theta - theta_t) / std::cos(theta_t);  // d = 1
    // Without the slab the edge is met from x0 = -7 tan(theta); the slab shifts the ray
    // back by `lateral` perpendicular to it, i.e. lateral / cos(theta) along x.
    const double expected = -7.0 * std::tan(theta) + lateral / std::cos(theta);
    EXPECT_NEAR(lo, expected, 1e-4) << "theta " << theta;
  }
  EXPECT_GT(counts.refraction, 0u);
  EXPECT_EQ(counts.total_internal_reflections, 0u);
}

// Two parallel mirrors one unit apart that glow with radiance 1 and reflect half: a ray
// between them sees the geometric series 1 + 1/2 + 1/4 + ...
Scene facing_mirrors() {
  Scene scene;
  Material mirror;
  mirror.diffuse = Color(0.0f);
  mirror.ambient = 0.0f;
  mirror.emission = Color(1.0f);
  mirror.reflectivity = Color(0.5f);
  add_object(&scene, "a", quad(-10, 10, -10, 10, 0.0f), mirror);
  add_object(&scene, "b", quad(-10, 10, -10, 10, 1.0f), mirror);
  return scene;
}

TEST(Whitted, FacingMirrorsTerminateAtTheMaximumDepthAndLoseEnergy) {
  const auto compiled = facing_mirrors().compile();
  for (int depth : {0, 1, 5, 256}) {
    Settings settings;
    settings.max_depth = depth;
    settings.cutoff = 0.0f;  // only the depth limit stops the recursion
    const WhittedIntegrator integrator(*compiled, settings);
    RayCounts counts;
    Ray ray{Vec3(0.0f, 0.0f, 0.5f), Vec3(0.0f, 0.0f, -1.0f), 0.0f, kInfinity};
    const float c = integrator.trace(ray, NodeState{}, &counts).x;
    // A geometric series: sum_{k=0..depth} 0.5^k.
    EXPECT_NEAR(c, 2.0f * (1.0f - std::pow(0.5f, depth + 1)), 1e-5f) << depth;
    EXPECT_EQ(counts.reflection, static_cast<uint64_t>(depth));
    // At depth 0 the analysis leaves reflection out altogether: nothing is even cut.
    EXPECT_EQ(counts.depth_limited, depth == 0 ? 0u : 1u);
  }
}

// Adaptive depth control: a branch stops once its weight on the pixel falls below the
// cutoff, and what it leaves out is bounded by that weight times what it would have seen.
TEST(Whitted, CutoffStopsTheRayTreeWhenItsContributionCannotShow) {
  const auto compiled = facing_mirrors().compile();
  uint64_t previous_rays = 0;
  for (float cutoff : {0.1f, 1.0f / 255.0f, 1e-4f, 0.0f}) {
    Settings settings;
    settings.max_depth = 256;
    settings.cutoff = cutoff;
    const WhittedIntegrator integrator(*compiled, settings);
    RayCounts counts;
    Ray ray{Vec3(0.0f, 0.0f, 0.5f), Vec3(0.0f, 0.0f, -1.0f), 0.0f, kInfinity};
    const float c = integrator.trace(ray, NodeState{}, &counts).x;
    // Bounce k has weight 0.5^k: traced while 0.5^k >= cutoff.
    const int traced = cutoff > 0.0f ? static_cast<int>(std::floor(-std::log2(cutoff))) : 256;
    EXPECT_EQ(counts.reflection, static_cast<uint64_t>(traced)) << cutoff;
    EXPECT_EQ(counts.cutoff_skipped + counts.depth_limited, 1u) << cutoff;
    // The untraced tail sum_{k>traced} 0.5^k is below twice the cutoff.
    EXPECT_NEAR(c, 2.0f, std::max(2.0f * cutoff, 1e-5f)) << cutoff;
    // A lower cutoff never traces fewer rays.
    EXPECT_GE(counts.total(), previous_rays) << cutoff;
    previous_rays = counts.total();
  }
}

TEST(Whitted, SpotLightSendsNothingOutsideItsCone) {
  Scene scene;
  Material white;
  white.ambient = 0.0f;
  add_object(&scene, "floor", quad(-20, 20, -20, 20, 0), white);
  Light spot;
  spot.type = LightType::kSpot;
  spot.color = Color(10.0f);
  spot.position = Vec3(0.0f, 0.0f, 2.0f);
  spot.direction = Vec3(0.0f, 0.0f, -1.0f);
  spot.spot_size = 2.0f * std::atan(0.5f);  // cone edge at radius 1 on the floor
  spot.spot_blend = 0.0f;
  scene.set_light("spot", spot);
  const auto compiled = scene.compile();
  const WhittedIntegrator integrator(*compiled, Settings{});
  RayCounts counts;
  const auto floor_radiance = [&](float x) {
    Ray ray{Vec3(x, 0.0f, 0.5f), Vec3(0.0f, 0.0f, -1.0f), 0.0f, kInfinity};
    return integrator.trace(ray, NodeState{}, &counts).x;
  };
  EXPECT_NEAR(floor_radiance(0.0f), 0.8f / kPi * 10.0f / 4.0f, 1e-5f);
  EXPECT_GT(floor_radiance(0.95f), 0.0f);
  EXPECT_EQ(floor_radiance(1.05f), 0.0f);
  EXPECT_EQ(counts.shadow, 2u);  // none for the point outside the cone
}

TEST(Whitted, AmbientAndBackground) {
  Scene scene;
  Material m;
  m.diffuse = Color(0.5f, 0.25f, 1.0f);
  m.ambient = 0.8f;
  add_object(&scene, "floor", quad(-1, 1, -1, 1, 0), m);
  scene.set_ambient(Color(0.1f, 0.2f, 0.3f));
  scene.set_background(Color(0.3f, 0.6f, 0.9f));
  const auto compiled = scene.compile();
  const WhittedIntegrator integrator(*compiled, Settings{});
  RayCounts counts;
  const Color hit =
      integrator.trace({Vec3(0, 0, 1), Vec3(0, 0, -1), 0.0f, kInfinity}, NodeState{}, &counts);
  const Color miss =
      integrator.trace({Vec3(5, 0, 1), Vec3(0, 0, -1), 0.0f, kInfinity}, NodeState{}, &counts);
  EXPECT_NEAR(hit.x, 0.8f * 0.1f * 0.5f, 1e-6f);
  EXPECT_NEAR(hit.z, 0.8f * 0.3f * 1.0f, 1e-6f);
  EXPECT_EQ(miss, scene.background());
}

// A floor under a sun, seen from many directions: a Burley material (Cycles 3.x's
// Principled diffuse) is the Lambertian value times burley_diffuse of that pixel's
// light and view; a coat added on top (not layered) leaves that diffuse as it is, and a
// layered one takes the coat's Fresnel share from it.
TEST(Whitted, BurleyDiffuseAndAnUnlayeredCoat) {
  const Vec3 to_sun = glm::normalize(Vec3(0.6f, -0.3f, 0.5f));
  const auto render = [&](const Material& m, std::vector<Ray>* rays) {
    Scene scene;
    add_object(&scene, "floor", quad(-40, 40, -40, 40, 0), m);
    Light sun;
    sun.type = LightType::kSun;
    sun.color = Color(3.0f);  // irradiance, W/m^2
    sun.direction = -to_sun;
    scene.set_light("sun", sun);
    scene.camera = looking_down(Vec3(0.0f, 0.0f, 1.0f), 2.0f);  // views to 63 degrees
    scene.set_background(Color(0.0f));
    const auto compiled = scene.compile();
    const WhittedIntegrator integrator(*compiled, Settings{});
    RayCounts counts;
    std::vector<float> out;
    const int n = 24;
    for (int y = 0; y < n; ++y) {
      for (int x = 0; x < n; ++x) {
        const Ray ray = scene.camera.generate_ray((x + 0.5f) / n, (y + 0.5f) / n);
        if (rays != nullptr) rays->push_back(ray);
        out.push_back(integrator.trace(ray, NodeState{}, &counts).x);
      }
    }
    return out;
  };
  Material lambert;
  lambert.diffuse = Color(0.6f);
  lambert.ambient = 0.0f;
  Material burley = lambert;
  burley.diffuse_model = DiffuseModel::kBurley;
  burley.diffuse_roughness = 0.8f;
  std::vector<Ray> rays;
  const std::vector<float> flat = render(lambert, &rays);
  const std::vector<float> shaped = render(burley, nullptr);
  Material coated = burley;  // a coat that mirrors the black background only
  coated.coat_reflectivity = 1.0f;
  coated.coat_layered = false;
  const std::vector<float> unlayered = render(coated, nullptr);
  coated.coat_layered = true;
  const std::vector<float> layered = render(coated, nullptr);
  float brightest = 0.0f;
  for (size_t i = 0; i < rays.size(); ++i) {
    const Vec3 wo = -glm::normalize(rays[i].direction);
    const float shape = burley_diffuse(to_sun.z, wo.z, glm::dot(to_sun, wo), 0.8f);
    ASSERT_NEAR(shaped[i], flat[i] * shape, 1e-5f * flat[i]) << "pixel " << i;
    EXPECT_EQ(unlayered[i], shaped[i]);
    const float f = fresnel_exact(wo.z, 1.0f / 1.5f);
    ASSERT_NEAR(layered[i], (1.0f - f) * shaped[i], 1e-5f * shaped[i]) << "pixel " << i;
    brightest = std::max(brightest, shape);
  }
  EXPECT_GT(brightest, 1.05f);  // retro-reflection shows where the view nears the sun
}

// The kernel is chosen once, for the benchmark's query log or the inspector's ray tree:
// never both.
TEST(Whitted, TakesAQueryLogOrARayTreeNotBoth) {
  Scene scene;
  add_object(&scene, "floor", quad(-1, 1, -1, 1, 0), Material{});
  const auto compiled = scene.compile();
  RayLog log;
  RayTree tree;
  EXPECT_THROW(WhittedIntegrator(*compiled, Settings{}, Camera{}, &log, &tree),
               std::invalid_argument);
  EXPECT_NO_THROW(WhittedIntegrator(*compiled, Settings{}, Camera{}, &log));
  EXPECT_NO_THROW(WhittedIntegrator(*compiled, Settings{}, Camera{}, nullptr, &tree));
}

}  // namespace
}  // namespace whitted
