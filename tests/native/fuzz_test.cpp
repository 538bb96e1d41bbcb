// Randomized ("fuzz") test of the scene-building API, intersection and shading math:
// whatever finite or non-finite input arrives, no crash, no NaN or Inf pixel, and bad
// input is refused with std::invalid_argument. WHITTED_FUZZ_ITERATIONS sets the number
// of random scenes (a short run in the suite; `python -m whitted_tools fuzz` runs a long one).
#include <gtest/gtest.h>

#include <cstdlib>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <random>
#include <stdexcept>

#include "integrator/render.h"
#include "scene_builders.h"

namespace whitted {
namespace {

int iterations() {
  const char* env = std::getenv("WHITTED_FUZZ_ITERATIONS");
  return env != nullptr ? std::max(1, std::atoi(env)) : 60;
}

class Fuzzer {
 public:
  explicit Fuzzer(uint32_t seed) : rng_(seed) {}

  // A float from a mix of ordinary, extreme, tiny, denormal and non-finite values.
  float value() {
    switch (pick(12)) {
      case 0:
        return std::numeric_limits<float>::quiet_NaN();
      case 1:
        return pick(2) ? kInfinity : -kInfinity;
      case 2:
        return std::numeric_limits<float>::denorm_min() * static_cast<float>(pick(100));
      case 3:
        return (pick(2) ? 1.0f : -1.0f) * std::pow(10.0f, static_cast<float>(pick(77)) - 38.0f);
      case 4:
        return 0.0f;
      default:
        return uniform(-10.0f, 10.0f);
    }
  }
  // Mostly sane, sometimes wild.
  float sane_or_wild(float lo, float hi) { return pick(8) == 0 ? value() : uniform(lo, hi); }
  Vec3 vec(float lo, float hi) {
    return {sane_or_wild(lo, hi), sane_or_wild(lo, hi), sane_or_wild(lo, hi)};
  }
  int pick(int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng_); }
  float uniform(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng_); }

 private:
  std::mt19937 rng_;
};

Material random_material(Fuzzer& f) {
  Material m;
  m.diffuse = glm::abs(f.vec(0.0f, 1.0f));
  m.specular = glm::abs(f.vec(0.0f, 1.0f));
  m.shininess = std::fabs(f.sane_or_wild(1.0f, 1000.0f));
  m.reflectivity = glm::abs(f.vec(0.0f, 1.0f));
  m.transmissivity = glm::abs(f.vec(0.0f, 1.0f));
  m.ior = std::fabs(f.sane_or_wild(0.2f, 4.0f));
  m.emission = glm::abs(f.vec(0.0f, 2.0f));
  m.alpha = f.uniform(0.0f, 1.0f);
  m.priority = f.pick(3);
  return m;
}

Light random_light(Fuzzer& f) {
  Light l;
  l.type = static_cast<LightType>(f.pick(4));
  l.color = glm::abs(f.vec(0.0f, 100.0f));
  l.position = f.vec(-10.0f, 10.0f);
  l.direction = f.vec(-1.0f, 1.0f);
  if (!(glm::length(l.direction) > 0.0f) || !is_finite(glm::normalize(l.direction))) {
    l.direction = Vec3(0.0f, 0.0f, -1.0f);
  }
  l.direction = glm::normalize(l.direction);
  l.spot_size = f.uniform(0.0f, kPi);
  l.spot_blend = f.uniform(0.0f, 1.0f);
  l.size[0] = std::fabs(f.sane_or_wild(0.0f, 3.0f));
  l.size[1] = std::fabs(f.sane_or_wild(0.0f, 3.0f));
  l.radius = f.pick(2) ? f.uniform(0.0f, 1.0f) : 0.0f;
  l.angle = f.pick(2) ? f.uniform(0.0f, 1.0f) : 0.0f;
  l.samples = 1 + f.pick(3);
  l.shape = static_cast<AreaShape>(f.pick(2));
  return l;
}

// Only finite light and material values reach the core through the bindings (they
// check); the core itself must stay finite for any finite input.
bool finite_light(const Light& l) {
  return is_finite(l.color) && is_finite(l.position) && std::isfinite(l.size[0]) &&
         std::isfinite(l.size[1]);
}

