// Lights: what the constructor refuses and clamps, the irradiance of sized lights
// against their point-like limits, and where rays meet their shapes.
#include "scene/light.h"

#include <gtest/gtest.h>

#include "integrator/mis.h"
#include "program_builder.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace whitted {
namespace {

Color total_irradiance(const Light& light, const Vec3& p, const Vec3& n) {
  Color sum(0.0f);
  for (int s = 0; s < light.sample_count(); ++s) {
    const LightSample ls = sample_light(light, p, s);
    sum += ls.irradiance * std::max(0.0f, glm::dot(n, ls.wi));
  }
  return sum;
}

// A square area light of radiance 1 and side `size`, 1 m above the origin, facing down.
Light square_above_origin(float size) {
  Light area;
  area.type = LightType::kArea;
  area.color = Color(1.0f);
  area.position = Vec3(0.0f, 0.0f, 1.0f);
  area.direction = Vec3(0.0f, 0.0f, -1.0f);
  area.size[0] = area.size[1] = size;
  return area;
}

TEST(Light, SphereLightFarAwayGivesThePointLightsIrradiance) {
  Light light;
  light.color = Color(100.0f);
  light.position = Vec3(0.0f, 0.0f, 10.0f);
  light.radius = 0.5f;
  light.samples = 4;
  EXPECT_EQ(light.sample_count(), 16);
  const Color e = total_irradiance(light, Vec3(0.0f), Vec3(0.0f, 0.0f, 1.0f));
  EXPECT_NEAR(e.x, 100.0f / 100.0f, 0.01f);
  light.radius = 0.0f;
  EXPECT_EQ(light.sample_count(), 1);
}

TEST(Light, SunWithAngleKeepsItsIrradiance) {
  Light sun;
  sun.type = LightType::kSun;
  sun.color = Color(3.0f);
  sun.direction = Vec3(0.0f, 0.0f, -1.0f);
  sun.angle = 0.1f;
  sun.samples = 5;
  const Color e = total_irradiance(sun, Vec3(0.0f), Vec3(0.0f, 0.0f, 1.0f));
  // Directions tilt by at most 0.05 rad: cos >= 0.9987.
  EXPECT_NEAR(e.x, 3.0f, 3.0f * 2e-3f);
  // The feelers really spread over the disc.
  const Vec3 first = sample_light(sun, Vec3(0.0f), 0).wi;
  const Vec3 last = sample_light(sun, Vec3(0.0f), 24).wi;
  EXPECT_GT(std::acos(glm::dot(first, last)), 0.05f);
}

// A square area light of radiance L seen from far along its normal acts like a point
// light of intensity L*A.
TEST(Light, AreaLightFarAwayActsLikeAPointOfIntensityRadianceTimesArea) {
  for (AreaShape shape : {AreaShape::kRectangle, AreaShape::kEllipse}) {
    Light area;
    area.type = LightType::kArea;
    area.shape = shape;
    area.color = Color(2.0f);
    area.position = Vec3(0.0f, 0.0f, 20.0f);
    area.direction = Vec3(0.0f, 0.0f, -1.0f);
    area.size[0] = 1.0f;
    area.size[1] = 2.0f;
    area.samples = 3;
    const float a = shape == AreaShape::kRectangle ? 2.0f : 0.25f * kPi * 2.0f;
    const Color e = total_irradiance(area, Vec3(0.0f), Vec3(0.0f, 0.0f, 1.0f));
    // Off-axis samples (up to 1 unit at distance 20) are a little further and more
    // oblique: the exact finite-size irradiance is about 0.2% below the point limit.
    EXPECT_NEAR(e.x, 2.0f * a / 400.0f, 2.0f * a / 400.0f * 5e-3f);
    // Behind the light: nothing (one-sided).
    EXPECT_EQ(total_irradiance(area, Vec3(0.0f, 0.0f, 40.0f), Vec3(0.0f, 0.0f, -1.0f)).x, 0.0f);
  }
}

// Jittered feelers (sample_light's jitter): jitter 0 is the lattice of stratum centres;
// any other puts each feeler somewhere in its own stratum, a new place for each jitter;
// one feeler per camera sample, averaged over many, gives the lamp's irradiance.
TEST(Light, AGivenPointLandsThereAndUniformPointsAverageToTheLamp) {
  Light area = square_above_origin(2.0f);
  area.samples = 3;
  const Light lattice(area);
  const Vec3 p(0.0f);
  const auto target = [&](const LightSample& ls) { return p + ls.wi * ls.distance; };
  // Stratum 4 of 3 x 3 is the middle one: its centre is the lamp's.
  EXPECT_NEAR(glm::length(target(sample_light(lattice, p, 4)) - area.position), 0.0f, 1e-5f);
  // Given a point of [0, 1)^2, any sample lands there on the 2 x 2 square: [-1, 1]^2.
  for (const glm::vec2 at : {glm::vec2(0.0f), glm::vec2(0.25f, 0.9f), glm::vec2(0.99f, 0.5f)}) {
    for (int k : {0, 4, 8}) {
      const Vec3 t = target(sample_light(lattice, p, k, &at));
      EXPECT_NEAR(t.x, -1.0f + 2.0f * at.x, 1e-5f);
      EXPECT_NEAR(t.y, -1.0f + 2.0f * at.y, 1e-5f);
    }
  }
  // One feeler (n = 1) at 40,000 uniform points against a 64 x 64 lattice.
  area.samples = 1;
  const Light one(area);
  area.samples = 64;
  const Light fine(area);
  const Vec3 n(0.0f, 0.0f, 1.0f);
  const float expected = total_irradiance(fine, p, n).x;
  double sum = 0.0;
  constexpr int kDraws = 40000;
  for (uint32_t draw = 1; draw <= kDraws; ++draw) {
    const uint32_t h = hash3(draw, 0x6c69u, 0u);
    const glm::vec2 at(unit_float(h), unit_float(hash3(h, 1u, 2u)));
    const LightSample ls = sample_light(one, p, 0, &at);
    sum += ls.irradiance.x * std::max(0.0f, glm::dot(n, ls.wi));
  }
  EXPECT_NEAR(sum / kDraws, expected, expected * 0.01);
  // The lattice's single feeler is the centre's alone: it misses the lamp's edges.
  EXPECT_GT(total_irradiance(one, p, n).x, expected * 1.2f);
}

// A small area light of Spread s sends towards angle a off its normal (tan h - tan a) /
// (tan h - h) of a plain one's light, h = s / 2 (Cycles' soft box), none past h; summed
// over the hemisphere its power is the plain light's.
TEST(Light, AreaSpreadNarrowsTheLightAndKeepsItsPower) {
  const Light area = square_above_origin(1e-3f);
  const float h = 0.5f * 0.8f;  // a spread of 0.8 rad
  Light narrow = area;
  narrow.spread = 0.8f;
  // Points on a sphere of radius 1 around the light, at angle a off its axis, facing it.
  double plain_power = 0.0;
  double narrow_power = 0.0;
  const int rings = 2000;
  for (int i = 0; i < rings; ++i) {
    const float a = (static_cast<float>(i) + 0.5f) / static_cast<float>(rings) * 0.5f * kPi;
    const Vec3 p = area.position + Vec3(std::sin(a), 0.0f, -std::cos(a));
    const Vec3 n = glm::normalize(area.position - p);
    const float plain = total_irradiance(area, p, n).x;
    const float got = total_irradiance(narrow, p, n).x;
    const float expected = std::max(0.0f, (std::tan(h) - std::tan(a)) / (std::tan(h) - h));
    EXPECT_NEAR(got, plain * expected, 1e-3f * plain * (1.0f + expected)) << a;
    const double ring = 2.0 * kPi * std::sin(a) * (0.5 * kPi / rings);  // solid angle
    plain_power += plain * ring;
    narrow_power += got * ring;
  }
  EXPECT_NEAR(narrow_power / plain_power, 1.0, 2e-3);
}

TEST(Light, SpotAtItsOwnCentreStaysFinite) {
  Light spot;
  spot.type = LightType::kSpot;
  spot.radius = 0.1f;
  spot.samples = 2;
  for (int s = 0; s < spot.sample_count(); ++s) {
    const LightSample ls = sample_light(spot, spot.position, s);
    EXPECT_TRUE(is_finite(ls.irradiance));
    EXPECT_TRUE(is_finite(ls.wi));
  }
}

// What Light's constructor says about a value that cannot be a light ("" when it takes it).
std::string refusal(const LightParams& params) {
  try {
    const Light light(params);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

TEST(Light, ConstructorRefusesWhatCannotBeALight) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(refusal({}), "");
  EXPECT_EQ(refusal({.color = Color(inf, 1.0f, 1.0f)}),
            "light colour, position and axes must be finite");
  EXPECT_EQ(refusal({.axis_v = Vec3(0.0f, nan, 0.0f)}),
            "light colour, position and axes must be finite");
  EXPECT_EQ(refusal({.direction = Vec3(0.0f)}), "light direction must not be zero");
  EXPECT_EQ(refusal({.spot_size = nan}), "light spot size, blend and area size must be finite");
  EXPECT_EQ(refusal({.size = {1.0f, inf}}), "light spot size, blend and area size must be finite");
  EXPECT_EQ(refusal({.radius = inf}), "light radius, angle and spread must be finite");
  EXPECT_EQ(refusal({.spread = nan}), "light radius, angle and spread must be finite");
  EXPECT_EQ(refusal({.samples = 0}), "light samples must be between 1 and 64");
  EXPECT_EQ(refusal({.samples = kMaxLightSamples + 1}), "light samples must be between 1 and 64");
  EXPECT_EQ(refusal({.samples = kMaxLightSamples}), "");
}

TEST(Light, ConstructorClampsToTheNearestLightAndNormalisesTheDirection) {
  const Light light({.type = LightType::kSpot,
                     .color = Color(-1.0f, 2.0f, 3.0f),
                     .direction = Vec3(0.0f, 0.0f, -4.0f),
                     .spot_size = 5.0f,
                     .spot_blend = -0.5f,
                     .size = {-1.0f, 2.0f},
                     .radius = -1.0f,
                     .angle = 7.0f});
  EXPECT_EQ(light.color, Color(0.0f, 2.0f, 3.0f));  // negative power emits nothing
  EXPECT_EQ(light.direction, Vec3(0.0f, 0.0f, -1.0f));
  EXPECT_EQ(light.spot_size, kPi);
  EXPECT_EQ(light.spot_blend, 0.0f);
  EXPECT_EQ(light.size[0], 0.0f);
  EXPECT_EQ(light.size[1], 2.0f);
  EXPECT_EQ(light.radius, 0.0f);
  EXPECT_EQ(light.angle, kPi);
}

// A ray meets an area light's rectangle from its lit side only, sees its radiance there,
// and the density its feelers draw that point with is t^2 / (A cos).
TEST(Light, ARayMeetsAnAreaLightsRectangleFromItsLitSide) {
  Light area = square_above_origin(2.0f);
  area.color = Color(3.0f);
  LightHit hit;
  const Vec3 up(0.0f, 0.0f, 1.0f);
  ASSERT_TRUE(intersect_light(area, Ray{Vec3(0.5f, -0.9f, 0.0f), up}, kInfinity, &hit));
  EXPECT_FLOAT_EQ(hit.t, 1.0f);
  EXPECT_EQ(hit.radiance, Color(3.0f));
  EXPECT_FLOAT_EQ(hit.density, 1.0f / 4.0f);  // t = 1, A = 4, cos = 1
  // Slanted: t = 1 / cos, density t^2 / (A cos) = 1 / (A cos^3).
  const Vec3 slant = glm::normalize(Vec3(0.5f, 0.0f, 1.0f));
  ASSERT_TRUE(intersect_light(area, Ray{Vec3(0.0f), slant}, kInfinity, &hit));
  EXPECT_NEAR(hit.t, 1.0f / slant.z, 1e-6f);
  EXPECT_NEAR(hit.density, 1.0f / (4.0f * slant.z * slant.z * slant.z), 1e-6f);
  // Past its edge, beyond t_max or behind the ray's start, and from above (its back).
  EXPECT_FALSE(intersect_light(area, Ray{Vec3(1.1f, 0.0f, 0.0f), up}, kInfinity, &hit));
  EXPECT_FALSE(intersect_light(area, Ray{Vec3(0.0f), up}, 0.9f, &hit));
  EXPECT_FALSE(intersect_light(area, Ray{Vec3(0.0f, 0.0f, 2.0f), up}, kInfinity, &hit));
  EXPECT_FALSE(intersect_light(area, Ray{Vec3(0.0f, 0.0f, 2.0f), -up}, kInfinity, &hit));
  // An ellipse (here a disc of diameter 2) leaves the square's corners out.
  area.shape = AreaShape::kEllipse;
  EXPECT_FALSE(intersect_light(area, Ray{Vec3(0.8f, 0.8f, 0.0f), up}, kInfinity, &hit));
  ASSERT_TRUE(intersect_light(area, Ray{Vec3(0.6f, 0.6f, 0.0f), up}, kInfinity, &hit));
  EXPECT_FLOAT_EQ(hit.density, 1.0f / kPi);
  // A light without a shape is met by no ray.
  Light point;
  point.position = Vec3(0.0f, 0.0f, 1.0f);
  EXPECT_FALSE(intersect_light(point, Ray{Vec3(0.0f), up}, kInfinity, &hit));
}

// A sphere light is met as the disc of its radius facing the ray's origin, of radiance
// I / (pi r^2); a spot's cone limits it by the direction the ray comes from.
TEST(Light, ARayMeetsASphereLightsDiscAndASpotsOnlyInsideItsCone) {
  Light sphere;
  sphere.color = Color(5.0f);
  sphere.position = Vec3(0.0f, 0.0f, 4.0f);
  sphere.radius = 0.5f;
  LightHit hit;
  const Vec3 up(0.0f, 0.0f, 1.0f);
  ASSERT_TRUE(intersect_light(sphere, Ray{Vec3(0.3f, 0.0f, 0.0f), up}, kInfinity, &hit));
  // The disc's normal points to the origin, d / |d| with d = (0.3, 0, -4): t = |d|^2 / 4.
  EXPECT_NEAR(hit.t, (0.09f + 16.0f) / 4.0f, 1e-5f);
  EXPECT_NEAR(hit.radiance.x, 5.0f / (kPi * 0.25f), 1e-4f);
  EXPECT_FALSE(intersect_light(sphere, Ray{Vec3(0.6f, 0.0f, 0.0f), up}, kInfinity, &hit));
  // From inside it, no disc faces the origin.
  EXPECT_FALSE(intersect_light(sphere, Ray{Vec3(0.0f, 0.0f, 3.9f), up}, kInfinity, &hit));
  // A spot pointing down sees the ray coming up from below; one pointing up does not.
  Light spot = sphere;
  spot.type = LightType::kSpot;
  spot.direction = -up;
  spot.spot_size = 1.0f;
  spot.spot_blend = 0.0f;
  ASSERT_TRUE(intersect_light(spot, Ray{Vec3(0.0f), up}, kInfinity, &hit));
  EXPECT_NEAR(hit.radiance.x, 5.0f / (kPi * 0.25f), 1e-4f);
  spot.direction = up;
  EXPECT_FALSE(intersect_light(spot, Ray{Vec3(0.0f), up}, kInfinity, &hit));
}

// Each feeler is what a ray along it meets: the same point and density, and its
// irradiance the radiance there over the n x n feelers' summed density (for a sphere light
// up to the disc's cosine, which its feelers leave out).
TEST(Light, FeelersIntegrateTheRadianceRaysMeetOnTheShape) {
  Light area = square_above_origin(1.5f);
  area.color = Color(2.0f);
  area.samples = 3;
  Light sphere;
  sphere.color = Color(7.0f);
  sphere.position = Vec3(0.4f, 0.2f, 3.0f);
  sphere.radius = 0.3f;
  sphere.samples = 3;
  for (const Light& light : {Light(area), Light(sphere)}) {
    const Vec3 p(0.3f, -0.2f, 0.0f);
    for (int s = 0; s < light.sample_count(); ++s) {
      const LightSample ls = sample_light(light, p, s);
      LightHit hit;
      ASSERT_TRUE(intersect_light(light, Ray{p, ls.wi}, kInfinity, &hit));
      EXPECT_NEAR(hit.t, ls.distance, 1e-5f);
      EXPECT_NEAR(hit.density, ls.density, 1e-4f * ls.density);
      const float tolerance = light.type == LightType::kArea ? 1e-5f : 0.02f;
      const float expected =
          hit.radiance.x / (static_cast<float>(light.sample_count()) * hit.density);
      EXPECT_NEAR(ls.irradiance.x, expected, tolerance * expected);
    }
  }
}

// A glossy ray's weight on a lamp and the lamp's feeler's on the same direction are the
// power heuristic's two halves (they sum to 1); a ray not drawn from a lobe counts the
// lamp whole.
TEST(Light, LampWeightsOfGlossyRaysAndFeelersSumToOne) {
  Light area = square_above_origin(1.0f);
  area.samples = 4;
  const Light light(area);
  const float density = 0.8f;  // one feeler's, per unit solid angle
  for (const float lobe : {0.01f, 0.5f, 16.0f, 1e4f}) {
    const float ray = lamp_weight(lobe, light, density);
    const float feeler = power_heuristic(16.0f * density, lobe);
    EXPECT_NEAR(ray + feeler, 1.0f, 1e-6f);
    const float r = lobe / (16.0f * density);
    EXPECT_NEAR(ray, r * r / (1.0f + r * r), 1e-6f);
  }
  EXPECT_EQ(lamp_weight(0.0f, light, density), 1.0f);
}

// A lamp program: Light Falloff's output `falloff` (0 Quadratic, 1 Linear, 2 Constant) of
// Strength `strength` at the ray length, in register 2.
std::shared_ptr<const Program> falloff_program(uint32_t falloff, float strength) {
  using testing::Row;
  return std::make_shared<const Program>(testing::make(
      {Row{Op::kInput, kInputRayLength, 1}, Row{Op::kLightFalloff, falloff, 2, 0, 3, 1}},
      {glm::vec4(strength), glm::vec4(0.0f), glm::vec4(0.0f), glm::vec4(0.0f)}));
}

// Light Falloff on a lamp (Cycles evaluates the lamp's node tree at each sample with the
// distance to the lit point): Linear undoes one power of the inverse square, Constant
// both, Quadratic neither; where a ray meets an area lamp its radiance is scaled alike.
TEST(Light, LightFalloffProgramScalesByTheDistanceToTheLitPoint) {
  LightParams point;
  point.color = Color(100.0f);
  point.position = Vec3(0.0f, 0.0f, 4.0f);
  point.program_output = 2;
  for (const float d : {1.0f, 2.5f, 4.0f}) {
    const Vec3 p(0.0f, 0.0f, 4.0f - d);
    point.program = falloff_program(0, 0.5f);
    EXPECT_NEAR(sample_light(Light(point), p, 0).irradiance.x, 50.0f / (d * d), 1e-4f);
    point.program = falloff_program(1, 0.5f);
    EXPECT_NEAR(sample_light(Light(point), p, 0).irradiance.x, 50.0f / d, 1e-4f);
    point.program = falloff_program(2, 0.5f);
    EXPECT_NEAR(sample_light(Light(point), p, 0).irradiance.y, 50.0f, 1e-3f);
  }
  LightParams area = square_above_origin(0.5f);
  const LightHit plain = [&] {
    LightHit hit;
    EXPECT_TRUE(intersect_light(Light(area), Ray{Vec3(0.1f, 0.0f, -2.0f), Vec3(0.0f, 0.0f, 1.0f)},
                                kInfinity, &hit));
    return hit;
  }();
  area.program = falloff_program(2, 2.0f);
  area.program_output = 2;
  LightHit hit;
  ASSERT_TRUE(intersect_light(Light(area), Ray{Vec3(0.1f, 0.0f, -2.0f), Vec3(0.0f, 0.0f, 1.0f)},
                              kInfinity, &hit));
  EXPECT_NEAR(hit.t, 3.0f, 1e-5f);
  EXPECT_NEAR(hit.radiance.z, plain.radiance.z * 2.0f * 9.0f, 1e-4f);
}

// What a lamp cannot run is refused (ValueError in Python), never run on made-up inputs.
TEST(Light, RefusesProgramsALampCannotRun) {
  using testing::Row;
  LightParams sun;
  sun.type = LightType::kSun;
  sun.program = falloff_program(1, 1.0f);
  EXPECT_THROW(Light{sun}, std::invalid_argument);
  LightParams point;
  point.program = falloff_program(1, 1.0f);
  point.program_output = 4;  // past its four registers
  EXPECT_THROW(Light{point}, std::invalid_argument);
  point.program_output = 1;
  EXPECT_NO_THROW(Light{point});
  point.program = std::make_shared<const Program>(
      testing::make({Row{Op::kInput, kInputGenerated, 0}}, {glm::vec4(0.0f)}));
  point.program_output = 0;
  EXPECT_THROW(Light{point}, std::invalid_argument);
}

}  // namespace
}  // namespace whitted
