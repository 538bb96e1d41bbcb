// Hard cases stay numerically stable: watertightness, energy through glass, nested media,
// the camera inside glass, scale invariance, coplanar faces.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

#include "integrator/render.h"
#include "scene_builders.h"

namespace whitted {
namespace {

using testing::add_object;
using testing::clear;
using testing::emitter;
using testing::looking_down;
using testing::quad;

// A closed octahedron of radius 1 around the origin, outward winding, shared vertices.
Mesh octahedron() {
  const float p[] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
  const uint32_t t[] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  return make_mesh(p, 6, t, 8, nullptr, nullptr);
}

// Rays aimed exactly at shared vertices and edges of a closed mesh, from outside and
// from inside, never slip through.
TEST(Robustness, RaysAtSharedEdgesAndVerticesNeverSlipThrough) {
  auto device = std::make_shared<AccelDevice>();
  const Mesh mesh = octahedron();
  const auto blas = std::make_shared<const MeshAccel>(device, mesh);
  std::vector<Vec3> targets;
  for (uint32_t v = 0; v < 6; ++v) targets.push_back(mesh.vertex(v));
  for (size_t i = 0; i < mesh.triangles.size(); i += 3) {
    for (int e = 0; e < 3; ++e) {
      const Vec3 a = mesh.vertex(mesh.triangles[i + e]);
      const Vec3 b = mesh.vertex(mesh.triangles[i + (e + 1) % 3]);
      for (float f : {0.5f, 0.25f, 1.0f / 3.0f}) targets.push_back(a + f * (b - a));
    }
  }
  int misses = 0;
  int rays = 0;
  for (float scale : {1e-3f, 1.0f, 1e4f}) {
    for (const glm::mat4& xf : {glm::scale(glm::mat4(1.0f), Vec3(scale)),
                                glm::rotate(glm::scale(glm::mat4(1.0f), Vec3(scale)), 0.3f,
                                            glm::normalize(Vec3(1.0f, 2.0f, 3.0f)))}) {
      const SceneAccel tlas(device, {{blas, xf, kAllRayKinds}});
      for (const Vec3& local : targets) {
        const Vec3 target = Vec3(xf * glm::vec4(local, 1.0f));
        // From inside (the centre) outwards, and from outside inwards.
        const Vec3 outside = 3.0f * target + Vec3(0.01f, 0.02f, 0.0f) * scale;
        for (const Ray& ray : {Ray{Vec3(0.0f), glm::normalize(target), 0.0f, kInfinity},
                               Ray{outside, glm::normalize(target - outside), 0.0f, kInfinity}}) {
          Hit hit;
          ++rays;
          if (!tlas.intersect(ray, &hit)) ++misses;
        }
      }
    }
  }
  EXPECT_GT(rays, 400);
  EXPECT_EQ(misses, 0);
}

// A clear glass ball under a uniform white sky: reflection and transmission shares add up
// to one at every interface (total internal reflection included), so every ray sees 1.
TEST(Robustness, GlassInAUniformSkyConservesEnergy) {
  for (Fresnel fresnel : {Fresnel::kExact, Fresnel::kSchlick}) {
    for (float ior : {1.5f, 2.4f, 0.7f}) {
      Scene scene;
      add_object(&scene, "ball", octahedron(), clear(ior));
      scene.set_background(Color(1.0f));
      const auto compiled = scene.compile();
      Settings settings;
      settings.fresnel = fresnel;
      settings.max_depth = 200;
      settings.cutoff = 0.0f;
      const WhittedIntegrator integrator(*compiled, settings);
      RayCounts counts;
      for (int i = 0; i < 200; ++i) {
        const float a = 0.0317f * static_cast<float>(i);
        const Vec3 origin(3.0f * std::cos(a), 3.0f * std::sin(a), 0.7f * std::sin(3.0f * a));
        const Vec3 target(0.3f * std::sin(5.0f * a), 0.2f * std::cos(7.0f * a), 0.1f);
        const Ray ray{origin, glm::normalize(target - origin), 0.0f, kInfinity};
        const Color c = integrator.trace(ray, NodeState{}, &counts);
        ASSERT_TRUE(is_finite(c));
        EXPECT_NEAR(c.x, 1.0f, 2e-3f) << "ior " << ior << " ray " << i;
      }
      EXPECT_GT(counts.refraction, 0u);
      if (ior > 1.0f) EXPECT_GT(counts.total_internal_reflections, 0u) << ior;
    }
  }
}

TEST(Robustness, IndexOfRefractionOnePassesStraightThrough) {
  Scene scene;
  add_object(&scene, "ball", octahedron(), clear(1.0f));
  add_object(&scene, "marker", quad(-0.05f, 0.05f, -0.05f, 0.05f, -5.0f), emitter(Color(7.0f)));
  const auto compiled = scene.compile();
  const WhittedIntegrator integrator(*compiled, Settings{});
  RayCounts counts;
  const Ray ray{Vec3(0.01f, 0.02f, 5.0f), Vec3(0.0f, 0.0f, -1.0f), 0.0f, kInfinity};
  EXPECT_NEAR(integrator.trace(ray, NodeState{}, &counts).x, 7.0f, 1e-5f);
  EXPECT_EQ(counts.refraction, 2u);
}

TEST(Robustness, TotalInternalReflectionAtTheCriticalAngleAndOneUlpEitherSide) {
  const float eta = 1.5f;  // glass to air
  const Vec3 n(0.0f, 1.0f, 0.0f);
  const float critical = std::asin(1.0f / eta);
  for (float angle : {std::nextafter(critical, 0.0f), critical, std::nextafter(critical, 2.0f)}) {
    const Vec3 u(std::sin(angle), -std::cos(angle), 0.0f);
    Vec3 t(0.0f);
    const bool refracts = refract(u, n, eta, &t);
    const float f = fresnel_exact(std::cos(angle), eta);
    EXPECT_TRUE(std::isfinite(f));
    EXPECT_NEAR(f, 1.0f, 2e-3f) << angle;  // continuous up to total internal reflection
    if (refracts) EXPECT_TRUE(is_finite(t));
  }
  // Grazing incidence: cos -> 0 gives finite results.
  for (float c : {0.0f, 1e-30f, 1e-7f}) {
    const Vec3 u = glm::normalize(Vec3(1.0f, -c, 0.0f));
    Vec3 t(0.0f);
    if (refract(u, n, 1.0f / 1.5f, &t)) EXPECT_TRUE(is_finite(t));
    EXPECT_TRUE(std::isfinite(fresnel_exact(c, 1.0f / 1.5f)));
    EXPECT_TRUE(std::isfinite(fresnel_schlick(c, 1.0f / 1.5f)));
  }
}

// Slabs stacked along z, met by a ray at angle theta: where does it land at z = -3?
// Each layer of thickness d and index n shifts it by d * tan(theta_n), Snell's law
// keeping n sin(theta_n) constant.
float landing_x(float theta, std::initializer_list<std::pair<float, float>> layers) {
  float x = 5.0f * std::tan(theta);  // from z = 5 down to the first surface at z = 0
  float depth = 0.0f;
  const float invariant = std::sin(theta);  // n sin(theta) in air
  for (auto [thickness, n] : layers) {
    x += thickness * std::tan(std::asin(invariant / n));
    depth += thickness;
  }
  return x + (3.0f - depth) * std::tan(theta);
}

// A slab between z0 (top, facing +z) and z1 (bottom, facing -z).
void add_slab(Scene* scene, const std::string& name, float z0, float z1, const Material& m) {
  add_object(scene, name + "_top", quad(-50, 50, -50, 50, z0), m);
  Mesh bottom = quad(-50, 50, -50, 50, z1);
  std::swap(bottom.triangles[1], bottom.triangles[2]);
  std::swap(bottom.triangles[4], bottom.triangles[5]);
  scene->set_mesh(name + "_bottom", std::move(bottom));
  scene->set_instance(name + "_bottom",
                      Instance{name + "_bottom", glm::mat4(1.0f), {name + "_top"}});
}

// Where a ray from (x0, 0, 5) at angle theta lands on the floor z = -3 (found by the
// bright half-floor's edge).
float traced_landing(const Scene& scene_in, float theta, const MediumStack& media = {}) {
  Scene scene = scene_in;
  add_object(&scene, "bright", quad(0.0f, 50, -50, 50, -3.0f), emitter(Color(1.0f)));
  const auto compiled = scene.compile();
  Settings settings;
  settings.fresnel = Fresnel::kOff;
  const WhittedIntegrator integrator(*compiled, settings);
  RayCounts counts;
  const Vec3 dir(std::sin(theta), 0.0f, -std::cos(theta));
  float lo = -30.0f;
  float hi = 30.0f;
  for (int i = 0; i < 60; ++i) {
    const float mid = 0.5f * (lo + hi);
    const Ray ray{Vec3(mid, 0.0f, 5.0f), dir, 0.0f, kInfinity};
    (integrator.trace(ray, NodeState{0, Color(1.0f), media}, &counts).x > 0.5f ? hi : lo) = mid;
  }
  return -lo;  // the origin that lands on x = 0 is minus the landing offset
}

TEST(Robustness, OverlappingGlassOfOneKindActsAsOnePiece) {
  Scene scene;
  add_slab(&scene, "a", 0.0f, -1.0f, clear(1.5f));
  add_slab(&scene, "b", -0.5f, -1.5f, clear(1.5f));  // overlaps a over [-1, -0.5]
  for (float theta : {0.3f, 0.8f}) {
    EXPECT_NEAR(traced_landing(scene, theta), landing_x(theta, {{1.5f, 1.5f}}), 1e-4f);
  }
}

// Water modelled to reach 0.1 into the glass wall, as artists model it. With the glass of
// higher priority the overlap is glass, and the rays bend at the true glass-water
// interface; with equal priorities the overlap goes to the medium entered last, water.
TEST(Robustness, WaterInAGlassModelledWithOverlapFollowsPriorities) {
  for (int glass_priority : {1, 0}) {
    Scene scene;
    Material glass = clear(1.5f);
    glass.priority = glass_priority;
    add_slab(&scene, "glass", 0.0f, -1.0f, glass);
    add_slab(&scene, "water", -0.9f, -2.0f, clear(1.33f));
    const float glass_depth = glass_priority > 0 ? 1.0f : 0.9f;
    for (float theta : {0.3f, 0.8f}) {
      EXPECT_NEAR(traced_landing(scene, theta),
                  landing_x(theta, {{glass_depth, 1.5f}, {2.0f - glass_depth, 1.33f}}), 1e-4f)
          << "glass priority " << glass_priority << ", theta " << theta;
    }
  }
}

TEST(Robustness, CameraInsideGlassStartsInTheGlass) {
  Scene scene;
  // A slab whose top is above the camera (z = 5): the camera is inside it.
  add_slab(&scene, "glass", 6.0f, -1.0f, clear(1.5f));
  add_object(&scene, "bright", quad(0.0f, 50, -50, 50, -3.0f), emitter(Color(1.0f)));
  const auto compiled = scene.compile();
  const WhittedIntegrator integrator(*compiled, Settings{});
  const MediumStack media = integrator.media_at(Vec3(0.0f, 0.0f, 5.0f));
  ASSERT_FALSE(media.empty());
  EXPECT_EQ(compiled->materials[static_cast<size_t>(media.current())].ior, 1.5f);
  EXPECT_TRUE(integrator.media_at(Vec3(0.0f, 0.0f, 7.0f)).empty());
  // From inside, the ray leaves through the bottom into air: 6 units in glass, then air.
  Scene without_floor;
  add_slab(&without_floor, "glass", 6.0f, -1.0f, clear(1.5f));
  const float theta = 0.4f;
  const float in_glass = 6.0f * std::tan(theta);  // z = 5 down to z = -1, inside glass
  const float theta_air = std::asin(1.5f * std::sin(theta));
  const float expected = in_glass + 2.0f * std::tan(theta_air);
  EXPECT_NEAR(traced_landing(without_floor, theta, media), expected, 1e-4f);
}

Scene lit_shapes(float s) {
  Scene scene;
  Material white;
  white.diffuse = Color(0.7f);
  white.specular = Color(0.2f);
  white.shininess = 20.0f;
  white.ambient = 0.1f;
  add_object(&scene, "floor", quad(-10 * s, 10 * s, -10 * s, 10 * s, 0), white);
  Material mirror;
  mirror.diffuse = Color(0.1f);
  mirror.reflectivity = Color(0.8f);
  add_object(&scene, "ball", octahedron(), mirror,
             glm::scale(glm::translate(glm::mat4(1.0f), Vec3(0.5f, 0.0f, 1.0f) * s), Vec3(s)));
  add_object(&scene, "glass", octahedron(), clear(1.5f),
             glm::scale(glm::translate(glm::mat4(1.0f), Vec3(-1.5f, 0.5f, 1.0f) * s), Vec3(s)));
  Light light;
  light.color = Color(40.0f * s * s);  // irradiance I / r^2 stays the same at every scale
  light.position = Vec3(2.0f, -1.0f, 5.0f) * s;
  scene.set_light("light", light);
  scene.set_ambient(Color(0.2f));
  scene.set_background(Color(0.3f, 0.4f, 0.5f));
  scene.camera = looking_down(Vec3(0.3f, -0.2f, 8.0f) * s, 0.45f);
  scene.camera.clip_start = 1e-3f * s;
  scene.camera.clip_end = 1e3f * s;
  return scene;
}

std::vector<float> render_image(const Scene& scene, int threads = 2, int tile = 16) {
  Settings settings;
  settings.width = 64;
  settings.height = 64;
  settings.threads = threads;
  settings.tile_size = tile;
  RenderJob job(scene, settings, scene.camera);
  testing::run_to_end(job);
  return job.film().pixels();
}

// The same scene at scales 1e-4, 1 and 1e5 renders the same image: no scale-dependent
// epsilon anywhere, so no acne appears at either end.
TEST(Robustness, SceneScaleDoesNotChangeTheImage) {
  const std::vector<float> reference = render_image(lit_shapes(1.0f));
  for (float s : {1e-4f, 1e5f}) {
    const std::vector<float> image = render_image(lit_shapes(s));
    double err = 0.0;
    double norm = 0.0;
    int far_off = 0;
    for (size_t i = 0; i < image.size(); ++i) {
      const double d = image[i] - reference[i];
      err += d * d;
      norm += double(reference[i]) * reference[i];
      // A pixel that differs by more than 1% of the scene's brightest value: acne, or an
      // edge pixel where a silhouette moved by rounding.
      if (std::fabs(d) > 0.01) ++far_off;
    }
    EXPECT_LT(std::sqrt(err / norm), 1e-3) << "scale " << s;
    EXPECT_LE(far_off, 8) << "scale " << s;  // at most a few silhouette pixels
  }
}

// Two coplanar quads of different colours: which one shows is decided by the BVH
// traversal, the same in every render and with any thread count or tile size.
TEST(Robustness, CoplanarFacesGiveTheSameImageEveryTime) {
  const auto build = [] {
    Scene scene;
    add_object(&scene, "red", quad(-1, 1, -1, 1, 0), emitter(Color(1.0f, 0.0f, 0.0f)));
    add_object(&scene, "blue", quad(-1, 1, -1, 1, 0), emitter(Color(0.0f, 0.0f, 1.0f)));
    scene.camera = looking_down(Vec3(0.0f, 0.0f, 3.0f), 0.3f);
    return scene;
  };
  const std::vector<float> first = render_image(build(), 1, 64);
  EXPECT_EQ(render_image(build(), 2, 7), first);
  EXPECT_EQ(render_image(build(), 3, 1), first);
}

// The same with camera rays in packets of several pixels (a block fixed in the image):
// a border that starts and ends inside blocks, and tiles that cut them, leave every
// pixel as the whole image has it, where the packet decides each tie.
TEST(Robustness, CoplanarFacesInCameraPacketsDoNotDependOnBorderOrTiles) {
  Scene scene;
  add_object(&scene, "red", quad(-1, 1, -1, 1, 0), emitter(Color(1.0f, 0.0f, 0.0f)));
  add_object(&scene, "blue", quad(-1, 1, -1, 1, 0), emitter(Color(0.0f, 0.0f, 1.0f)));
  scene.camera = looking_down(Vec3(0.0f, 0.0f, 3.0f), 0.3f);
  for (int n : {2, 3}) {  // blocks of 4 pixels and of 1
    Settings settings;
    settings.width = 64;
    settings.height = 64;
    settings.aa_samples = n;
    settings.threads = 1;
    settings.tile_size = 64;
    RenderJob whole(scene, settings, scene.camera);
    ASSERT_TRUE(whole.stats().camera_packets);
    whole.start();
    while (!whole.wait(1.0)) {
    }
    const std::vector<float>& reference = whole.film().pixels();
    settings.border[0] = 3;
    settings.border[1] = 5;
    settings.border[2] = 57;
    settings.border[3] = 40;
    settings.threads = 2;
    settings.tile_size = 9;
    RenderJob part(scene, settings, scene.camera);
    part.start();
    while (!part.wait(1.0)) {
    }
    const std::vector<float>& pixels = part.film().pixels();
    int differ = 0;
    for (int y = 5; y < 40; ++y) {
      for (int x = 3; x < 57; ++x) {
        for (int c = 0; c < 4; ++c) {
          const size_t i = (static_cast<size_t>(y) * 64 + static_cast<size_t>(x)) * 4 + c;
          differ += pixels[i] != reference[i];
        }
      }
    }
    EXPECT_EQ(differ, 0) << n << "x" << n << " samples";
  }
}

// A low-poly UV sphere with smooth (vertex) normals, as corner normals.
Mesh smooth_sphere(int rings, int segments) {
  std::vector<float> p;
  std::vector<uint32_t> t;
  std::vector<float> n;
  const auto vertex = [&](int ring, int segment) {
    const float theta = kPi * static_cast<float>(ring) / static_cast<float>(rings);
    const float phi = 2.0f * kPi * static_cast<float>(segment) / static_cast<float>(segments);
    return Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
  };
  for (int r = 0; r < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      const Vec3 a = vertex(r, s), b = vertex(r + 1, s), c = vertex(r + 1, s + 1),
                 d = vertex(r, s + 1);
      for (const Vec3& v : {a, b, c, a, c, d}) {
        t.push_back(static_cast<uint32_t>(p.size() / 3));
        p.insert(p.end(), {v.x, v.y, v.z});
        n.insert(n.end(), {v.x, v.y, v.z});  // on a unit sphere the normal is the point
      }
    }
  }
  return make_mesh(p.data(), p.size() / 3, t.data(), t.size() / 3, n.data(), nullptr);
}

// A coarse smooth sphere lit at a grazing angle: where the smooth shading normal faces
// the light, the point is lit as the normal says, with no stair-step dark bands where
// the flat facets would shadow each other (the shading-point offset of Hanika).
TEST(Robustness, LowPolySmoothSphereShowsNoShadowTerminatorSteps) {
  Scene scene;
  Material white;
  white.ambient = 0.0f;
  add_object(&scene, "sphere", smooth_sphere(8, 12), white);
  Light sun;
  sun.type = LightType::kSun;
  sun.color = Color(3.0f);
  sun.direction = glm::normalize(Vec3(-1.0f, 0.0f, -0.15f));  // grazing the camera's view
  scene.set_light("sun", sun);
  scene.camera = looking_down(Vec3(0.0f, 0.0f, 6.0f), 0.2f);
  const auto compiled = scene.compile();
  const WhittedIntegrator integrator(*compiled, Settings{});
  RayCounts counts;
  int lit = 0;
  int dark = 0;
  const int size = 120;
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const Ray ray = scene.camera.generate_ray((x + 0.5f) / size, (y + 0.5f) / size);
      Hit hit;
      if (!compiled->accel->intersect(ray, &hit)) continue;
      const Interaction it = compiled->interaction(ray, hit);
      const float cos_l = glm::dot(it.shading_normal, -sun.direction);
      if (cos_l < 0.1f) continue;  // only where the smooth surface clearly faces the light
      const float expected = 0.8f * kInvPi * 3.0f * cos_l;
      const float got = integrator.trace(ray, NodeState{}, &counts).x;
      ++lit;
      if (got < 0.5f * expected) ++dark;
    }
  }
  EXPECT_GT(lit, 1000);
  EXPECT_EQ(dark, 0) << "of " << lit << " pixels facing the light";
}

}  // namespace
}  // namespace whitted
