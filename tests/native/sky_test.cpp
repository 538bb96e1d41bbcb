// The Sky Texture's models (shader/sky.h) against what their papers and Cycles fix:
// Preetham's zenith luminance, the symmetry about the sun's vertical plane, an empty
// atmosphere, Hosek/Wilkie's generated dataset and its cooking, and finite,
// non-negative radiance everywhere.
#include "shader/sky.h"

#include "shader/hosek_wilkie_data.inc"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace whitted {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

float luminance(Vec3 c) {
  return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z;
}

Vec3 towards(float elevation_degrees, float azimuth_degrees) {
  const float e = elevation_degrees * kPi / 180.0f;
  const float a = azimuth_degrees * kPi / 180.0f;
  return {std::cos(e) * std::sin(a), std::cos(e) * std::cos(a), std::sin(e)};
}

sky::ScatteringParams scattering(float elevation_degrees, float rotation_degrees) {
  sky::ScatteringParams p;
  p.sun_elevation = elevation_degrees * kPi / 180.0f;
  p.sun_rotation = rotation_degrees * kPi / 180.0f;
  p.sun_size = 0.009512f;
  return p;
}

TEST(Sky, PreethamZenithLuminanceFollowsThePaper) {
  // Preetham et al. 1999, appendix: Y_z = (4.0453 T - 4.9710) tan(chi) - 0.2155 T + 2.4192,
  // chi = (4/9 - T/120)(pi - 2 theta_s); at T = 2 and the sun at the zenith (chi = 1.3439, tan chi
  // = 4.3311), 15.50 kcd/m^2.
  EXPECT_NEAR(sky::preetham_zenith_luminance(0.0f, 2.0f), 15.50f, 0.01f);
  // The sky's luminance straight up is that value (Cycles' 0.06 scale) for any sun.
  for (const float sun_elevation : {10.0f, 30.0f, 60.0f}) {
    for (const float turbidity : {2.0f, 2.2f, 6.0f}) {
      const Vec3 sun = towards(sun_elevation, 30.0f);
      const std::vector<float> t = sky::preetham_table(sun, turbidity);
      const float zenith = luminance(sky::radiance(sky::Model::kPreetham, t.data(), {0, 0, 1}));
      const float expected = 0.06f * sky::preetham_zenith_luminance(std::acos(sun.z), turbidity);
      EXPECT_NEAR(zenith, expected, 1e-3f * expected) << sun_elevation << " " << turbidity;
    }
  }
}

TEST(Sky, SymmetricAboutTheSunsAzimuth) {
  const float sun_azimuth = 30.0f;
  const std::vector<float> preetham = sky::preetham_table(towards(20.0f, sun_azimuth), 3.0f);
  const std::vector<float> hosek = sky::hosek_wilkie_table(towards(20.0f, sun_azimuth), 3.0f, 0.3f);
  const std::vector<float> single = sky::scattering_table(scattering(20.0f, sun_azimuth));
  sky::ScatteringParams p = scattering(20.0f, sun_azimuth);
  p.style = sky::Style::kMultipleScattering;
  const std::vector<float> multiple = sky::scattering_table(p);
  for (const float elevation : {-5.0f, 1.0f, 10.0f, 40.0f, 80.0f}) {
    for (const float offset : {5.0f, 45.0f, 100.0f, 170.0f}) {
      const Vec3 left = towards(elevation, sun_azimuth - offset);
      const Vec3 right = towards(elevation, sun_azimuth + offset);
      for (const auto& [model, table] : {std::pair{sky::Model::kPreetham, &preetham},
                                         std::pair{sky::Model::kHosekWilkie, &hosek},
                                         std::pair{sky::Model::kSingleScattering, &single},
                                         std::pair{sky::Model::kSingleScattering, &multiple}}) {
        const Vec3 a = sky::radiance(model, table->data(), left);
        const Vec3 b = sky::radiance(model, table->data(), right);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-4f * (1.0f + a[c]));
      }
    }
  }
}

TEST(Sky, ScatteringSkyIsBrightestTowardsTheSunAndBluerOverhead) {
  sky::ScatteringParams p = scattering(15.0f, 0.0f);
  p.sun_disc = false;
  const std::vector<float> t = sky::scattering_table(p);
  const auto at = [&](float e, float a) {
    return sky::radiance(sky::Model::kSingleScattering, t.data(), towards(e, a));
  };
  EXPECT_GT(luminance(at(15.0f, 0.0f)), 5.0f * luminance(at(15.0f, 180.0f)));
  const Vec3 zenith = at(90.0f, 0.0f);
  EXPECT_GT(zenith.z, zenith.x);  // Rayleigh scattering: blue overhead
}