TEST(Fuzz, RandomScenesNeverCrashOrProduceNonFinitePixels) {
  const int n = iterations();
  int rendered = 0;
  int refused = 0;
  // WHITTED_FUZZ_FIRST starts at a later scene: replays a failure a long run found.
  const char* first_env = std::getenv("WHITTED_FUZZ_FIRST");
  const int first = first_env != nullptr ? std::max(0, std::atoi(first_env)) : 0;
  for (int iteration = first; iteration < first + n; ++iteration) {
    Fuzzer f(static_cast<uint32_t>(iteration) * 2654435761u + 17u);
    Scene scene;
    const int meshes = 1 + f.pick(3);
    for (int k = 0; k < meshes; ++k) {
      const int vertices = 3 + f.pick(12);
      const int triangles = 1 + f.pick(12);
      std::vector<float> p;
      for (int i = 0; i < 3 * vertices; ++i) p.push_back(f.sane_or_wild(-3.0f, 3.0f));
      std::vector<uint32_t> t;
      for (int i = 0; i < 3 * triangles; ++i) {
        t.push_back(static_cast<uint32_t>(f.pick(vertices + (f.pick(20) == 0 ? 3 : 0))));
      }
      std::vector<float> normals;
      for (int i = 0; i < 9 * triangles; ++i) normals.push_back(f.sane_or_wild(-1.0f, 1.0f));
      const std::string name = "m" + std::to_string(k);
      try {
        scene.set_mesh(name, make_mesh(p.data(), vertices, t.data(), triangles,
                                       f.pick(2) ? normals.data() : nullptr, nullptr));
      } catch (const std::invalid_argument&) {
        ++refused;  // NaN vertices, bad indices: refused with a message
        continue;
      }
      scene.set_material(name, random_material(f));
      glm::mat4 xf = glm::translate(glm::mat4(1.0f), f.vec(-2.0f, 2.0f));
      xf = glm::scale(xf, f.vec(-2.0f, 2.0f));
      try {
        scene.set_instance(name, Instance{name, xf, {name}});
      } catch (const std::invalid_argument&) {
        ++refused;  // NaN or infinite transform
      }
    }
    for (int k = 0; k < 2; ++k) {
      const Light light = random_light(f);
      if (finite_light(light)) scene.set_light("l" + std::to_string(k), light);
    }
    scene.set_ambient(glm::abs(f.vec(0.0f, 0.5f)));
    scene.set_background(Color(0.2f));
    scene.camera.to_world = glm::translate(glm::mat4(1.0f), Vec3(0.0f, 0.0f, 8.0f));
    scene.camera.projection = f.pick(2) ? Projection::kPerspective : Projection::kOrthographic;
    Settings settings;
    settings.width = 12;
    settings.height = 9;
    settings.max_depth = f.pick(12);
    settings.fresnel = static_cast<Fresnel>(f.pick(3));
    settings.cutoff = f.pick(2) ? 0.0f : 1.0f / 255.0f;
    settings.threads = 1;
    RenderJob job(scene, settings, scene.camera);
    testing::run_to_end(job);
    for (float v : job.film().pixels()) ASSERT_TRUE(std::isfinite(v)) << "iteration " << iteration;
    ++rendered;
  }
  EXPECT_EQ(rendered, n);  // iterations first .. first + n - 1
  EXPECT_GT(refused, 0);   // the generator does produce bad input
}

TEST(Fuzz, ShadingMathStaysFiniteForFiniteInput) {
  Fuzzer f(7);
  const int n = 2000 * iterations();
  for (int i = 0; i < n; ++i) {
    const Vec3 u = glm::normalize(Vec3(f.uniform(-1, 1), f.uniform(-1, 1), f.uniform(-1, 1)));
    const Vec3 nrm = glm::normalize(Vec3(f.uniform(-1, 1), f.uniform(-1, 1), f.uniform(-1, 1)));
    if (!is_finite(u) || !is_finite(nrm)) continue;
    const float eta = f.uniform(0.05f, 20.0f);
    const Vec3 facing = glm::dot(u, nrm) < 0.0f ? nrm : -nrm;
    Vec3 t(0.0f);
    if (refract(u, facing, eta, &t)) ASSERT_TRUE(is_finite(t));
    ASSERT_TRUE(is_finite(reflect(u, facing)));
    const float c = f.uniform(-0.1f, 1.1f);
    const float fe = fresnel_exact(c, eta);
    const float fs = fresnel_schlick(std::clamp(c, 0.0f, 1.0f), eta);
    ASSERT_TRUE(std::isfinite(fe) && fe >= 0.0f && fe <= 1.0f) << c << " " << eta;
    ASSERT_TRUE(std::isfinite(fs) && fs >= 0.0f && fs <= 1.0f) << c << " " << eta;
    const Vec3 p = f.vec(-1e6f, 1e6f);
    if (!is_finite(p)) continue;
    const Vec3 q = offset_ray_origin(p, Vec3(gamma(7) * max_component(glm::abs(p))), facing);
    ASSERT_TRUE(is_finite(q));
  }
}

}  // namespace
}  // namespace whitted
