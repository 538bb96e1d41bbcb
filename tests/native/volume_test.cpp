// Homogeneous media (integrator/volume.h, issue 48): a slab's transmittance, a point
// lamp's single scattering in an effectively infinite medium against the line integral,
// density 0 and a huge density, glass with a volume, and a fog box rendered the same
// whatever the threads and tiles. Heterogeneous media (heterogeneous.h, march.h): a
// program of constant value against the homogeneous medium, a density ramp's
// transmittance against exp(-integral). Volume objects' grids (scene/volume_object.h): a
// block of voxels against exp(-depth), in object and world space; Cycles' step and density
// scale; the box rays enter through.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "integrator/analysis.h"
#include "integrator/render.h"
#include "integrator/volume.h"
#include "program_builder.h"
#include "scene_builders.h"

namespace whitted {
namespace {

using testing::add_object;
using testing::box;
using testing::fog;
using testing::looking_down;
using testing::make;
using testing::quad;
using testing::small_render;

struct Rendered {
  std::vector<float> pixels;
  RenderStats stats;
};

Rendered render(const Scene& scene, const Settings& settings) {
  RenderJob job(scene, settings, scene.camera);
  testing::run_to_end(job);
  return {job.film().pixels(), job.stats()};
}

// One pixel looking straight down -z from `eye`: its one ray is the camera's axis.
Settings one_ray(int samples) {
  Settings settings = small_render(1, 1, samples, 2, 8);
  settings.aa_mode = AntiAliasing::kJittered;
  return settings;
}

TEST(Volume, SlabTransmittanceIsExpOfMinusSigmaTTimesDepth) {
  const Color sigma_a(0.5f, 1.0f, 2.0f);
  for (const float depth : {0.1f, 0.7f, 2.5f}) {
    Scene scene;
    scene.set_background(Color(1.0f));
    // Narrow about the camera's axis: each bound's crossing starts the next segment off the
    // face by its rounding error bound, which grows with the vertices' coordinates (4e-5
    // of length at +-50, ray.h's offset_ray_origin).
    add_object(&scene, "slab", box(Vec3(-1.0f, -1.0f, 1.0f), Vec3(1.0f, 1.0f, 1.0f + depth)),
               fog(sigma_a, Color(0.0f)));
    scene.camera = looking_down(Vec3(0.0f, 0.0f, 5.0f), 1e-5f);
    const Rendered r = render(scene, one_ray(1));
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(r.pixels[static_cast<size_t>(c)], std::exp(-sigma_a[c] * depth), 1e-5f)
          << "depth " << depth << " channel " << c;
    }
  }
}

// A glowing box (emission e, nothing absorbed) over a white Lambert floor lights the
// floor with its emission over its volume: E = e * integral cos / r^2 dV (a midpoint sum
// in double precision). The camera, looking down through the box onto the floor's
// origin, sees that (E / pi) and the box's own glow along its depth (e * h).
TEST(Volume, AGlowingBoxLightsTheFloorUnderIt) {
  const Color e(0.6f, 0.3f, 0.1f);
  const Vec3 lo(-0.5f, -0.7f, 1.0f);
  const Vec3 hi(0.7f, 0.5f, 1.8f);
  Scene scene;
  add_object(&scene, "glow", box(lo, hi), fog(Color(0.0f), Color(0.0f), 0.0f, e));
  Material white;
  white.diffuse = Color(1.0f);
  white.ambient = 0.0f;
  add_object(&scene, "floor", quad(-50.0f, 50.0f, -50.0f, 50.0f, 0.0f), white);
  scene.camera = looking_down(Vec3(0.0f, 0.0f, 5.0f), 1e-5f);
  Settings settings = one_ray(32);
  settings.emitter_samples = 4;
  const Rendered r = render(scene, settings);
  const int n = 120;
  const glm::dvec3 size = glm::dvec3(hi - lo);
  const glm::dvec3 cell = size / static_cast<double>(n);
  double integral = 0.0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      for (int k = 0; k < n; ++k) {
        const glm::dvec3 x = glm::dvec3(lo) + (glm::dvec3(i, j, k) + 0.5) * cell;
        const double r2 = glm::dot(x, x);
        integral += x.z / (r2 * std::sqrt(r2));
      }
    }
  }
  integral *= cell.x * cell.y * cell.z;
  EXPECT_GT(r.stats.rays.volume_feelers, 0u);
  for (int c = 0; c < 3; ++c) {
    const double expected = e[c] * (hi.z - lo.z) + e[c] * integral / std::numbers::pi;
    EXPECT_NEAR(r.pixels[static_cast<size_t>(c)], expected, 0.01 * expected) << c;
  }
}