TEST(Sky, BelowTheHorizonEachVersionFadesTheHorizonAsCyclesDoes) {
  // 3.x fades the horizon's colour by (1 + 2.5 z)^3 along the direction's z; 5.x bakes
  // that fade into the texture's rows below its middle, each at its row's depth
  // pi/2 (1 - y / rows)^2, and reads them bilinearly (up to 5% brighter at -9 degrees
  // with 3.x's fade, 30% at -20: Cycles 5.0 measured per pixel).
  constexpr uint32_t kRows = 16;
  for (const sky::Style style : {sky::Style::kNishita, sky::Style::kSingleScattering}) {
    sky::ScatteringParams p = scattering(10.0f, 0.0f);
    p.sun_disc = false;
    p.style = style;
    const std::vector<float> t = sky::scattering_table(p, 32, kRows);
    const auto at = [&](float elevation, float azimuth_degrees) {
      const float a = azimuth_degrees * kPi / 180.0f;
      return sky::radiance(sky::Model::kSingleScattering, t.data(),
                           {std::cos(elevation) * std::sin(a), std::cos(elevation) * std::cos(a),
                            std::sin(elevation)});
    };
    for (const float azimuth : {20.0f, 75.0f, 160.0f}) {
      // 5.x: the horizon's stored row alone at its texel centre just above the horizon.
      const float just_above = kPi / 2.0f * std::pow(0.5f / kRows, 2.0f);
      const Vec3 horizon =
          style == sky::Style::kNishita ? at(0.0f, azimuth) : at(just_above, azimuth);
      ASSERT_GT(luminance(horizon), 0.0f);
      for (const uint32_t row : {2u, 5u, 9u, 14u}) {
        // The depth of row `row`'s centre as 5.x reads it.
        const float s = 1.0f - (static_cast<float>(row) + 0.5f) / kRows;
        const float depth = kPi / 2.0f * s * s;
        float fade = 0.0f;
        if (style == sky::Style::kNishita) {
          fade = std::pow(1.0f - 2.5f * std::sin(depth), 3.0f);
          if (std::sin(depth) > 0.4f) fade = 0.0f;
        } else {
          const float r = 1.0f - static_cast<float>(row) / kRows;
          const float z = std::sin(kPi / 2.0f * r * r);
          fade = z < 0.4f ? std::pow(1.0f - 2.5f * z, 3.0f) : 0.0f;
        }
        const Vec3 below = at(-depth, azimuth);
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(below[c], horizon[c] * fade, 1e-3f * horizon[c] + 1e-7f)
              << static_cast<int>(style) << " " << azimuth << " " << row << " " << c;
        }
      }
    }
  }
}

TEST(Sky, AnEmptyAtmosphereShowsOnlyTheSunAtItsFullRadiance) {
  // No air, aerosols or ozone: a black sky, and the disc as bright at any elevation (no
  // extinction), Intensity scaling it.
  float first = 0.0f;
  for (const float elevation : {5.0f, 30.0f, 70.0f}) {
    sky::ScatteringParams p = scattering(elevation, 10.0f);
    p.air_density = p.dust_density = p.ozone_density = 0.0f;
    p.sun_intensity = 2.0f;
    const std::vector<float> t = sky::scattering_table(p);
    const Vec3 sun = sky::sun_direction(p.sun_elevation, p.sun_rotation);
    const float disc = luminance(sky::radiance(sky::Model::kSingleScattering, t.data(), sun));
    EXPECT_EQ(luminance(sky::radiance(sky::Model::kSingleScattering, t.data(),
                                      towards(elevation + 10.0f, 10.0f))),
              0.0f);
    if (first == 0.0f) first = disc;
    EXPECT_GT(disc, 1e6f);
    EXPECT_NEAR(disc, first, 1e-4f * first);
  }
}

TEST(Sky, HosekWilkieTableHoldsTheDatasetTheWheelHolds) {
  // The first and last values of each field of Mitsuba 3.9.1's sunsky_datasets.bin, as
  // tools/whitted_tools/generate/hosek_wilkie.py reads them.
  namespace data = sky::hosek_wilkie_data;
  EXPECT_EQ(data::kParameters.front(), -1.099459);
  EXPECT_EQ(data::kParameters.back(), 0.6966285);
  EXPECT_EQ(data::kRadiances.front(), 1.962684);
  EXPECT_EQ(data::kRadiances.back(), 28.93432);
}

