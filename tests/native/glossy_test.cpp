// Glossy reflection (distributed ray tracing over the GGX lobe, scene/microfacet.h) in
// the integrator: the highlight a lamp gives is the lobe evaluated, a white lobe in a
// white world gains no energy, a lobe tending to a mirror gives the mirror's image, the
// analysis reports it, and the pixels depend on neither threads nor tiles.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "integrator/analysis.h"
#include "integrator/render.h"
#include "integrator/whitted.h"
#include "scene/microfacet.h"
#include "scene_builders.h"

namespace whitted {
namespace {

using testing::add_object;
using testing::emitter;
using testing::looking_down;
using testing::quad;
using testing::render_pixels;

Material rough_metal(float roughness, Color colour = Color(1.0f)) {
  Material m;
  m.diffuse = Color(0.0f);
  m.specular = Color(0.0f);
  m.ambient = 0.0f;
  m.reflectivity = colour;
  m.roughness = roughness;
  return m;
}

// A point lamp far from the mirror direction of a very rough metal still lights it, by
// exactly the GGX lobe (the Phong lobe clamped at exponent 1 gave almost nothing there).
TEST(Glossy, ALampsHighlightIsTheLobeEvaluated) {
  for (const float roughness : {0.3f, 1.0f}) {
    Scene scene;
    add_object(&scene, "floor", quad(-20, 20, -20, 20, 0), rough_metal(roughness, Color(0.9f)));
    Light light;
    light.color = Color(50.0f);
    light.position = Vec3(-3.0f, 0.0f, 1.0f);  // low on the left
    scene.set_light("light", light);
    scene.set_background(Color(0.0f));
    const auto compiled = scene.compile();
    Settings settings;
    settings.max_depth = 0;  // the lamp alone
    const WhittedIntegrator integrator(*compiled, settings);
    RayCounts counts;
    // Seen from high on the left: the lamp is more than 90 degrees from the mirror
    // direction of the view.
    const Vec3 origin(-1.0f, 0.0f, 3.0f);
    const Vec3 target(0.5f, 0.2f, 0.0f);
    const Ray ray{origin, glm::normalize(target - origin), 0.0f, kInfinity};
    const float got = integrator.trace(ray, NodeState{}, &counts).x;
    const Vec3 n(0.0f, 0.0f, 1.0f);
    const Vec3 wo = -ray.direction;
    const Vec3 to_light = light.position - target;
    const float d2 = glm::dot(to_light, to_light);
    const Vec3 wi = to_light / std::sqrt(d2);
    ASSERT_LT(glm::dot(wi, reflect(-wo, n)), 0.0f) << "the lamp is not far from the mirror";
    // Irradiance on a surface facing the lamp: I / d^2.
    const float expected =
        0.9f * ggx_reflection(GgxLobe(n, roughness * roughness), wo, wi) * 50.0f / d2;
    EXPECT_GT(expected, 1e-3f) << roughness;
    EXPECT_NEAR(got, expected, 1e-4f * expected + 1e-7f) << "roughness " << roughness;
  }
}

// A white furnace for glossy rays: a white rough metal plane under a uniform white world
// returns at most what arrives; single scattering loses more as roughness grows, and
// Multiscatter GGX's energy scale gives it back.
TEST(Glossy, AWhiteLobeInAWhiteWorldGainsNoEnergy) {
  for (const bool multiscatter : {false, true}) {
    for (const float roughness : {0.1f, 0.3f, 0.6f, 1.0f}) {
      Scene scene;
      Material white = rough_metal(roughness);
      white.multiscatter = multiscatter;
      add_object(&scene, "floor", quad(-1000, 1000, -1000, 1000, 0), white);
      scene.set_background(Color(1.0f));
      scene.camera = looking_down(Vec3(0.0f, 0.0f, 3.0f), 2.0f);
      const auto compiled = scene.compile();
      Settings settings;
      settings.glossy_samples = 8;
      settings.cutoff = 0.0f;
      const WhittedIntegrator integrator(*compiled, settings);
      RayCounts counts;
      double sum = 0.0;
      const int n = 16;
      for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
          const Ray ray = scene.camera.generate_ray((x + 0.5f) / n, (y + 0.5f) / n);
          NodeState sample;
          sample.seed =
              hash3(static_cast<uint32_t>(x), static_cast<uint32_t>(y), 0u);  // as the sampler
          const Color c = integrator.trace(ray, sample, &counts);
          ASSERT_TRUE(is_finite(c));
          // Each sample of a single-scattering lobe weighs G2/G1 <= 1; the energy scale
          // makes them up to 1/E (1 on average).
          const float bound = multiscatter ? 1.0f / ggx_albedo(-ray.direction.z, roughness) : 1.0f;
          EXPECT_LE(max_component(c), bound + 1e-5f) << roughness;
          EXPECT_GE(c.x, 0.0f);
          sum += c.x;
        }
      }
      const double mean = sum / (n * n);
      // Single scattering keeps 0.99 at roughness 0.1, 0.43 at 1 (measured here).
      const double least = multiscatter ? 0.97 : roughness <= 0.3f ? 0.9 : 0.4;
      EXPECT_GT(mean, least) << "roughness " << roughness << " multiscatter " << multiscatter;
      if (multiscatter) EXPECT_LT(mean, 1.02) << "roughness " << roughness;
      EXPECT_LE(counts.glossy, static_cast<uint64_t>(n * n * 64));
      EXPECT_GT(counts.glossy, static_cast<uint64_t>(n * n * 32));
      EXPECT_EQ(counts.reflection, 0u);
    }
  }
}