// The single-scatter radiance reaching the origin along -z from a point lamp of intensity
// I at c = (D, 0, -h) in a medium filling [-L, L]^3: the line integral
//   L = int_0^L exp(-sigma_t t) sigma_s p(cos) I exp(-sigma_t r) / r^2 dt,
//   r = |x(t) - c|, x(t) = (0, 0, -t), cos the angle between the light's way to x and -z,
// by Simpson's rule in double precision (2e5 intervals).
double line_integral(double sigma_s, double sigma_t, double g, double intensity, double d, double h,
                     double length) {
  const int n = 200000;
  const double step = length / n;
  double sum = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double t = i * step;
    const double dz = -h + t;  // c - x along z
    const double r2 = d * d + dz * dz;
    const double r = std::sqrt(r2);
    const double cos_theta = -dz / r;  // wi . (0, 0, -1), wi = (c - x) / r
    const double denominator = 1.0 + g * g - 2.0 * g * cos_theta;
    const double phase = (1.0 - g * g) / (4.0 * M_PI * denominator * std::sqrt(denominator));
    const double f =
        std::exp(-sigma_t * t) * sigma_s * phase * intensity * std::exp(-sigma_t * r) / r2;
    sum += f * (i == 0 || i == n ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0));
  }
  return sum * step / 3.0;
}

TEST(Volume, PointLampSingleScatteringMatchesTheLineIntegral) {
  const float half = 1000.0f;  // effectively infinite: the camera's ray leaves at t = 1000
  struct Case {
    float sigma_a, sigma_s, g, tolerance;
  };
  // Without extinction and isotropic, equiangular sampling has no variance at all.
  for (const Case k : {Case{0.0f, 0.05f, 0.0f, 1e-4f}, Case{0.03f, 0.1f, 0.0f, 0.01f},
                       Case{0.02f, 0.1f, 0.6f, 0.01f}, Case{0.02f, 0.1f, -0.4f, 0.01f}}) {
    SCOPED_TRACE(::testing::Message()
                 << "sigma_a " << k.sigma_a << " sigma_s " << k.sigma_s << " g " << k.g);
    Scene scene;
    add_object(&scene, "medium", box(Vec3(-half), Vec3(half)),
               fog(Color(k.sigma_a), Color(k.sigma_s), k.g));
    Light lamp;
    lamp.color = Color(10.0f);
    lamp.position = Vec3(1.0f, 0.0f, -3.0f);
    scene.set_light("lamp", lamp);
    scene.camera = looking_down(Vec3(0.0f), 1e-5f);
    const Rendered r = render(scene, one_ray(32));
    const double expected =
        line_integral(k.sigma_s, k.sigma_a + k.sigma_s, k.g, 10.0, 1.0, 3.0, half);
    EXPECT_NEAR(r.pixels[0] / expected, 1.0, k.tolerance) << r.pixels[0] << " " << expected;
    EXPECT_EQ(r.stats.rays.nonfinite_samples, 0u);
    EXPECT_GT(r.stats.rays.volume_feelers, 0u);
  }
}

// A floor lit by a point lamp, seen from above, with a box around the floor's middle.
Scene floor_scene() {
  Scene scene;
  Material white;
  white.ambient = 0.0f;
  add_object(&scene, "floor", quad(-20, 20, -20, 20, 0), white);
  Light light;
  light.color = Color(30.0f);
  light.position = Vec3(0.5f, 0.3f, 4.0f);
  scene.set_light("light", light);
  scene.camera = looking_down(Vec3(0.0f, 0.0f, 6.0f), 0.8f);
  return scene;
}

// The Whitted Rays pass counts what fog costs: the feelers from its scatter points (among
// the shadow rays) and the rays going on behind its bounds and walking feelers through
// them; every pixel's camera rays cross the fog box's top.
TEST(Volume, TheCostPassCountsTheRaysOfTheFog) {
  const Scene scene = testing::foggy_glass_and_mirror_scene(Color(0.1f));
  RenderJob job(scene, small_render(16, 16, 2, 2, 8), scene.camera);
  testing::run_to_end(job);
  const RayCounts& rays = job.stats().rays;
  EXPECT_GT(rays.volume_feelers, 0u);
  EXPECT_GT(rays.volume_bounds, 0u);
  EXPECT_GT(rays.volume_queries, 0u);
  EXPECT_EQ(rays.total(), rays.camera + rays.shadow + rays.reflection + rays.refraction +
                              rays.glossy + rays.transparent + rays.volume_bounds +
                              rays.volume_queries);
  double cost = 0.0;
  float least = kInfinity;
  for (const float c : job.film().cost()) {
    cost += c;
    least = std::min(least, c);
  }
  EXPECT_EQ(cost, static_cast<double>(rays.total()));
  EXPECT_GE(least, 4.0f * 2.0f);  // 4 camera rays, each going on behind the bound
}