TEST(Sky, HosekWilkieCooksTheBezierEndsAndBlendsAlbedoAndTurbidity) {
  // The sun on the horizon reads the first control point, at the zenith the last; an
  // albedo or turbidity between two of the dataset's is their mean.
  namespace data = sky::hosek_wilkie_data;
  constexpr double kScale = 2.0 * std::numbers::pi / 683.0;
  const auto parameter = [](size_t turbidity, size_t albedo, size_t point, size_t channel,
                            size_t k) {
    return data::kParameters[(((turbidity * 2 + albedo) * 6 + point) * 3 + channel) * 9 + k];
  };
  const auto radiance = [](size_t turbidity, size_t albedo, size_t point, size_t channel) {
    return data::kRadiances[((turbidity * 2 + albedo) * 6 + point) * 3 + channel];
  };
  for (const auto& [elevation, point] : {std::pair{0.0f, size_t{0}}, std::pair{90.0f, size_t{5}}}) {
    const std::vector<float> t = sky::hosek_wilkie_table(towards(elevation, 0.0f), 4.0f, 0.0f);
    const std::vector<float> mean_albedo =
        sky::hosek_wilkie_table(towards(elevation, 0.0f), 4.0f, 0.5f);
    const std::vector<float> mean_turbidity =
        sky::hosek_wilkie_table(towards(elevation, 0.0f), 4.5f, 0.0f);
    for (size_t c = 0; c < 3; ++c) {
      for (size_t k = 0; k < 9; ++k) {
        const double at = parameter(3, 0, point, c, k);
        EXPECT_NEAR(t[2 + 10 * c + k], at, 1e-5 * (1.0 + std::fabs(at)));
        const double albedos = (at + parameter(3, 1, point, c, k)) / 2.0;
        EXPECT_NEAR(mean_albedo[2 + 10 * c + k], albedos, 1e-5 * (1.0 + std::fabs(albedos)));
        const double turbidities = (at + parameter(4, 0, point, c, k)) / 2.0;
        EXPECT_NEAR(mean_turbidity[2 + 10 * c + k], turbidities,
                    1e-5 * (1.0 + std::fabs(turbidities)));
      }
      EXPECT_NEAR(t[2 + 10 * c + 9], radiance(3, 0, point, c) * kScale, 1e-6);
    }
  }
}

TEST(Sky, FiniteAndNonNegativeEverywhere) {
  for (const float sun_elevation : {-40.0f, -0.2f, 0.0f, 0.2f, 45.0f, 90.0f}) {
    sky::ScatteringParams multiple = scattering(sun_elevation, 0.0f);
    multiple.style = sky::Style::kMultipleScattering;
    const std::vector<float> tables[] = {
        sky::preetham_table(towards(sun_elevation, 0.0f), 2.2f),
        sky::hosek_wilkie_table(towards(sun_elevation, 0.0f), 10.0f, 1.0f),
        sky::hosek_wilkie_table(towards(sun_elevation, 0.0f), 1.0f, 0.0f),
        sky::scattering_table(scattering(sun_elevation, 0.0f), 16, 8),
        sky::scattering_table(multiple, 16, 8)};
    const sky::Model models[] = {sky::Model::kPreetham, sky::Model::kHosekWilkie,
                                 sky::Model::kHosekWilkie, sky::Model::kSingleScattering,
                                 sky::Model::kSingleScattering};
    for (int m = 0; m < 5; ++m) {
      for (float e = -90.0f; e <= 90.0f; e += 7.5f) {
        for (float a = -180.0f; a <= 180.0f; a += 15.0f) {
          const Vec3 c = sky::radiance(models[m], tables[m].data(), towards(e, a));
          EXPECT_TRUE(is_finite(c) && c.x >= 0.0f && c.y >= 0.0f && c.z >= 0.0f)
              << m << " " << sun_elevation << " " << e << " " << a;
        }
      }
      const Vec3 zero = sky::radiance(models[m], tables[m].data(), Vec3(0.0f));
      EXPECT_TRUE(is_finite(zero) && zero.x >= 0.0f);
    }
  }
}

}  // namespace
}  // namespace whitted