// Roughness towards 0: the glossy image of an emitter tends to the mirror's.
TEST(Glossy, ALobeTendingToAMirrorGivesTheMirrorsImage) {
  const auto render = [](float roughness) {
    Scene scene;
    add_object(&scene, "floor", quad(-20, 20, -20, 20, 0), rough_metal(roughness, Color(0.8f)));
    // An emissive panel: its feelers and their MIS weights are drawn the same way.
    add_object(&scene, "panel", quad(-0.5f, 0.5f, -0.5f, 0.5f, 2.0f),
               emitter(Color(3.0f), EmissionSampling::kBoth));
    scene.set_background(Color(0.1f));
    scene.camera = looking_down(Vec3(0.0f, 0.0f, 1.0f), 1.0f);
    const auto compiled = scene.compile();
    Settings settings;
    settings.glossy_samples = 4;
    const WhittedIntegrator integrator(*compiled, settings);
    RayCounts counts;
    std::vector<float> image;
    const int n = 32;
    for (int y = 0; y < n; ++y) {
      for (int x = 0; x < n; ++x) {
        NodeState sample;
        sample.seed = hash3(static_cast<uint32_t>(x), static_cast<uint32_t>(y), 0u);
        const Ray ray = scene.camera.generate_ray((x + 0.5f) / n, (y + 0.5f) / n);
        image.push_back(integrator.trace(ray, sample, &counts).x);
      }
    }
    return image;
  };
  const std::vector<float> mirror = render(0.0f);
  double previous = 1e9;
  for (const float roughness : {0.4f, 0.2f, 0.1f, 0.04f}) {
    const std::vector<float> glossy = render(roughness);
    double difference = 0.0;
    for (size_t i = 0; i < mirror.size(); ++i) difference += std::fabs(glossy[i] - mirror[i]);
    difference /= static_cast<double>(mirror.size());
    EXPECT_LT(difference, previous) << "roughness " << roughness;
    previous = difference;
  }
  EXPECT_LT(previous, 0.05);
}

// A rough clear coat (plastic's specular layer): its lobe, weighted by the Fresnel factor
// (4% at normal incidence), reflects the world. Split over 6 x 6 rays, each ray's share
// is below the cutoff; the lobe's is not, so all are traced (each used to be cut).
TEST(Glossy, ARoughCoatReflectsTheWorldThoughEachRayIsBelowTheCutoff) {
  for (const float roughness : {0.0f, 0.5f}) {
    Scene scene;
    Material plastic;
    plastic.diffuse = Color(0.0f);
    plastic.ambient = 0.0f;
    plastic.coat_reflectivity = 1.0f;
    plastic.coat_ior = 1.5f;
    plastic.coat_roughness = roughness;
    add_object(&scene, "floor", quad(-100, 100, -100, 100, 0), plastic);
    scene.set_background(Color(0.5f));
    const auto compiled = scene.compile();
    Settings settings;
    settings.glossy_samples = 6;
    const WhittedIntegrator integrator(*compiled, settings);
    RayCounts counts;
    const Ray ray{Vec3(0.0f, 0.0f, 2.0f), Vec3(0.0f, 0.0f, -1.0f), 0.0f, kInfinity};
    const float got = integrator.trace(ray, NodeState{}, &counts).x;
    // ((1.5 - 1) / (1.5 + 1))^2 = 0.04 of the world's 0.5; the rough lobe keeps less of
    // it (single scattering, its facets' Fresnel factors; 36 rays of one sample). Cut, it
    // gave 0.
    if (roughness > 0.0f) {
      EXPECT_GT(got, 0.014f);
      EXPECT_LT(got, 0.021f);
    } else {
      EXPECT_NEAR(got, 0.02f, 1e-6f);
    }
    EXPECT_EQ(counts.cutoff_skipped, 0u);
    if (roughness > 0.0f) EXPECT_GE(counts.glossy, 25u);  // the rest fell below the surface
  }
}