TEST(Volume, DensityZeroIsNoMediumAtAll) {
  const Scene without = floor_scene();
  Scene with = without;
  add_object(&with, "fog", box(Vec3(-2.0f, -2.0f, -1.0f), Vec3(2.0f, 2.0f, 5.0f)),
             fog(Color(0.0f), Color(0.0f)));
  const Settings settings = small_render(16, 16, 2, 2, 8);
  const Rendered a = render(with, settings);
  const Rendered b = render(without, settings);
  ASSERT_EQ(a.pixels, b.pixels);
  EXPECT_EQ(a.stats.rays.total(), b.stats.rays.total());
  for (const EffectDecision& d : a.stats.effects) {
    if (d.name == "volumes") EXPECT_FALSE(d.on) << d.why;
  }
}

TEST(Volume, HugeDensityIsOpaqueWithoutNaN) {
  for (const float density : {1e6f, 1e20f, 1e30f}) {
    SCOPED_TRACE(density);
    Scene scene = floor_scene();
    // Around the lamp and the floor's middle: the camera's rays and the lamp's feelers cross it.
    add_object(&scene, "fog", box(Vec3(-1.0f, -1.0f, -1.0f), Vec3(1.0f, 1.0f, 5.0f)),
               fog(Color(density), Color(density)));
    const Rendered r = render(scene, small_render(16, 16, 2, 2, 8));
    EXPECT_EQ(r.stats.rays.nonfinite_samples, 0u);
    float brightest_outside = 0.0f;
    for (int y = 0; y < 16; ++y) {
      for (int x = 0; x < 16; ++x) {
        const size_t at = (static_cast<size_t>(y) * 16 + static_cast<size_t>(x)) * 4;
        for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(r.pixels[at + c]));
        // The middle pixels look through the box's top: nothing gets through it.
        if (x >= 6 && x < 10 && y >= 6 && y < 10) {
          for (int c = 0; c < 3; ++c) EXPECT_LT(r.pixels[at + c], 1e-6f) << x << " " << y;
        } else {
          brightest_outside = std::max(brightest_outside, r.pixels[at]);
        }
      }
    }
    // Outside it the floor is dark too: the lamp is inside the box.
    EXPECT_LT(brightest_outside, 1e-6f);
  }
}

TEST(Volume, AbsorbingFogDimsTheLampOnTheFloorAsTheLineSays) {
  // The lamp above a fog layer: the floor under it gets exp(-sigma_t d) of the light whose
  // feeler crosses d of fog, seen through the same layer again by the camera.
  const float sigma = 0.4f;
  Scene without = floor_scene();
  without.camera = looking_down(Vec3(0.5f, 0.3f, 6.0f), 1e-5f);
  Scene with = without;
  add_object(&with, "fog", box(Vec3(-10.0f, -10.0f, 1.0f), Vec3(10.0f, 10.0f, 2.0f)),
             fog(Color(sigma), Color(0.0f)));
  const Rendered a = render(with, one_ray(1));
  const Rendered b = render(without, one_ray(1));
  EXPECT_NEAR(a.pixels[0] / b.pixels[0], std::exp(-2.0f * sigma), 1e-5f);
}

TEST(Volume, AFogBoxStandingOnTheFloorRendersAsOneSunkIntoIt) {
  // The fog box's bottom face in the floor's plane, given in place or placed there by its
  // instance's transform (as Blender's objects are): a camera ray reaching the floor meets
  // two coplanar faces, and if it crossed the bound first, going on from beyond it, it
  // would miss the floor and see the world. The floor is met first, so the images are
  // those of a box whose bottom is 1 below the floor, hidden.
  const Material absorbing = fog(Color(0.2f), Color(0.1f));
  Scene sunk = floor_scene();
  add_object(&sunk, "fog", box(Vec3(-2.0f, -2.0f, -1.0f), Vec3(2.0f, 2.0f, 5.0f)), absorbing);
  Scene in_place = floor_scene();
  add_object(&in_place, "fog", box(Vec3(-2.0f, -2.0f, 0.0f), Vec3(2.0f, 2.0f, 5.0f)), absorbing);
  Scene placed = floor_scene();
  add_object(&placed, "fog", box(Vec3(-2.0f, -2.0f, -2.5f), Vec3(2.0f, 2.0f, 2.5f)), absorbing,
             glm::translate(glm::mat4(1.0f), Vec3(0.0f, 0.0f, 2.5f)));
  const Settings settings = small_render(16, 16, 2, 2, 8);
  const Rendered reference = render(sunk, settings);
  for (const Scene* standing : {&in_place, &placed}) {
    const Rendered r = render(*standing, settings);
    for (size_t i = 0; i < r.pixels.size(); ++i) {
      EXPECT_NEAR(r.pixels[i], reference.pixels[i], 1e-4f * (1.0f + reference.pixels[i])) << i;
    }
  }
}

