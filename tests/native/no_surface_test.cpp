// A material without a surface (Material::surface false: Cycles' material whose output
// has a Volume and no Surface) is no surface: every ray passes through its mesh untouched
// and it casts no shadow, as Cycles lets rays through a volume's bounds (issue 48, step 0).
#include <gtest/gtest.h>

#include <stdexcept>

#include "integrator/analysis.h"
#include "integrator/render.h"
#include "scene_builders.h"

namespace whitted {
namespace {

using testing::add_object;
using testing::box;
using testing::emitter;
using testing::glass_and_mirror_scene;
using testing::looking_down;
using testing::quad;
using testing::render_pixels;
using testing::small_render;

// What the exporter makes of a material whose output has a Volume and no Surface: the rest
// of its fields as a bright emitter, so that any ray stopping on it would show.
Material no_surface() {
  MaterialParams m = emitter(Color(7.0f), EmissionSampling::kBoth);
  m.reflectivity = Color(0.5f);
  m.surface = false;
  return Material(m);  // the checks, as the bindings make every material
}

// glass_and_mirror_scene (a floor, a glass pane, a mirror, a point light and an area light:
// camera, shadow, reflected and refracted rays), its mirror rough (glossy rays) or not.
Scene lit_scene(bool glossy) {
  Scene scene = glass_and_mirror_scene();
  if (glossy) {
    Material mirror;
    mirror.reflectivity = Color(0.8f);
    mirror.roughness = 0.4f;
    scene.set_material("mirror", mirror);
  }
  return scene;
}

struct Rendered {
  std::vector<float> pixels;
  RenderStats stats;
};

Rendered render(const Scene& scene, bool waves) {
  Settings settings = small_render(24, 24, 2, 2, 8);
  settings.waves = waves;
  RenderJob job(scene, settings, scene.camera);
  testing::run_to_end(job);
  return {job.film().pixels(), job.stats()};
}

// Renders a scene `with` a no-surface box and `without` it, with waves and without: the
// same pixels, rays and effects.
void expect_unseen(const Scene& with, const Scene& without) {
  for (const bool waves : {false, true}) {
    SCOPED_TRACE(waves ? "waves" : "recursion");
    const Rendered a = render(with, waves);
    const Rendered b = render(without, waves);
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    for (size_t i = 0; i < a.pixels.size(); ++i) ASSERT_EQ(a.pixels[i], b.pixels[i]) << i;
    // It costs nothing: not one ray more (no continuation behind it), no effect switched on.
    EXPECT_EQ(a.stats.rays.total(), b.stats.rays.total());
    EXPECT_EQ(a.stats.rays.transparent, 0u);
    ASSERT_EQ(a.stats.effects.size(), b.stats.effects.size());
    for (size_t i = 0; i < a.stats.effects.size(); ++i) {
      EXPECT_EQ(a.stats.effects[i].on, b.stats.effects[i].on) << a.stats.effects[i].name;
    }
  }
}

TEST(NoSurface, BoxBetweenCameraLampsAndFloorChangesNoPixel) {
  for (const bool glossy : {false, true}) {
    SCOPED_TRACE(glossy ? "glossy mirror" : "mirror");
    const Scene without = lit_scene(glossy);
    Scene with = without;
    // Around the glass and the mirror, under both lamps, in front of the camera: camera,
    // reflected, refracted and glossy rays and the feelers all cross it.
    add_object(&with, "fog", box(Vec3(-4.0f), Vec3(4.0f, 4.0f, 2.0f)), no_surface());
    expect_unseen(with, without);
  }
}

TEST(NoSurface, BoxAroundTheCameraChangesNoPixel) {
  const Scene without = lit_scene(false);
  Scene with = without;
  const Vec3 eye(without.camera.to_world[3]);
  add_object(&with, "fog", box(eye - Vec3(1.0f), eye + Vec3(1.0f)), no_surface());
  expect_unseen(with, without);
}

TEST(NoSurface, CastsNoShadow) {
  // A box between a point light and a floor, out of the camera's way: the floor under it
  // is lit as without it (the occluder scene's blocker, which does shadow it, removed).
  Scene without = testing::occluder_over_floor(2.0f);
  without.remove_instance("blocker");
  Scene with = without;
  add_object(&with, "fog", box(Vec3(-1.0f, -1.0f, 0.5f), Vec3(1.0f, 1.0f, 1.5f)), no_surface());
  expect_unseen(with, without);
}

TEST(NoSurface, AMeshOfNoSurfaceAnywhereIsSeenByNoRay) {
  Scene scene = testing::occluder_over_floor(2.0f);
  scene.set_material("blocker", no_surface());
  const auto compiled = scene.compile();
  for (const auto& instance : compiled->instances) {
    EXPECT_EQ(instance.visibility, instance.name == "blocker" ? 0u : uint32_t{kAllRayKinds});
  }
  // A slot past the instance's materials takes the default material, a surface.
  const float p[] = {-0.5f, -0.5f, 1.0f, 0.5f, -0.5f, 1.0f, 0.5f, 0.5f, 1.0f, -0.5f, 0.5f, 1.0f};
  const uint32_t t[] = {0, 1, 2, 0, 2, 3};
  const int32_t slots[] = {0, 1};
  scene.set_mesh("blocker", make_mesh(p, 4, t, 2, nullptr, slots));
  EXPECT_EQ(scene.compile()->instances[0].visibility, uint32_t{kAllRayKinds});
}

TEST(NoSurface, SharingAMeshWithASurfaceItIsACutOut) {
  // The blocker's two triangles: slot 0 no surface, slot 1 an emitter. Looking down through
  // the first, the lit floor (the light passes it); through the second, its emission.
  Scene scene = testing::occluder_over_floor(2.0f);
  const float p[] = {-0.5f, -0.5f, 1.0f, 0.5f, -0.5f, 1.0f, 0.5f, 0.5f, 1.0f, -0.5f, 0.5f, 1.0f};
  const uint32_t t[] = {0, 1, 2, 0, 2, 3};
  const int32_t slots[] = {0, 1};
  scene.set_mesh("blocker", make_mesh(p, 4, t, 2, nullptr, slots));
  scene.set_material("fog", no_surface());
  scene.set_material("lamp", emitter(Color(5.0f)));
  scene.set_instance("blocker", Instance{"blocker", glm::mat4(1.0f), {"fog", "lamp"}});
  Scene unblocked = scene;
  unblocked.remove_instance("blocker");
  const auto down_at = [](const Scene& at, float x, float y) {
    const auto compiled = at.compile();
    const WhittedIntegrator integrator(*compiled, Settings{});
    RayCounts counts;
    float alpha = 0.0f;
    const Ray ray{Vec3(x, y, 3.0f), Vec3(0.0f, 0.0f, -1.0f), 0.0f, kInfinity, kCameraRay};
    const float radiance = integrator.trace(ray, NodeState{}, &counts, &alpha).x;
    EXPECT_EQ(alpha, 1.0f);
    return radiance;
  };
  // Triangle 0 (0,1,2) lies below the diagonal y = x, triangle 1 above it; the feeler from
  // the floor at (0.2, -0.2) to the light crosses triangle 0.
  const float lit = down_at(unblocked, 0.2f, -0.2f);
  EXPECT_GT(lit, 0.0f);
  EXPECT_EQ(down_at(scene, 0.2f, -0.2f), lit);
  EXPECT_FLOAT_EQ(down_at(scene, -0.2f, 0.2f), 5.0f);
}

TEST(NoSurface, HasNoProgramOrTexture) {
  MaterialParams params;
  params.surface = false;
  params.alpha_texture = "holes";
  EXPECT_THROW(Material{params}, std::invalid_argument);
  params.alpha_texture.clear();
  params.alpha = 1.0f;
  EXPECT_EQ(Material(params).alpha, 0.0f);  // nothing of it covers anything
}

}  // namespace
}  // namespace whitted
