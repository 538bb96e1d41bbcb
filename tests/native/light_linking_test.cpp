// Light linking and shadow linking (Blender 4.0+): an emitter lights only the receivers'
// light sets in its mask, and only the blockers' shadow sets in its shadow mask cast its
// shadows (scene/light.h).
#include <gtest/gtest.h>

#include <cmath>

#include "integrator/whitted.h"
#include "scene_builders.h"

namespace whitted {
namespace {

using testing::add_object;
using testing::emitter;
using testing::looking_down;
using testing::occluder_over_floor;
using testing::quad;

constexpr uint64_t set_bit(int set) {
  return uint64_t{1} << set;
}

// Puts instance `name` (as add_object made it) in the given sets.
void link(Scene* scene, const std::string& name, InstanceLinks links) {
  Instance instance{name, glm::mat4(1.0f), {name}};
  instance.links = links;
  scene->set_instance(name, instance);
}

Color seen(const Scene& scene, float x, float y, const Settings& settings = Settings{}) {
  const auto compiled = scene.compile();
  const WhittedIntegrator integrator(*compiled, settings);
  RayCounts counts;
  return integrator.trace(scene.camera.generate_ray(x, y), NodeState{}, &counts);
}

// Two floors side by side under one lamp: the left one in light set 1, the right in none.
Scene two_floors(uint64_t light_sets) {
  Scene scene;
  Material white;
  white.ambient = 0.0f;
  add_object(&scene, "left", quad(-4, 0, -2, 2, 0), white);
  add_object(&scene, "right", quad(0, 4, -2, 2, 0), white);
  link(&scene, "left", {.light_set = 1});
  Light light;
  light.color = Color(10.0f);
  light.position = Vec3(0.0f, 0.0f, 2.0f);
  light.light_sets = light_sets;
  scene.set_light("light", light);
  scene.camera = looking_down(Vec3(0.0f, 0.0f, 5.0f), 0.8f);
  return scene;
}

TEST(LightLinking, ALampLightsOnlyTheSetsItLinks) {
  const float left = 0.25f, right = 0.75f;  // film x of each floor's middle
  EXPECT_GT(seen(two_floors(kAllLightSets), left, 0.5f).x, 0.0f);
  EXPECT_GT(seen(two_floors(kAllLightSets), right, 0.5f).x, 0.0f);
  // Including set 1 only (Blender: the collection includes the left floor).
  EXPECT_GT(seen(two_floors(set_bit(1)), left, 0.5f).x, 0.0f);
  EXPECT_EQ(seen(two_floors(set_bit(1)), right, 0.5f).x, 0.0f);
  // Excluding set 1 (the collection excludes it): every other set is lit.
  EXPECT_EQ(seen(two_floors(~set_bit(1)), left, 0.5f).x, 0.0f);
  EXPECT_EQ(seen(two_floors(~set_bit(1)), right, 0.5f),
            seen(two_floors(kAllLightSets), right, 0.5f));
}

// The blocker of occluder_over_floor in shadow set 1: the lamp's shadow is cast only if
// its shadow mask holds set 1. Sized lamps send packets of feelers; glass elsewhere
// sends them through the translucent walk: both paths honour the mask.
TEST(ShadowLinking, OnlyTheLinkedBlockersCastALampsShadow) {
  for (const bool sized : {false, true}) {
    for (const bool translucent : {false, true}) {
      const auto centre = [&](uint64_t shadow_sets) {
        Scene scene = occluder_over_floor(0.2f);
        link(&scene, "blocker", {.shadow_set = 1});
        Light light;
        light.color = Color(10.0f);
        light.position = Vec3(0.0f, 0.0f, 2.0f);
        light.radius = sized ? 0.1f : 0.0f;
        light.samples = 3;
        light.shadow_sets = shadow_sets;
        scene.set_light("light", light);
        if (translucent) {
          Material cut_out;
          cut_out.alpha = 0.5f;
          add_object(&scene, "veil", quad(8, 9, 8, 9, 1.0f), cut_out);
        }
        // The floor at (0.75, 0), in the blocker's shadow, seen past the blocker.
        return seen(scene, 0.875f, 0.5f).x;
      };
      const float r2 = 0.75f * 0.75f + 4.0f;
      const float lit = 0.8f / kPi * 10.0f * (2.0f / std::sqrt(r2)) / r2;  // unblocked
      SCOPED_TRACE(::testing::Message() << "sized " << sized << " translucent " << translucent);
      EXPECT_EQ(centre(kAllLightSets), 0.0f);
      EXPECT_EQ(centre(set_bit(1)), 0.0f);
      EXPECT_NEAR(centre(set_bit(0)), lit, 5e-3f * lit);  // the blocker casts none
      EXPECT_NEAR(centre(~set_bit(1)), lit, 5e-3f * lit);
    }
  }
}

// An emissive panel over a floor, linked to light set 1 only: it lights the floor when
// the floor is in set 1; seen in a mirror outside set 1 it is not there (a bounce sees
// only the emitters that light the surface it left), seen by the camera it always is.
TEST(LightLinking, AnEmissiveMeshLightsAndShowsOnlyWhereLinked) {
  const auto scene_with = [](uint8_t floor_set, uint8_t mirror_set) {
    Scene scene;
    Material white;
    white.ambient = 0.0f;
    add_object(&scene, "floor", quad(-20, 20, -20, 20, 0), white);
    link(&scene, "floor", {.light_set = floor_set});
    // Facing down at height 2 (wound clockwise seen from below: its normal is -z).
    const float panel[] = {-0.5f, -0.5f, 2, -0.5f, 0.5f, 2, 0.5f, 0.5f, 2, 0.5f, -0.5f, 2};
    const uint32_t triangles[] = {0, 1, 2, 0, 2, 3};
    add_object(&scene, "panel", make_mesh(panel, 4, triangles, 2, nullptr, nullptr),
               emitter(Color(5.0f), EmissionSampling::kBoth));
    link(&scene, "panel", {.light_sets = set_bit(1)});
    Material mirror;
    mirror.diffuse = Color(0.0f);
    mirror.ambient = 0.0f;
    mirror.reflectivity = Color(1.0f);
    add_object(&scene, "mirror", quad(2, 8, -1, 1, 0.01f), mirror);
    link(&scene, "mirror", {.light_set = mirror_set});
    scene.camera = looking_down(Vec3(0.0f, 0.0f, 5.0f), 0.4f);
    return scene;
  };
  // The floor at (1.2, 0), lit by the panel and seen past it.
  EXPECT_GT(seen(scene_with(1, 0), 0.8f, 0.5f).x, 0.0f);
  EXPECT_EQ(seen(scene_with(0, 0), 0.8f, 0.5f).x, 0.0f);
  // From above the mirror, looking up at the panel through it.
  const auto through_mirror = [&](uint8_t mirror_set) {
    const Scene scene = scene_with(0, mirror_set);
    const auto compiled = scene.compile();
    const WhittedIntegrator integrator(*compiled, Settings{});
    RayCounts counts;
    const Vec3 from(7.0f, 0.0f, 0.5f);
    const Vec3 image(0.0f, 0.0f, -1.98f);  // the panel mirrored in z = 0.01
    const Ray ray{from, glm::normalize(image - from), 0.0f, kInfinity, kCameraRay};
    return integrator.trace(ray, NodeState{}, &counts).x;
  };
  EXPECT_NEAR(through_mirror(1), 5.0f, 1e-4f);
  EXPECT_EQ(through_mirror(0), 0.0f);
  // The camera sees the panel whatever its links.
  const Scene scene = scene_with(0, 0);
  const auto compiled = scene.compile();
  const WhittedIntegrator integrator(*compiled, Settings{});
  RayCounts counts;
  const Ray up{Vec3(0.0f, 0.0f, 1.0f), Vec3(0.0f, 0.0f, 1.0f), 0.0f, kInfinity, kCameraRay};
  EXPECT_NEAR(integrator.trace(up, NodeState{}, &counts).x, 5.0f, 1e-4f);
}

}  // namespace
}  // namespace whitted
