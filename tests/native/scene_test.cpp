// The compile cache: what a change rebuilds, what it reuses, and that a snapshot stands
// on its own while the scene is edited.
#include "scene/scene.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "integrator/render.h"
#include "scene_builders.h"

namespace whitted {
namespace {

using testing::add_object;
using testing::looking_down;
using testing::quad;

Scene lit_floor() {
  Scene scene;
  Material white;
  white.ambient = 0.0f;
  add_object(&scene, "floor", quad(-5, 5, -5, 5, 0), white);
  Light light;
  light.color = Color(20.0f);
  light.position = Vec3(0.0f, 0.0f, 3.0f);
  scene.set_light("light", light);
  scene.camera = looking_down(Vec3(0.0f, 0.0f, 4.0f), 0.5f);
  return scene;
}

std::vector<float> render(const Scene& scene) {
  Settings settings;
  settings.width = 12;
  settings.height = 10;
  RenderJob job(scene, settings, scene.camera);
  testing::run_to_end(job);
  return job.film().pixels();
}

TEST(Scene, AnUnchangedSceneCompilesOnce) {
  Scene scene = lit_floor();
  bool built = false;
  const auto first = scene.compile(&built);
  EXPECT_TRUE(built);
  const auto second = scene.compile(&built);
  EXPECT_FALSE(built);
  EXPECT_EQ(first, second);
  scene.camera = looking_down(Vec3(1.0f, 0.0f, 4.0f), 0.3f);  // the camera is not compiled
  EXPECT_EQ(scene.compile(), first);
  EXPECT_EQ(scene.top_level_builds(), 1u);
}

TEST(Scene, ShadingChangesReuseTheTopLevelBvh) {
  Scene scene = lit_floor();
  const auto before = scene.compile();
  Material red;
  red.diffuse = Color(0.9f, 0.1f, 0.1f);
  scene.set_material("floor", red);
  bool built = true;
  const auto after = scene.compile(&built);
  EXPECT_FALSE(built);
  EXPECT_NE(after, before);
  EXPECT_EQ(after->accel, before->accel);
  EXPECT_EQ(after->materials[after->instances[0].materials[0]].diffuse, red.diffuse);

  Light light;
  light.position = Vec3(1.0f, 0.0f, 2.0f);
  scene.set_light("second", light);
  scene.set_background(Color(0.5f));
  scene.set_ambient(Color(0.25f));
  scene.set_texture("checker", Texture{TexCoord::kUV, CheckerTexture{}});
  scene.remove_texture("checker");
  scene.remove_light("second");
  const auto last = scene.compile(&built);
  EXPECT_FALSE(built);
  EXPECT_EQ(last->accel, before->accel);
  EXPECT_EQ(last->background, Color(0.5f));
  EXPECT_EQ(last->ambient, Color(0.25f));
  EXPECT_EQ(scene.top_level_builds(), 1u);
  // The reused BVH renders what a fresh compile renders.
  const Scene built_afresh = [&] {
    Scene fresh = lit_floor();
    fresh.set_material("floor", red);
    fresh.set_background(Color(0.5f));
    fresh.set_ambient(Color(0.25f));
    return fresh;
  }();
  EXPECT_EQ(render(scene), render(built_afresh));
}

TEST(Scene, GeometryChangesAndShadowMasksRebuildTheTopLevelBvh) {
  Scene scene = lit_floor();
  scene.compile();
  scene.set_instance("second", Instance{"floor", glm::mat4(1.0f), {"floor"}});
  bool built = false;
  scene.compile(&built);
  EXPECT_TRUE(built);
  scene.remove_instance("second");
  scene.compile(&built);
  EXPECT_TRUE(built);
  scene.set_mesh("unused", quad(0, 1, 0, 1, 2));
  scene.compile(&built);
  EXPECT_TRUE(built);
  // Glass lets shadow feelers through: the instance's mask lives in the top-level BVH.
  Material glass;
  glass.transmissivity = Color(0.5f);
  scene.set_material("floor", glass);
  scene.compile(&built);
  EXPECT_TRUE(built);
  EXPECT_EQ(scene.top_level_builds(), 5u);
}

TEST(Scene, AFailedCompileKeepsNothing) {
  Scene scene = lit_floor();
  scene.compile();
  scene.set_instance("orphan", Instance{"floor", glm::mat4(1.0f), {"no such material"}});
  EXPECT_THROW(scene.compile(), std::invalid_argument);
  EXPECT_THROW(scene.compile(), std::invalid_argument);  // not cached as good
  scene.remove_instance("orphan");
  EXPECT_NO_THROW(scene.compile());
}

// A snapshot owns what it reads: it still traces after the scene replaced or removed
// every mesh and was destroyed.
TEST(Scene, ASnapshotOutlivesItsScene) {
  std::shared_ptr<const CompiledScene> snapshot;
  {
    Scene scene = lit_floor();
    snapshot = scene.compile();
    scene.set_mesh("floor", quad(-1, 1, -1, 1, 0));
    scene.remove_instance("floor");
    scene.remove_mesh("floor");
    scene.compile();
  }
  Hit hit;
  EXPECT_TRUE(snapshot->accel->intersect(
      Ray{Vec3(3.0f, 3.0f, 1.0f), Vec3(0.0f, 0.0f, -1.0f), 0.0f, kInfinity, kCameraRay}, &hit));
  EXPECT_FLOAT_EQ(hit.t, 1.0f);
}

// Editing the scene while a job renders it changes nothing in that job's image.
TEST(Scene, EditsDuringARenderDoNotReachIt) {
  Scene scene = lit_floor();
  const std::vector<float> reference = render(scene);
  Settings settings;
  settings.width = 12;
  settings.height = 10;
  settings.tile_size = 1;
  settings.threads = 2;
  RenderJob job(scene, settings, scene.camera);
  job.start();
  Material red;
  red.diffuse = Color(1.0f, 0.0f, 0.0f);
  scene.set_material("floor", red);
  scene.set_mesh("floor", quad(-1, 1, -1, 1, 0));
  scene.remove_light("light");
  scene.set_background(Color(1.0f));
  scene.compile();
  while (!job.wait(1.0)) {
  }
  EXPECT_EQ(job.film().pixels(), reference);
  EXPECT_NE(render(scene), reference);
}

}  // namespace
}  // namespace whitted