// Frosted glass: a rough slab seen from above against a white world passes at most what
// arrives, blurs (its rays are glossy ones), and a camera inside it looking out past the
// critical angle gets finite, non-negative values from facets that totally reflect.
TEST(Glossy, FrostedGlassTransmitsNoMoreThanArrivesAndStaysFiniteInside) {
  for (const float roughness : {0.0f, 0.3f, 0.8f}) {
    Scene scene;
    Material glass = testing::clear(1.5f);
    glass.roughness = roughness;
    // A slab between z = -0.5 and 0.5: its top faces up, its bottom down.
    add_object(&scene, "top", quad(-50, 50, -50, 50, 0.5f), glass);
    add_object(&scene, "bottom", quad(-50, 50, -50, 50, -0.5f), glass,
               glm::rotate(glm::mat4(1.0f), kPi, Vec3(1.0f, 0.0f, 0.0f)));
    scene.set_background(Color(1.0f));
    const auto compiled = scene.compile();
    Settings settings;
    settings.glossy_samples = 4;
    settings.max_depth = 8;
    const WhittedIntegrator integrator(*compiled, settings);
    RayCounts counts;
    NodeState from_above;
    from_above.seed = 7;
    const Ray down{Vec3(0.1f, 0.2f, 3.0f), glm::normalize(Vec3(0.05f, 0.0f, -1.0f)), 0.0f,
                   kInfinity};
    const Color c = integrator.trace(down, from_above, &counts);
    ASSERT_TRUE(is_finite(c));
    EXPECT_LE(max_component(c), 1.0f + 1e-5f) << roughness;
    EXPECT_GT(c.x, roughness > 0.5f ? 0.3f : 0.8f) << roughness;
    if (roughness > 0.0f) EXPECT_GT(counts.glossy, 0u);
    // Inside, looking out at 60 degrees (past the critical angle of 41.8): a smooth
    // slab reflects it all; rough facets let some out.
    NodeState inside;
    inside.media = integrator.media_at(Vec3(0.0f));
    inside.seed = 11;
    const Ray out{Vec3(0.0f), glm::normalize(Vec3(std::sqrt(3.0f), 0.0f, 1.0f)), 0.0f, kInfinity};
    const Color d = integrator.trace(out, inside, &counts);
    ASSERT_TRUE(is_finite(d)) << roughness;
    EXPECT_GE(d.x, 0.0f);
    EXPECT_LE(max_component(d), 1.0f + 1e-5f);
  }
}

TEST(Glossy, TheAnalysisNamesTheGlossyMaterials) {
  Scene scene;
  add_object(&scene, "rough", quad(-1, 1, -1, 1, 0), rough_metal(0.5f));
  add_object(&scene, "mirror", quad(2, 3, -1, 1, 0), rough_metal(0.0f));
  const auto compiled = scene.compile();
  const Effects effects = analyse(*compiled, Settings{});
  EXPECT_TRUE(effects.has(kGlossyEffect));
  bool named = false;
  for (const EffectDecision& d : effects.decisions) {
    if (d.name == "glossy reflection") {
      named = true;
      EXPECT_TRUE(d.on);
      EXPECT_EQ(d.why, "1 material rough above 0.02");
    }
  }
  EXPECT_TRUE(named);
  Scene plain;
  add_object(&plain, "mirror", quad(2, 3, -1, 1, 0), rough_metal(0.01f));
  EXPECT_FALSE(analyse(*plain.compile(), Settings{}).has(kGlossyEffect));
}

// Glossy rays and emitter feelers are drawn from a hash of the camera sample, never from
// a thread's state: the same pixels on any thread count and tile size.
TEST(Glossy, ThePixelsDependOnNeitherThreadsNorTiles) {
  Scene scene;
  add_object(&scene, "floor", quad(-20, 20, -20, 20, 0), rough_metal(0.35f, Color(0.8f)));
  // An emissive panel: its feelers and their MIS weights are drawn the same way.
  add_object(&scene, "panel", quad(-0.5f, 0.5f, -0.5f, 0.5f, 2.0f),
             emitter(Color(3.0f), EmissionSampling::kBoth));
  Light light;
  light.color = Color(20.0f);
  light.position = Vec3(1.0f, 1.0f, 3.0f);
  scene.set_light("light", light);
  scene.set_background(Color(0.2f));
  scene.camera = looking_down(Vec3(0.3f, 0.0f, 1.5f), 1.0f);
  Settings settings;
  settings.width = 41;
  settings.height = 29;
  settings.aa_samples = 2;
  settings.glossy_samples = 3;
  settings.threads = 1;
  settings.tile_size = 64;
  const std::vector<float> reference = render_pixels(scene, settings);
  for (auto [threads, tile] : {std::pair{2, 5}, std::pair{3, 16}}) {
    settings.threads = threads;
    settings.tile_size = tile;
    EXPECT_TRUE(render_pixels(scene, settings) == reference)
        << threads << " threads, tile " << tile;
  }
}

}  // namespace
}  // namespace whitted