TEST(Volume, GlassWithAVolumeAbsorbsAlongTheRefractedRay) {
  // A slab of glass of index 1 (no bending, no Fresnel loss worth counting at normal
  // incidence: 0) whose material also holds an absorbing volume: what passes is exp(-sigma d).
  Scene scene;
  scene.set_background(Color(1.0f));
  MaterialParams glass = testing::clear(1.0f);
  glass.volume_absorption = Color(0.3f, 0.6f, 0.9f);
  add_object(&scene, "glass", box(Vec3(-50.0f, -50.0f, 1.0f), Vec3(50.0f, 50.0f, 2.0f)),
             Material(glass));
  scene.camera = looking_down(Vec3(0.0f, 0.0f, 5.0f), 1e-5f);
  const Rendered r = render(scene, one_ray(1));
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(r.pixels[static_cast<size_t>(c)], std::exp(-glass.volume_absorption[c]), 1e-5f)
        << c;
  }
}

TEST(Volume, FogGoesOnInsideGlassAndOverlappingFogsAddUp) {
  // Down the camera's axis: an absorbing fog from z = 0.5 to 3.5 around a slab of glass of
  // index 1 (z from 1 to 2, no volume of its own) and a second fog from 2.5 to 3 inside the
  // first: the ray crosses 3 of the first fog, the glass included (Cycles fills it with the
  // volumes around it), and 0.5 of both.
  const Color first(0.3f, 0.2f, 0.1f);
  const Color second(0.4f, 0.0f, 0.8f);
  Scene scene;
  scene.set_background(Color(1.0f));
  add_object(&scene, "fog", box(Vec3(-1.0f, -1.0f, 0.5f), Vec3(1.0f, 1.0f, 3.5f)),
             fog(first, Color(0.0f)));
  add_object(&scene, "denser", box(Vec3(-1.0f, -1.0f, 2.5f), Vec3(1.0f, 1.0f, 3.0f)),
             fog(second, Color(0.0f)));
  add_object(&scene, "glass", box(Vec3(-1.0f, -1.0f, 1.0f), Vec3(1.0f, 1.0f, 2.0f)),
             Material(testing::clear(1.0f)));
  scene.camera = looking_down(Vec3(0.0f, 0.0f, 5.0f), 1e-5f);
  const Rendered r = render(scene, one_ray(1));
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(r.pixels[static_cast<size_t>(c)], std::exp(-3.0f * first[c] - 0.5f * second[c]),
                1e-5f)
        << c;
  }
}

TEST(Volume, FogBoxIsTheSameWhateverTheThreadsTilesAndWaves) {
  Scene scene = floor_scene();
  add_object(&scene, "fog", box(Vec3(-2.0f, -2.0f, -1.0f), Vec3(2.0f, 2.0f, 5.0f)),
             fog(Color(0.05f), Color(0.3f), 0.3f));
  Material blocker;
  add_object(&scene, "blocker", quad(-0.5f, 0.5f, -0.5f, 0.5f, 1.5f), blocker);
  Settings settings = small_render(24, 24, 3, 1, 8);
  settings.aa_mode = AntiAliasing::kJittered;
  settings.waves = false;
  const Rendered reference = render(scene, settings);
  settings.threads = 2;
  settings.tile_size = 5;
  EXPECT_EQ(render(scene, settings).pixels, reference.pixels);
  settings.waves = true;
  const Rendered waves = render(scene, settings);
  for (size_t i = 0; i < reference.pixels.size(); ++i) {
    EXPECT_NEAR(waves.pixels[i], reference.pixels[i], 1e-5f * (1.0f + reference.pixels[i])) << i;
  }
  // The fog shows: lit where the lamp's light crosses it, the blocker's shadow cut in it.
  EXPECT_GT(reference.stats.rays.volume_feelers, 0u);
  EXPECT_GT(reference.stats.rays.volume_queries, 0u);
  bool named = false;
  for (const EffectDecision& d : reference.stats.effects) {
    if (d.name == "volumes") named = d.on;
  }
  EXPECT_TRUE(named);
}

