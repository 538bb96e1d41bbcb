// Small scenes for the native tests, built through the same Scene API the add-on uses.
#pragma once

#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "integrator/render.h"
#include "scene/scene.h"

namespace whitted::testing {

// An axis-aligned rectangle in the plane z = `z`, spanning [x0,x1] x [y0,y1], wound so
// its normal points along +z.
inline Mesh quad(float x0, float x1, float y0, float y1, float z) {
  const float p[] = {x0, y0, z, x1, y0, z, x1, y1, z, x0, y1, z};
  const uint32_t t[] = {0, 1, 2, 0, 2, 3};
  return make_mesh(p, 4, t, 2, nullptr, nullptr);
}

// A closed axis-aligned box from `lo` to `hi`, its faces wound outwards.
inline Mesh box(Vec3 lo, Vec3 hi) {
  const float p[] = {lo.x, lo.y, lo.z, hi.x, lo.y, lo.z, hi.x, hi.y, lo.z, lo.x, hi.y, lo.z,
                     lo.x, lo.y, hi.z, hi.x, lo.y, hi.z, hi.x, hi.y, hi.z, lo.x, hi.y, hi.z};
  const uint32_t t[] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                        1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7};
  return make_mesh(p, 8, t, 12, nullptr, nullptr);
}

inline void add_object(Scene* scene, const std::string& name, Mesh mesh, const Material& material,
                       const glm::mat4& to_world = glm::mat4(1.0f)) {
  scene->set_mesh(name, std::move(mesh));
  scene->set_material(name, material);
  scene->set_instance(name, Instance{name, to_world, {name}});
}

// Starts a render and waits for its end.
inline void run_to_end(RenderJob& job) {
  job.start();
  while (!job.wait(1.0)) {
  }
}

// Settings of a small render: `width` x `height` pixels, `samples` x `samples` regular
// camera samples a pixel, on `threads` threads in tiles of `tile` pixels.
inline Settings small_render(int width, int height, int samples, int threads, int tile) {
  Settings settings;
  settings.width = width;
  settings.height = height;
  settings.aa_samples = samples;
  settings.threads = threads;
  settings.tile_size = tile;
  return settings;
}

// The pixels of a whole render of `scene` from its camera, waited for.
inline std::vector<float> render_pixels(const Scene& scene, const Settings& settings) {
  RenderJob job(scene, settings, scene.camera);
  run_to_end(job);
  return job.film().pixels();
}

// A surface that shows `radiance` to the rays meeting it and, with `sampling`, lights the
// scene as an emissive mesh (None: a marker the tests look for, lighting nothing).
inline Material emitter(Color radiance, EmissionSampling sampling = EmissionSampling::kNone) {
  Material m;
  m.diffuse = Color(0.0f);
  m.ambient = 0.0f;
  m.emission = radiance;
  m.emission_sampling = sampling;
  return m;
}

// Clear glass (or any dielectric) of index `ior`: no diffuse, all transmitted.
inline Material clear(float ior) {
  Material m;
  m.diffuse = Color(0.0f);
  m.ambient = 0.0f;
  m.transmissivity = Color(1.0f);
  m.ior = ior;
  return m;
}

// A camera at `position` looking down -z with a square window of half-width `half`.
inline Camera looking_down(Vec3 position, float half) {
  Camera c;
  c.to_world = glm::translate(glm::mat4(1.0f), position);
  c.window[0] = -half;
  c.window[1] = half;
  c.window[2] = -half;
  c.window[3] = half;
  c.clip_start = 1e-3f;
  c.clip_end = 1e6f;
  return c;
}

// A white 40x40 floor at z = 0, a white 1x1 blocker at height 1 and a point light of
// colour 10 at height 2 (no ambient), seen by a camera looking down from height 5 with a
// window of half-width `half`. The blocker's hard shadow is the square |x|,|y| < 1.
inline Scene occluder_over_floor(float half) {
  Scene scene;
  Material white;
  white.ambient = 0.0f;
  add_object(&scene, "floor", quad(-20, 20, -20, 20, 0), white);
  add_object(&scene, "blocker", quad(-0.5f, 0.5f, -0.5f, 0.5f, 1.0f), white);
  Light light;
  light.color = Color(10.0f);
  light.position = Vec3(0.0f, 0.0f, 2.0f);
  scene.set_light("light", light);
  scene.camera = looking_down(Vec3(0.0f, 0.0f, 5.0f), half);
  return scene;
}

// A floor, a glass pane and a mirror under a point light and an area light: every
// effect, for tests of the render driver.
inline Scene glass_and_mirror_scene() {
  Scene scene;
  Material floor;
  floor.diffuse = Color(0.6f, 0.5f, 0.4f);
  floor.specular = Color(0.2f);
  add_object(&scene, "floor", quad(-5, 5, -5, 5, 0), floor);
  Material glass;
  glass.diffuse = Color(0.0f);
  glass.transmissivity = Color(0.9f);
  add_object(&scene, "glass", quad(-1, 1, -1, 1, 1), glass);
  Material mirror;
  mirror.reflectivity = Color(0.8f);
  add_object(&scene, "mirror", quad(-3, -2, -3, 3, 0.5f), mirror);
  Light light;
  light.color = Color(30.0f);
  light.position = Vec3(1.0f, 2.0f, 4.0f);
  scene.set_light("light", light);
  Light area;
  area.type = LightType::kArea;
  area.color = Color(5.0f);
  area.position = Vec3(-2.0f, 0.0f, 3.0f);
  area.size[0] = area.size[1] = 1.0f;
  area.samples = 3;
  scene.set_light("area", area);
  scene.set_ambient(Color(0.05f));
  scene.camera = looking_down(Vec3(0.3f, 0.2f, 6.0f), 0.9f);
  return scene;
}

// What the exporter makes of a material whose output has only a constant volume shader.
inline Material fog(Color absorption, Color scattering, float anisotropy = 0.0f,
                    Color emission = Color(0.0f)) {
  MaterialParams m;
  m.surface = false;
  m.volume_absorption = absorption;
  m.volume_scattering = scattering;
  m.volume_anisotropy = anisotropy;
  m.volume_emission = emission;
  return Material(m);
}

// glass_and_mirror_scene() in a fog box around its surfaces and lamps (the camera outside),
// scattering (and absorbing, and emitting `emission`): the camera's rays, the mirror's and
// the glass's cross it.
inline Scene foggy_glass_and_mirror_scene(Color scattering, Color emission = Color(0.0f)) {
  Scene scene = glass_and_mirror_scene();
  add_object(&scene, "fog", box(Vec3(-4.0f, -4.0f, -1.0f), Vec3(4.0f, 4.0f, 4.5f)),
             fog(Color(0.02f), scattering, 0.3f, emission));
  return scene;
}

}  // namespace whitted::testing