// A heterogeneous fog's material: its program computes the medium at each point, here
// sigma_a and sigma_s from the position p: sigma = slope . p + offset per field.
Material programmed_fog(Vec3 absorption_slope, Color absorption_offset, Vec3 scattering_slope,
                        Color scattering_offset, float anisotropy = 0.0f) {
  // r0 the position, r1/r2 the slopes, r3/r4 their dot products with p, r5/r6 the
  // offsets, r7/r8 the sums.
  const auto add = static_cast<uint32_t>(VectorMathOp::kAdd);
  const auto dot = static_cast<uint32_t>(VectorMathOp::kDotProduct);
  MaterialParams m;
  m.surface = false;
  m.volume_anisotropy = anisotropy;
  m.program = std::make_shared<const Program>(
      make({{Op::kInput, kInputPosition, 0},
            {Op::kVectorMath, dot, 3, 0, 1},
            {Op::kVectorMath, dot, 4, 0, 2},
            {Op::kVectorMath, add, 7, 3, 5},
            {Op::kVectorMath, add, 8, 4, 6}},
           {glm::vec4(0.0f), glm::vec4(absorption_slope, 0.0f), glm::vec4(scattering_slope, 0.0f),
            glm::vec4(0.0f), glm::vec4(0.0f), glm::vec4(absorption_offset, 0.0f),
            glm::vec4(scattering_offset, 0.0f), glm::vec4(0.0f), glm::vec4(0.0f)}));
  m.outputs[kVolumeAbsorptionField] = 7;
  m.outputs[kVolumeScatteringField] = 8;
  return Material(m);
}

TEST(HeterogeneousVolume, AProgramOfConstantValueRendersTheHomogeneousMedium) {
  // The fog box of FogBoxIsTheSameWhateverTheThreadsTilesAndWaves, lit by its point lamp
  // and a sun, once with constant coefficients and once with a program computing the
  // same ones everywhere: marched, the same light within float rounding (the steps'
  // exp(-sigma dt) multiply to exp(-sigma d), the lamps' distances are the same draws).
  const Color sigma_a(0.05f, 0.08f, 0.1f);
  const Color sigma_s(0.3f, 0.25f, 0.2f);
  Scene constant = floor_scene();
  Light sun;
  sun.type = LightType::kSun;
  sun.color = Color(2.0f);
  sun.direction = glm::normalize(Vec3(0.3f, 0.2f, -1.0f));
  constant.set_light("sun", sun);
  Material blocker;
  add_object(&constant, "blocker", quad(-0.5f, 0.5f, -0.5f, 0.5f, 1.5f), blocker);
  Scene programmed = constant;
  const Mesh fog_box = box(Vec3(-2.0f, -2.0f, -1.0f), Vec3(2.0f, 2.0f, 5.0f));
  add_object(&constant, "fog", fog_box, fog(sigma_a, sigma_s, 0.3f));
  add_object(&programmed, "fog", fog_box,
             programmed_fog(Vec3(0.0f), sigma_a, Vec3(0.0f), sigma_s, 0.3f));
  Settings settings = small_render(16, 16, 2, 2, 8);
  settings.aa_mode = AntiAliasing::kJittered;
  const Rendered a = render(constant, settings);
  const Rendered b = render(programmed, settings);
  double sum_a = 0.0, sum_b = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    EXPECT_NEAR(b.pixels[i], a.pixels[i], 1e-3f * (1.0f + a.pixels[i])) << i;
    sum_a += a.pixels[i];
    sum_b += b.pixels[i];
  }
  EXPECT_NEAR(sum_b / sum_a, 1.0, 1e-4);
  EXPECT_EQ(a.stats.rays.volume_steps, 0u);
  EXPECT_GT(b.stats.rays.volume_steps, 0u);
  EXPECT_EQ(b.stats.rays.nonfinite_samples, 0u);
  for (const EffectDecision& d : b.stats.effects) {
    if (d.name == "volumes") {
      EXPECT_TRUE(d.on);
      EXPECT_NE(d.why.find("1 object: heterogeneous, ray marched at step rate"), std::string::npos)
          << d.why;
    }
  }
}

TEST(HeterogeneousVolume, ADensityRampLetsThroughExpOfMinusItsIntegral) {
  // A slab from z = 1 to 1 + depth whose absorption grows linearly with height,
  // sigma(z) = a + b (z - 1), seen straight down against a white background:
  // T = exp(-(a depth + b depth^2 / 2)). The march's grid and shade points are drawn per
  // camera sample; 64 of them average its error away (each at most b depth dt / 2).
  const float a = 0.3f, b = 0.8f;
  for (const float depth : {0.5f, 1.5f, 3.0f}) {
    Scene scene;
    scene.set_background(Color(1.0f));
    add_object(&scene, "slab", box(Vec3(-1.0f, -1.0f, 1.0f), Vec3(1.0f, 1.0f, 1.0f + depth)),
               programmed_fog(Vec3(0.0f, 0.0f, b), Color(a - b), Vec3(0.0f), Color(0.0f)));
    scene.camera = looking_down(Vec3(0.0f, 0.0f, 5.0f), 1e-5f);
    Settings settings = one_ray(8);
    settings.volume_step_rate = 0.1f;
    const Rendered r = render(scene, settings);
    const float expected = std::exp(-(a * depth + 0.5f * b * depth * depth));
    EXPECT_NEAR(r.pixels[0], expected, 1e-3f) << "depth " << depth;
    EXPECT_GT(r.stats.rays.volume_steps, 0u);
  }
}

TEST(HeterogeneousVolume, AFeelerThroughADensityRampIsDimmedByExpOfMinusItsIntegral) {
  // The lamp above a slab whose absorption grows with height (as above): the floor under
  // it gets what the feeler lets through, seen through the same slab again by the camera
  // ray; the feeler's march takes each step's midpoint, exact for a linear density.
  const float a = 0.2f, b = 0.5f, depth = 1.0f;
  Scene without = floor_scene();
  without.camera = looking_down(Vec3(0.5f, 0.3f, 6.0f), 1e-5f);
  Scene with = without;
  add_object(&with, "slab", box(Vec3(-10.0f, -10.0f, 1.0f), Vec3(10.0f, 10.0f, 1.0f + depth)),
             programmed_fog(Vec3(0.0f, 0.0f, b), Color(a - b), Vec3(0.0f), Color(0.0f)));
  Settings settings = one_ray(8);
  settings.volume_step_rate = 0.1f;
  const Rendered lit = render(with, settings);
  const Rendered bare = render(without, settings);
  const float once = std::exp(-(a * depth + 0.5f * b * depth * depth));
  EXPECT_NEAR(lit.pixels[0] / bare.pixels[0], once * once, 1e-3f);
}

TEST(HeterogeneousVolume, ACloudIsTheSameWhateverTheThreadsTilesAndWavesAndSeenFromInside) {
  // A fog box whose scattering grows with height, lit by the floor scene's lamp, with a
  // blocker's shadow in it: the march's draws are the camera sample's, so threads, tiles
  // and waves change nothing; a camera inside the box (the media stack seeded with its
  // instance, WhittedIntegrator::media_at) sees it too, and nothing is NaN.
  Scene scene = floor_scene();
  add_object(&scene, "fog", box(Vec3(-2.0f, -2.0f, -1.0f), Vec3(2.0f, 2.0f, 5.0f)),
             programmed_fog(Vec3(0.0f), Color(0.02f), Vec3(0.0f, 0.0f, 0.1f), Color(0.05f), 0.3f));
  Material blocker;
  add_object(&scene, "blocker", quad(-0.5f, 0.5f, -0.5f, 0.5f, 1.5f), blocker);
  Settings settings = small_render(24, 24, 3, 1, 8);
  settings.aa_mode = AntiAliasing::kJittered;
  settings.waves = false;
  const Rendered reference = render(scene, settings);
  settings.threads = 2;
  settings.tile_size = 5;
  EXPECT_EQ(render(scene, settings).pixels, reference.pixels);
  settings.waves = true;
  const Rendered waves = render(scene, settings);
  for (size_t i = 0; i < reference.pixels.size(); ++i) {
    EXPECT_NEAR(waves.pixels[i], reference.pixels[i], 1e-5f * (1.0f + reference.pixels[i])) << i;
  }
  EXPECT_GT(reference.stats.rays.volume_steps, 0u);
  EXPECT_GT(reference.stats.rays.volume_feelers, 0u);
  EXPECT_EQ(reference.stats.rays.nonfinite_samples, 0u);
  // From inside: the camera at z = 4.5 under the box's top, looking down. Its rays meet
  // no bound before the floor: only the media stack media_at seeds says they are in the
  // fog, and only segments inside a medium send feelers from it to the lamp.
  scene.camera = looking_down(Vec3(0.3f, 0.2f, 4.5f), 0.8f);
  const Rendered inside = render(scene, settings);
  EXPECT_GT(inside.stats.rays.volume_feelers, 0u);
  EXPECT_EQ(inside.stats.rays.nonfinite_samples, 0u);
}

}  // namespace
}  // namespace whitted

namespace whitted {
namespace {

// One block of 8^3 voxels of density 1, voxels of 0.25: the cube [0, 2]^3 in object space.
std::shared_ptr<const VolumeGrid> full_block() {
  VolumeGridData data;
  data.name = "density";
  data.index_to_object = glm::scale(glm::mat4(1.0f), Vec3(0.25f));
  data.active_lower = glm::ivec3(0);
  data.active_upper = glm::ivec3(7);
  data.active_voxels = 512;
  data.block_counts = glm::ivec3(1);
  data.blocks = {1};
  data.values.assign(VolumeGrid::kBlockVoxels, 1.0f);
  return std::make_shared<const VolumeGrid>(std::move(data));
}

// What the exporter makes of a Volume object's material (addon/export/volume.py): an
// absorption of `k` times its density grid, times Cycles' object density.
Material grid_fog(float k) {
  const auto multiply = static_cast<uint32_t>(VectorMathOp::kMultiply);
  MaterialParams m;
  m.surface = false;
  m.program = std::make_shared<const Program>(
      make({{Op::kInput, kInputGrid + static_cast<uint32_t>(GridRole::kDensity), 0},
            {Op::kInput, kInputVolumeDensity, 3},
            {Op::kVectorMath, multiply, 2, 0, 1},
            {Op::kVectorMath, multiply, 4, 2, 3}},
           {glm::vec4(0.0f), glm::vec4(k, k, k, 0.0f), glm::vec4(0.0f), glm::vec4(0.0f),
            glm::vec4(0.0f)}));
  m.outputs[kVolumeAbsorptionField] = 4;
  return Material(m);
}

// The transmittance straight down through the block's middle, placed by `to_world`.
float through_the_block(const glm::mat4& to_world, VolumeRender settings, float k) {
  VolumeObject::Grids grids;
  grids[static_cast<int>(GridRole::kDensity)] = full_block();
  const auto volume = std::make_shared<const VolumeObject>(to_world, grids, settings);
  Scene scene;
  scene.set_background(Color(1.0f));
  scene.set_mesh("smoke", volume->bound_mesh());
  scene.set_material("smoke", grid_fog(k));
  Instance instance{"smoke", to_world, {"smoke"}};
  instance.volume = volume;
  scene.set_instance("smoke", instance);
  const Vec3 middle = transform_point(to_world, Vec3(1.0f));
  scene.camera = looking_down(Vec3(middle.x, middle.y, 20.0f), 1e-5f);
  Settings one = one_ray(8);
  one.volume_step_rate = 0.1f;
  return render(scene, one).pixels[0];
}

TEST(GridVolume, ABlockOfDensityOneLetsThroughExpOfMinusItsDepth) {
  // Trilinear between voxel centres, the density falls from 1 to 0 over the half voxel
  // either side of each face: along a line across the block its integral is the block's
  // depth, 2, wherever the values stand (centres or index points).
  const float k = 0.4f;
  for (const bool centred : {true, false}) {
    EXPECT_NEAR(through_the_block(glm::mat4(1.0f), {true, 0.0f, centred}, k), std::exp(-2.0f * k),
                1e-4f)
        << centred;
  }
  // Scaled by 2: in object space a density is per unit of the object, so the twice as
  // long path is half as dense; in world space it is not.
  const glm::mat4 twice = glm::scale(glm::mat4(1.0f), Vec3(2.0f));
  EXPECT_NEAR(through_the_block(twice, {true, 0.0f, true}, k), std::exp(-2.0f * k), 1e-4f);
  EXPECT_NEAR(through_the_block(twice, {false, 0.0f, true}, k), std::exp(-4.0f * k), 1e-4f);
}

TEST(GridVolume, ItsStepDensityScaleAndMeshAreCycles) {
  VolumeObject::Grids grids;
  grids[static_cast<int>(GridRole::kDensity)] = full_block();
  const glm::mat4 to_world = glm::scale(glm::mat4(1.0f), Vec3(2.0f, 2.0f, 4.0f));
  const VolumeObject automatic(to_world, grids);
  EXPECT_FLOAT_EQ(automatic.step(), 0.5f);  // the voxel (0.25) carried to the world, smallest
  EXPECT_NEAR(automatic.density_scale(),
              1.0f / glm::length(Vec3(2.0f, 2.0f, 4.0f) / std::sqrt(3.0f)), 1e-6f);
  EXPECT_FLOAT_EQ(VolumeObject(to_world, grids, {true, 0.1f, true}).step(), 0.2f);
  EXPECT_FLOAT_EQ(VolumeObject(to_world, grids, {false, 0.1f, true}).step(), 0.1f);
  EXPECT_FLOAT_EQ(VolumeObject(to_world, grids, {false, 0.1f, true}).density_scale(), 1.0f);
  EXPECT_THROW(VolumeObject(to_world, grids, {true, -1.0f, true}), std::invalid_argument);
  // The reach: the active voxels and half a voxel more, moved back half a voxel where
  // values stand at the index points; it is the mesh's texture space.
  const auto reach = [&](bool centred) {
    return VolumeObject(to_world, grids, {true, 0.0f, centred}).interpolated_bounds();
  };
  EXPECT_NEAR(reach(true).lower.x, -0.125f, 1e-6f);
  EXPECT_NEAR(reach(true).upper.x, 2.125f, 1e-6f);
  EXPECT_NEAR(reach(false).lower.x, -0.25f, 1e-6f);
  EXPECT_NEAR(reach(false).upper.x, 2.0f, 1e-6f);
  // The mesh, as Cycles builds it: the block and the six its face voxels pad into, a
  // cross of seven blocks (0.25 a voxel, 2 a block) whose arms have five faces each.
  const Mesh mesh = VolumeObject(to_world, grids).bound_mesh();
  EXPECT_EQ(mesh.triangle_count(), 6u * 5u * 2u);
  EXPECT_NEAR(bounding_box(mesh).lower.x, -2.0f, 1e-6f);
  EXPECT_NEAR(bounding_box(mesh).upper.z, 4.0f, 1e-6f);
  EXPECT_NEAR(mesh.texspace_location.x, 1.0f, 1e-6f);
  EXPECT_NEAR(mesh.texspace_size.x, 1.125f, 1e-6f);
  // Below the Volume's Clipping every voxel is empty space: no mesh.
  EXPECT_EQ(VolumeObject(to_world, grids, {true, 0.0f, true, 1.5f}).bound_mesh().triangle_count(),
            0u);
  EXPECT_THROW(VolumeObject(to_world, grids, {true, 0.0f, true, -1.0f}), std::invalid_argument);
  EXPECT_EQ(VolumeObject(to_world, {}).bound_mesh().triangle_count(), 0u);
}

// Two voxels of density far apart in one grid: the mesh encloses the blocks around each
// (each voxel inside its block pads into none), not the empty space between them, and a
// ray through that space meets no medium.
TEST(GridVolume, ItsMeshLeavesOutTheEmptyBlocksBetweenTheVoxels) {
  VolumeGridData data;
  data.name = "density";
  data.index_to_object = glm::scale(glm::mat4(1.0f), Vec3(0.25f));
  data.active_lower = glm::ivec3(3);
  data.active_upper = glm::ivec3(3 + 8 * 4, 3, 3);
  data.active_voxels = 2;
  data.block_counts = glm::ivec3(5, 1, 1);
  data.blocks = {1, 0, 0, 0, 2};
  data.values.assign(2 * VolumeGrid::kBlockVoxels, 0.0f);
  const int middle = (3 * 8 + 3) * 8 + 3;  // voxel (3, 3, 3) of its block
  data.values[middle] = 1.0f;
  data.values[VolumeGrid::kBlockVoxels + middle] = 1.0f;
  VolumeObject::Grids grids;
  grids[static_cast<int>(GridRole::kDensity)] = std::make_shared<const VolumeGrid>(data);
  const Mesh mesh = VolumeObject(glm::mat4(1.0f), grids).bound_mesh();
  EXPECT_EQ(mesh.triangle_count(), 2u * 12u);  // two cubes
  EXPECT_EQ(mesh.vertex_count(), 16u);
  const Box box = bounding_box(mesh);
  EXPECT_NEAR(box.lower.x, 0.0f, 1e-6f);
  EXPECT_NEAR(box.upper.x, 10.0f, 1e-6f);
  // No triangle reaches into the three empty blocks between x = 2 and x = 8.
  for (size_t v = 0; v < mesh.vertex_count(); ++v) {
    const float x = mesh.positions[3 * v];
    EXPECT_TRUE(x <= 2.0f || x >= 8.0f) << x;
  }
}

}  // namespace
}  // namespace whitted
